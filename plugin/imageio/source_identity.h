// Which file a name stands for, and which version of it: what a result computed from the file
// is kept under, so that a file written again, or the same relative name in another working
// folder, is a different source.
#pragma once
#include <string>

namespace wavecam::plugin {

// "CANONICAL-PATH dev:DEVICE ino:INODE mtime:SECONDS.NANOSECONDS ctime:... size:BYTES" for the
// file `path` names (relative to the working folder), or "" when there is none. A wavecam name
// not on disk ("shot.exr.wavecam?runs=8") stands for the file under it ("shot.exr").
std::string source_identity(const std::string& path);

}  // namespace wavecam::plugin
