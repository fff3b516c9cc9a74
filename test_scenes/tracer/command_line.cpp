#include "command_line.h"
#include <cstdlib>
#include "units.h"

namespace wavecam::trace {

const char* const kUsage =
    "usage: wavecam-trace SCENE.toml OUT.exr [--width N] [--height N] [--samples N]\n"
    "                     [--pinhole-diameter LENGTH --film-distance LENGTH]\n"
    "Renders a scene to an OpenEXR with R, G, B (linear radiance) and Z (planar depth).\n"
    "--pinhole-diameter/--film-distance (e.g. 0.5mm, 50mm) render through a finite pinhole\n"
    "(ray optics) instead of the ideal one.\n";

namespace {
Result<int> parse_count(const std::string& flag, const std::string& text) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str() || *end != '\0' || v < 1 || v > 65536)
        return Error{flag + " '" + text + "': expected a whole number from 1 to 65536"};
    return static_cast<int>(v);
}
}  // namespace

Result<TraceOptions> parse_command_line(const std::vector<std::string>& args) {
    TraceOptions o;
    std::vector<std::string> positional;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            o.help = true;
            return o;
        }
        if (a.rfind("--", 0) != 0) {
            positional.push_back(a);
            continue;
        }
        if (i + 1 >= args.size()) return Error{a + ": missing value"};
        const std::string& value = args[++i];
        if (a == "--width" || a == "--height" || a == "--samples") {
            Result<int> n = parse_count(a, value);
            if (!n) return Error{n.error()};
            (a == "--width" ? o.width : a == "--height" ? o.height : o.samples) = *n;
        } else if (a == "--pinhole-diameter" || a == "--film-distance") {
            Result<double> length = parse_length(value, a);
            if (!length) return Error{length.error()};
            (a == "--pinhole-diameter" ? o.pinhole.diameter : o.pinhole.film_distance) = *length;
            (a == "--pinhole-diameter" ? o.pinhole_text : o.film_distance_text) = value;
        } else {
            return Error{"unknown option " + a};
        }
    }
    if (positional.size() != 2) return Error{"expected SCENE.toml and OUT.exr (see --help)"};
    if ((o.pinhole.diameter > 0) != (o.pinhole.film_distance > 0))
        return Error{"--pinhole-diameter and --film-distance go together"};
    o.scene_path = positional[0];
    o.output_path = positional[1];
    return o;
}

}  // namespace wavecam::trace
