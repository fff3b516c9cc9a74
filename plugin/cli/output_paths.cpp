#include "output_paths.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>

namespace wavecam::cli {
namespace {
namespace fs = std::filesystem;

// A file's identity: its device and inode when it is there (symlinks followed, hard links one
// file), else its folder's canonical path and its name (the file it will be).
std::string identity(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0)
        return "inode " + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
    std::error_code ec;
    const fs::path p = fs::absolute(path, ec);
    fs::path folder = fs::weakly_canonical(p.parent_path(), ec);
    if (ec) folder = p.parent_path().lexically_normal();
    return "name " + (folder / p.filename()).string();
}

// "" when the folder `path` is written into exists and can be written; else why not.
std::string folder_problem(const PathUse& out) {
    const fs::path parent = fs::path(out.path).parent_path();
    const std::string folder = parent.empty() ? "." : parent.string();
    struct stat st {};
    if (::stat(folder.c_str(), &st) != 0)
        return out.what + " " + out.path + ": its folder " + folder + " cannot be used (" + std::strerror(errno) +
               "); expected an existing folder";
    if (!S_ISDIR(st.st_mode)) return out.what + " " + out.path + ": " + folder + " is not a folder";
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        return out.what + " " + out.path + ": its folder " + folder + " is not writable (" + std::strerror(errno) +
               ")";
    return {};
}

}  // namespace

std::string path_conflict(const std::vector<PathUse>& reads, const std::vector<PathUse>& writes) {
    std::map<std::string, const PathUse*> read_ids, written_ids;
    for (const PathUse& r : reads)
        if (!r.path.empty()) read_ids.emplace(identity(r.path), &r);
    for (const PathUse& w : writes) {
        if (w.path.empty()) continue;
        const std::string id = identity(w.path);
        if (auto it = read_ids.find(id); it != read_ids.end())
            return w.what + " " + w.path + " is the same file as " + it->second->what + " " + it->second->path +
                   ": it would be overwritten; nothing done, choose another " + w.what.substr(0, w.what.find(" ("));
        if (auto [it, fresh] = written_ids.emplace(id, &w); !fresh)
            return w.what + " " + w.path + " is the same file as " + it->second->what + " " + it->second->path +
                   ": one output would replace the other; nothing done, give each its own name";
    }
    for (const PathUse& w : writes)
        if (!w.path.empty())
            if (const std::string bad = folder_problem(w); !bad.empty()) return bad;
    return {};
}

std::string aperture_mask_file(const std::string& aperture) {
    return aperture.rfind("mask:", 0) == 0 ? aperture.substr(5) : std::string();
}

}  // namespace wavecam::cli
