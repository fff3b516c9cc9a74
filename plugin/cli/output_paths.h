// No output may be an input or another output: every path a run writes is compared, before any
// work, with every path it reads and every other path it writes, by file identity (the same
// file however it is named: a symlink, a hard link, "./"), and every output's folder must exist
// and be writable.
#pragma once
#include <string>
#include <vector>

namespace wavecam::cli {

// One path of a run and what it is, as the message names it: "-o", "--compare", "the render",
// "--aperture mask", "-o (frame 3)".
struct PathUse {
    std::string path, what;
};

// "" when every written path is a file of its own in a writable folder; else one line naming
// both paths and what they are ("-o in.exr is the same file as the render in.exr; choose
// another -o"), or the output and its folder.
std::string path_conflict(const std::vector<PathUse>& reads, const std::vector<PathUse>& writes);

// The file a mask aperture names ("mask:FILE" -> FILE), or "" for every other aperture.
std::string aperture_mask_file(const std::string& aperture);

}  // namespace wavecam::cli
