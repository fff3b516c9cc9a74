// Writes a render as the float32 OpenEXR wavecam reads: channels R, G, B (linear radiance)
// and Z (planar depth, metres; 1e10 = nothing hit), with the header attributes
// wavecam.fov (horizontal, degrees), wavecam.depth = "planar", wavecam.scene and the standard
// worldToCamera (dotted names, as wavecam reads them: OIIO treats a "wavecam:" prefix as
// format-specific once wavecam's plugin is loaded and drops it). The file appears complete
// or not at all: core's write_image_atomically writes a temporary beside it, then renames.
#pragma once
#include <array>
#include <string>
#include <utility>
#include <vector>
#include "render.h"
#include "wavecam/result.h"

namespace wavecam::trace {

struct ExrHeader {
    float fov_deg = 0;
    std::string scene_name;
    std::array<float, 16> world_to_camera{};
    std::vector<std::pair<std::string, std::string>> extra;  // further string attributes
};

Result<bool> write_exr(const std::string& path, const RenderedImage& image, const ExrHeader& header);

}  // namespace wavecam::trace
