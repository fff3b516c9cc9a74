// `shot.wavecam` description files: a small TOML document naming the source render and the
// settings (the keys of settings.h). Parsed with toml++, never by hand.
//
//   source = "renders/shot.exr"   # relative to this file; must stay inside its folder
//   pinhole = "0.25mm"
//   film-distance = "50mm"
//   wavelengths = "8"             # or ["450nm", "550nm", "650nm"]
//   runs = 4
//   method = "convolution"       # or "random-phase" (the seed paper), "incoherent"
//   output-colorspace = "ACEScg"
//   aperture = "mask:pinhole.png"  # a mask, like the source, relative to this file and inside its folder
#pragma once
#include <string>
#include "settings.h"

namespace wavecam::front {

struct Description {
    std::string source;  // resolved path of the source render
    Settings settings;
};

// Reads a description file and checks its form and paths; its settings are checked when they
// are resolved (settings.h), with errors that name this file and the key.
Result<Description> read_description(const std::string& path);

// The same for a description already in memory; `path` places the source and names errors.
Result<Description> parse_description(std::string_view text, const std::string& path);

}  // namespace wavecam::front
