#include "wavecam/atomic_write.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace wavecam {
namespace {
namespace fs = std::filesystem;

// Beside the target, hidden, the real extension last so OIIO picks the right writer:
// "dir/.out.exr.tmp12345.exr".
fs::path temporary_for(const fs::path& target) {
    return target.parent_path() /
           ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + target.extension().string());
}

// Whatever fails, no temporary is left behind.
Result<bool> discard(const fs::path& temp, const std::string& message) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    return Result<bool>::failure(message);
}

// Renames the finished temporary over the target.
Result<bool> move_into_place(const fs::path& temp, const std::string& path) {
    std::error_code ec;
    fs::rename(temp, path, ec);
    return ec ? discard(temp, path + ": cannot move the finished file into place: " + ec.message())
              : Result<bool>::success(true);
}

}  // namespace

Result<bool> write_image_atomically(const OIIO::ImageBuf& image, const std::string& path, OIIO::TypeDesc format) {
    const fs::path temp = temporary_for(path);
    if (!image.write(temp.string(), format)) return discard(temp, path + ": cannot write: " + image.geterror());
    return move_into_place(temp, path);
}

Result<bool> write_text_atomically(const std::string& text, const std::string& path) {
    const fs::path temp = temporary_for(path);
    std::ofstream out(temp);
    out << text;
    out.close();
    if (!out) return discard(temp, path + ": cannot write");
    return move_into_place(temp, path);
}

}  // namespace wavecam
