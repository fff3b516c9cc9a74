// Lengths as typed on the command line: "0.5mm", "50mm", "550nm". The unit is required.
#pragma once
#include <string_view>
#include "result.h"

namespace wavecam::trace {

// A positive length with unit nm, um, mm, cm or m; returns metres. `field` names the flag.
Result<double> parse_length(std::string_view text, std::string_view field);

}  // namespace wavecam::trace
