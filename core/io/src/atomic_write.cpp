#include "wavecam/atomic_write.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace wavecam {

Result<bool> write_image_atomically(const OIIO::ImageBuf& image, const std::string& path, OIIO::TypeDesc format) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    // Keep the real extension last so OIIO picks the right writer: "dir/.out.exr.tmp12345.exr".
    const fs::path temp = target.parent_path() / ("." + target.filename().string() + ".tmp" +
                                                   std::to_string(::getpid()) + target.extension().string());
    if (!image.write(temp.string(), format)) {
        std::error_code ec;
        fs::remove(temp, ec);
        return Result<bool>::failure(path + ": cannot write: " + image.geterror());
    }
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) {
        fs::remove(temp, ec);
        return Result<bool>::failure(path + ": cannot move the finished image into place: " + ec.message());
    }
    return Result<bool>::success(true);
}

}  // namespace wavecam
