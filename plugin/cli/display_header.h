// The header of a display-referred file (PNG, JPEG, TIFF): it says what its pixels are, sRGB-
// encoded, and keeps nothing that described the scene-linear image they were made from.
#pragma once
#include <OpenImageIO/imageio.h>

namespace wavecam::cli {

// Tags `spec` as sRGB-encoded (oiio:ColorSpace "sRGB": OIIO's PNG writer then writes the sRGB
// chunk with gAMA 1/2.2 and sRGB's cHRM) and drops what said otherwise: oiio:Gamma, OpenEXR's
// chromaticities, whiteLuminance and adoptedNeutral, the ACES container flag, an ICC profile,
// a colour-interop id, and wavecam.output-colorspace (the linear space of the EXR, which a file
// read back as input would take for its own).
void tag_display_encoded(OIIO::ImageSpec& spec);

}  // namespace wavecam::cli
