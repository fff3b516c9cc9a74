// One vocabulary for every front: the same keys configure `wavecam apply` (as --KEY flags),
// the OIIO plugin (as `--iconfig wavecam:KEY VALUE` hints or the source's metadata) and
// description files (as TOML keys). Values are text with units, as a person types them.
#pragma once
#include <map>
#include <string>
#include <vector>
#include "wavecam/diffract_image.h"
#include "wavecam/result.h"

namespace wavecam::front {

using Settings = std::map<std::string, std::string>;

// Every key the fronts understand, with a one-line description (for help and errors).
const std::vector<std::pair<std::string, std::string>>& setting_keys();

// Applies `settings` over the defaults. Errors read "KEY: what was expected, got 'VALUE'";
// an unknown key is an error that lists the known ones.
Result<DiffractOptions> options_from_settings(const Settings& settings);

}  // namespace wavecam::front
