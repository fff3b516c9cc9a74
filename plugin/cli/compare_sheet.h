// Pictures for people: display-referred PNGs through the OCIO display view.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <string>
#include "wavecam/diffract_image.h"
#include "wavecam/result.h"

namespace wavecam::cli {

// input | output | difference, side by side and labelled, through the config's sRGB display.
Result<bool> write_compare_sheet(const OIIO::ImageBuf& input, const OIIO::ImageBuf& output,
                                 const DiffractOptions& opt, const std::string& path);

// The output alone through the display view.
Result<bool> write_display_png(const OIIO::ImageBuf& output, const DiffractOptions& opt, const std::string& path);

}  // namespace wavecam::cli
