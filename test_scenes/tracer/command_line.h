// The wavecam-trace command line:
//   wavecam-trace SCENE.toml OUT.exr [--width N] [--height N] [--samples N]
//                 [--pinhole-diameter LENGTH --film-distance LENGTH]
// Lengths carry a unit (nm, um, mm, cm, m): --pinhole-diameter 0.5mm --film-distance 50mm
// renders the ray-optics image of a finite pinhole instead of the ideal one.
#pragma once
#include <optional>
#include <string>
#include <vector>
#include "finite_pinhole.h"
#include "wavecam/result.h"

namespace wavecam::trace {

struct TraceOptions {
    std::string scene_path, output_path;
    std::optional<int> width, height, samples;  // override the scene file's
    FinitePinhole pinhole;                      // diameter 0: ideal pinhole
    std::string pinhole_text, film_distance_text;  // as typed, for the output header
    bool help = false;
};

Result<TraceOptions> parse_command_line(const std::vector<std::string>& args);

extern const char* const kUsage;

}  // namespace wavecam::trace
