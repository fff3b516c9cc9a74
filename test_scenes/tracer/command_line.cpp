#include "command_line.h"
#include "wavecam/units.h"

namespace wavecam::trace {

const char* const kUsage =
    "usage: wavecam-trace SCENE.toml OUT.exr [--width N] [--height N] [--samples N]\n"
    "                     [--pinhole-diameter LENGTH --film-distance LENGTH]\n"
    "Renders a scene to an OpenEXR with R, G, B (linear radiance) and Z (planar depth).\n"
    "--pinhole-diameter/--film-distance (e.g. 0.5mm, 50mm) render through a finite pinhole\n"
    "(ray optics) instead of the ideal one.\n";

Result<TraceOptions> parse_command_line(const std::vector<std::string>& args) {
    TraceOptions o;
    std::vector<std::string> positional;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            o.help = true;
            return Result<TraceOptions>::success(o);
        }
        if (a.rfind("--", 0) != 0) {
            positional.push_back(a);
            continue;
        }
        if (i + 1 >= args.size()) return Result<TraceOptions>::failure(a + ": missing value");
        const std::string& value = args[++i];
        if (a == "--width" || a == "--height" || a == "--samples") {
            const Result<long> n = parse_whole_number(value, a, 1, 65536);
            if (!n.ok()) return Result<TraceOptions>::failure(n.error);
            (a == "--width" ? o.width : a == "--height" ? o.height : o.samples) = static_cast<int>(n.value);
        } else if (a == "--pinhole-diameter" || a == "--film-distance") {
            const Result<double> length = parse_length(value, a);
            if (!length.ok()) return Result<TraceOptions>::failure(length.error);
            if (!(length.value > 0)) return Result<TraceOptions>::failure(a + ": expected a positive length, got '" + value + "'");
            (a == "--pinhole-diameter" ? o.pinhole.diameter : o.pinhole.film_distance) = length.value;
            (a == "--pinhole-diameter" ? o.pinhole_text : o.film_distance_text) = value;
        } else {
            return Result<TraceOptions>::failure("unknown option " + a);
        }
    }
    if (positional.size() != 2) return Result<TraceOptions>::failure("expected SCENE.toml and OUT.exr (see --help)");
    if ((o.pinhole.diameter > 0) != (o.pinhole.film_distance > 0))
        return Result<TraceOptions>::failure("--pinhole-diameter and --film-distance go together");
    o.scene_path = positional[0];
    o.output_path = positional[1];
    return Result<TraceOptions>::success(o);
}

}  // namespace wavecam::trace
