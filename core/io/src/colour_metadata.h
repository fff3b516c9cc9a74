// What a file's header says about its colour, and what the output's says: OpenEXR's
// `chromaticities` (primaries and white, CIE xy) and the ACES container flag, matched to the
// colour spaces of wavecam's config. Internal to wavecam_io.
#pragma once
#include <OpenImageIO/imageio.h>
#include <string>
#include "wavecam/colour_pipeline.h"
#include "wavecam/render_input.h"
#include "wavecam/result.h"

namespace wavecam::detail {

// The input's colour space from its header: chromaticities matched to a space the config has
// (within 0.002 in x and y), else the ACES container flag (ACES2065-1), else "" (the caller
// then takes oiio:ColorSpace or the default). Chromaticities matching none is refused, naming them.
Result<std::string> header_colour_space(const FileColour& file, const ColourConfig& config);

// The output header's colour attributes for `space`: its chromaticities where it has known
// primaries (erased otherwise), acesImageContainerFlag 1 for ACES2065-1 (erased otherwise),
// oiio:ColorSpace its name.
void write_colour_attributes(OIIO::ImageSpec& spec, const std::string& space, const ColourConfig& config);

}  // namespace wavecam::detail
