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

// The pixel type of a display-referred file named `path`: UINT8 for .png, .jpg, .jpeg, UINT16
// for .tif, .tiff; UNKNOWN for any other name (scene-linear files are OpenEXR).
OIIO::TypeDesc display_format(const std::string& path);

// The output's R, G, B alone (no alpha, no depth) through the display view, in the pixel type
// display_format(path) gives.
Result<bool> write_display_image(const OIIO::ImageBuf& output, const DiffractOptions& opt, const std::string& path);

}  // namespace wavecam::cli
