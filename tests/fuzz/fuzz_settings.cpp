// Fuzzes the settings vocabulary (the flags, hints and description keys): input lines
// "key=value" become settings; the result is options or an error, never a crash.
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

#include "front/settings.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    wavecam::front::Settings settings;
    for (std::string line; std::getline(in, line);) {
        const size_t eq = line.find('=');
        settings[line.substr(0, eq)] = eq == std::string::npos ? "" : line.substr(eq + 1);
    }
    wavecam::front::SettingSources sources;
    sources.given = settings;
    sources.given_name = [](const std::string& key) { return "--" + key; };
    auto r = wavecam::front::resolve_settings(OIIO::ImageSpec(), sources);
    if (!r.ok() && r.error.empty()) std::abort();
    if (r.ok() && (r.value.options.scene_sum.runs < 1 || r.value.options.wavelength_count < 1)) std::abort();
    // bounds are numbers: no nan or inf switches one off; a film at least 0.1 mm from the pinhole
    if (r.ok() && (!std::isfinite(r.value.options.max_terms) || !(r.value.options.max_terms > 0) ||
                   !(r.value.options.film_distance >= 0.1e-3)))
        std::abort();
    return 0;
}
