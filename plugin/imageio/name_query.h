// The settings a plugin name carries after its '?': "shot.exr.wavecam?pinhole=0.2mm&runs=8".
#pragma once
#include <string>

#include "../front/settings.h"
#include "wavecam/result.h"

namespace wavecam::plugin {

struct NameQuery {
    std::string path;         // the name before '?': "shot.exr.wavecam"
    front::Settings settings;  // {pinhole: 0.2mm, runs: 8}
};

// Splits `name` at its first '?' into KEY=VALUE items joined by '&', each key and value
// percent-decoded (RFC 3986: %20 is a space, %26 an '&', %3D an '=', %25 a '%'; '+' is itself).
// Refused, naming `name` and what was expected: an empty item (a trailing or doubled '&'), an
// item without '=', an empty key, a key given twice (as the command refuses an option given
// twice) and a '%' not followed by two hex digits.
Result<NameQuery> split_query(const std::string& name);

}  // namespace wavecam::plugin
