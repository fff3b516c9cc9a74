#include "display_header.h"

namespace wavecam::cli {

void tag_display_encoded(OIIO::ImageSpec& spec) {
    for (const char* linear_only : {"oiio:Gamma", "chromaticities", "whiteLuminance", "adoptedNeutral",
                                    "acesImageContainerFlag", "ICCProfile", "colorInteropID",
                                    "wavecam.output-colorspace"})
        spec.erase_attribute(linear_only);
    spec.attribute("oiio:ColorSpace", "sRGB");
}

}  // namespace wavecam::cli
