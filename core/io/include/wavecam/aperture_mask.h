// --aperture text to an Aperture, reading a mask image (mask:FILE) through OpenImageIO.
#pragma once
#include <string>
#include "wavecam/aperture.h"
#include "wavecam/result.h"

namespace wavecam {

// parse_aperture, and for mask:FILE the image's pixel values as amplitude transmission:
// the stored values (no colour conversion: a mask is data), one channel, or the mean of the
// first three for a colour image; alpha ignored. Row 0 of the file is the top (+y). A
// non-square image keeps its aspect: its width spans --pinhole, its height in proportion.
Result<Aperture> load_aperture(const std::string& text, const std::string& field);

}  // namespace wavecam
