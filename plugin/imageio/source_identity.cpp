#include "source_identity.h"

#include <sys/stat.h>

#include <filesystem>

namespace wavecam::plugin {
namespace {
constexpr const char* kExtension = ".wavecam";

std::string time_text(const timespec& t) {
    return std::to_string(t.tv_sec) + "." + std::to_string(t.tv_nsec);
}
}  // namespace

std::string source_identity(const std::string& path) {
    std::string name = path;
    struct stat st {};
    // a wavecam name stands for its source: "a.exr.wavecam?runs=8" -> "a.exr.wavecam" -> "a.exr"
    const size_t e = std::char_traits<char>::length(kExtension);
    while (::stat(name.c_str(), &st) != 0) {
        if (const size_t q = name.find('?'); q != std::string::npos) name.resize(q);
        else if (name.size() > e && name.compare(name.size() - e, e, kExtension) == 0) name.resize(name.size() - e);
        else return {};
    }
    std::error_code ec;
    std::filesystem::path where = std::filesystem::canonical(name, ec);
    if (ec) where = std::filesystem::absolute(name, ec);
    return where.string() + " dev:" + std::to_string(st.st_dev) + " ino:" + std::to_string(st.st_ino) +
           " mtime:" + time_text(st.st_mtim) + " ctime:" + time_text(st.st_ctim) +
           " size:" + std::to_string(st.st_size);
}

}  // namespace wavecam::plugin
