// Quantities with units, as typed on a command line or in a description file:
// "0.3mm", "550nm", "50deg", "inf". Values come back in SI (metres, radians).
#pragma once
#include <string_view>
#include "wavecam/result.h"

namespace wavecam {

// A length: nm, um (or µm), mm, cm, m. `field` names the flag or key for the error.
Result<double> parse_length(std::string_view text, std::string_view field);
// A length, or "inf" for a source at infinity (returns +infinity).
Result<double> parse_length_or_inf(std::string_view text, std::string_view field);
// An angle: deg or rad.
Result<double> parse_angle(std::string_view text, std::string_view field);
// A positive count written without a unit ("255").
Result<long> parse_count(std::string_view text, std::string_view field);

}  // namespace wavecam
