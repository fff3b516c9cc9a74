// Quantities with units, as typed on a command line or in a description file:
// "0.3mm", "550nm", "50deg", "inf", "16GiB". Values come back in SI (metres, radians, bytes).
#pragma once
#include <string>
#include <string_view>
#include "wavecam/result.h"

namespace wavecam {

// A length: nm, um (or µm), mm, cm, m. `field` names the flag or key for the error.
Result<double> parse_length(std::string_view text, std::string_view field);
// A length, or "inf" for a source at infinity (returns +infinity).
Result<double> parse_length_or_inf(std::string_view text, std::string_view field);
// An angle: deg or rad.
Result<double> parse_angle(std::string_view text, std::string_view field);
// A size in memory: KiB, MiB, GiB (powers of 1024) or KB, MB, GB (of 1000); > 0.
Result<double> parse_bytes(std::string_view text, std::string_view field);
// A whole number from `lo` to `hi` written without a unit ("255").
Result<long> parse_whole_number(std::string_view text, std::string_view field, long lo, long hi);

// The text the parsers read back, for headers and defaults: with_unit(0.3e-3, 1e-3, "mm") is
// "0.3mm" (six significant digits).
std::string with_unit(double value, double scale, std::string_view unit);

}  // namespace wavecam
