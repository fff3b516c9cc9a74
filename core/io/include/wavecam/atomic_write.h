// Writing a file so that nothing is lost or half-written: write a temporary beside the
// target, then rename it over the target (atomic on one filesystem). Every writer of wavecam's
// outputs (images, CSV tables, job records, scripts) goes through here.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <string>
#include "wavecam/result.h"

namespace wavecam {

// Writes `image` to `path` (format from the extension, as OIIO decides). On failure the
// target is untouched and the temporary removed; the error names the file.
Result<bool> write_image_atomically(const OIIO::ImageBuf& image, const std::string& path,
                                    OIIO::TypeDesc format = OIIO::TypeUnknown);

// Writes `text` to `path` the same way.
Result<bool> write_text_atomically(const std::string& text, const std::string& path);

}  // namespace wavecam
