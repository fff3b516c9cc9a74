#include "settings.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "wavecam/aperture_mask.h"
#include "wavecam/units.h"

namespace wavecam::front {

const std::vector<std::pair<std::string, std::string>>& setting_keys() {
    static const std::vector<std::pair<std::string, std::string>> keys = {
        {"pinhole", "pinhole diameter, e.g. 0.25mm (default: the optimum 1.9 sqrt(f lambda) at 550nm)"},
        {"aperture", "circle, square, polygon:N[:ROTATIONdeg] (vertex on +x at 0deg), mask:FILE (greyscale amplitude transmission, width = pinhole), zoneplate:N (N zones, outer diameter = pinhole) or sieve:N[:Kx][:FILL%][:SEED] (photon sieve: holes K zone widths wide, default 1.5x, covering FILL of each ring, default 50%)"},
        {"film-distance", "pinhole to film, e.g. 50mm"},
        {"fov", "the render's horizontal field of view, e.g. 50deg (default: from the file)"},
        {"depth-channel", "depth channel name (default Z; Blender: ViewLayer.Depth.Z)"},
        {"depth", "depth meaning: planar (along the view axis) or ray"},
        {"wavelengths", "a count over 400-700nm (e.g. 16) or a list: 450nm,550nm,650nm"},
        {"monochrome", "true: every channel diffracted with the same light (the wavelengths' mean PSF), grey in, grey out; "
                       "automatic for fewer than 3 wavelengths"},
        {"runs", "random-phase runs averaged; noise falls as 1/sqrt(runs)"},
        {"method", "fast (PSF-grid convolution, default), random-phase or its old name exact (the seed paper's random-phase sum), or incoherent (the exact incoherent sum)"},
        {"seed", "random seed: the same seed gives the same image"},
        {"film-subsamples", "n: each film pixel averages n x n points over its area (0 = enough to resolve the PSF)"},
        {"jitter", "true: move each source within its pixel every run"},
        {"vignetting", "true: keep the natural cos^4 fall-off; false divides it out"},
        {"colorconfig", "OpenColorIO config (default: wavecam's own)"},
        {"input-colorspace", "colour space of the input (default: from the file, else lin_rec709)"},
        {"output-colorspace", "colour space of the output (default: the input's)"},
        {"out-of-gamut", "desaturate (default): a colour the output space cannot hold (a negative channel) is pulled "
                         "toward the grey of the same luminance until that channel is 0; keep: written as it is"},
        {"max-terms", "refuse exact-method jobs (or shares) beyond this many terms (default 4e12); the estimate and its time at the measured rate print before work"},
        {"max-memory", "refuse jobs estimated to need more memory, e.g. 16GiB (the default), 512MiB"},
        {"overscan", "pixels of margin the render has on every side: light sources, cropped from the output "
                     "(the fov describes the whole input)"},
    };
    return keys;
}

namespace {

Result<bool> parse_bool(const std::string& key, const std::string& v) {
    if (v == "true" || v == "1" || v == "yes" || v == "on") return Result<bool>::success(true);
    if (v == "false" || v == "0" || v == "no" || v == "off") return Result<bool>::success(false);
    return Result<bool>::failure(key + ": expected true or false, got '" + v + "'");
}

Result<bool> parse_choice(const std::string& key, const std::string& v, std::initializer_list<const char*> choices) {
    std::string list;
    for (const char* c : choices) {
        if (v == c) return Result<bool>::success(true);
        list += (list.empty() ? "'" : ", '") + std::string(c) + "'";
    }
    return Result<bool>::failure(key + ": expected one of " + list + ", got '" + v + "'");
}

// "16" = that many wavelengths over the visible range; "450nm,550nm,650nm" = a list.
Result<bool> parse_wavelengths(const std::string& text, DiffractOptions& o) {
    if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
        auto n = parse_whole_number(text, "wavelengths", 1, 1000);
        if (!n.ok()) return Result<bool>::failure(n.error);
        o.wavelength_count = static_cast<int>(n.value);
        return Result<bool>::success(true);
    }
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        item.erase(0, item.find_first_not_of(' '));
        auto l = parse_length(item, "wavelengths");
        if (!l.ok()) return Result<bool>::failure(l.error);
        o.wavelengths.push_back(l.value);
    }
    if (o.wavelengths.empty()) return Result<bool>::failure("wavelengths: expected a count or a list, got ''");
    return Result<bool>::success(true);
}

}  // namespace

Result<DiffractOptions> options_from_settings(const Settings& settings) {
    DiffractOptions o;
    auto fail = [](const std::string& m) { return Result<DiffractOptions>::failure(m); };
    for (const auto& entry : settings) {
        const std::string& key = entry.first;  // named, not bound: lambdas below capture it
        const std::string& value = entry.second;
        const auto& keys = setting_keys();
        if (std::none_of(keys.begin(), keys.end(), [&](const auto& k) { return k.first == key; })) {
            std::string known;
            for (const auto& k : keys) known += (known.empty() ? "" : ", ") + k.first;
            return fail(key + ": unknown key (known: " + known + ")");
        }
        std::string error;
        auto take = [&error](const auto& r, auto& dst) {
            if (!r.ok()) error = r.error;
            else dst = r.value;
        };
        if (key == "pinhole") take(parse_length(value, key), o.pinhole);
        else if (key == "aperture") take(load_aperture(value, key), o.aperture);
        else if (key == "film-distance") take(parse_length(value, key), o.film_distance);
        else if (key == "fov") take(parse_angle(value, key), o.read.fov_h);
        else if (key == "depth-channel") o.read.depth_channel = value;
        else if (key == "depth") {
            auto c = parse_choice(key, value, {"planar", "ray"});
            if (!c.ok()) error = c.error;
            o.depth_meaning = value == "ray" ? DepthMeaning::Ray : DepthMeaning::Planar;
        } else if (key == "wavelengths") {
            auto w = parse_wavelengths(value, o);
            if (!w.ok()) error = w.error;
        } else if (key == "monochrome") take(parse_bool(key, value), o.monochrome);
        else if (key == "runs") {
            long n = 0;
            take(parse_whole_number(value, key, 1, 100000), n);
            o.diffraction.runs = static_cast<int>(n);
        } else if (key == "method") {
            auto c = parse_choice(key, value, {"fast", "exact", "random-phase", "incoherent"});
            if (!c.ok()) error = c.error;
            o.method = value == "fast"    ? DiffractMethod::Fast
                       : value == "exact" || value == "random-phase" ? DiffractMethod::RandomPhase
                                          : DiffractMethod::Incoherent;
        } else if (key == "seed") {
            long n = 0;
            take(parse_whole_number(value, key, 0, 1L << 62), n);
            o.diffraction.seed = static_cast<uint64_t>(n);
        } else if (key == "film-subsamples") {
            long n = 0;
            take(parse_whole_number(value, key, 0, 16), n);
            o.diffraction.film_subsamples = static_cast<int>(n);
        } else if (key == "jitter") take(parse_bool(key, value), o.diffraction.jitter);
        else if (key == "vignetting") take(parse_bool(key, value), o.vignetting);
        else if (key == "colorconfig") o.colorconfig = value;
        else if (key == "input-colorspace") o.input_colorspace = value;
        else if (key == "output-colorspace") o.output_colorspace = value;
        else if (key == "out-of-gamut") {
            auto c = parse_choice(key, value, {"desaturate", "keep"});
            if (!c.ok()) error = c.error;
            o.desaturate_out_of_gamut = value == "desaturate";
        }
        else if (key == "max-terms") {
            char* end = nullptr;
            o.max_terms = std::strtod(value.c_str(), &end);
            if (value.empty() || *end != '\0' || !(o.max_terms > 0))
                error = "max-terms: expected a positive number, got '" + value + "'";
        }
        else if (key == "max-memory") take(parse_bytes(value, key), o.max_memory);
        else if (key == "overscan") {
            long n = 0;
            take(parse_whole_number(value, key, 0, 100000), n);
            o.overscan = static_cast<int>(n);
        }
        if (!error.empty()) return fail(error);
    }
    return Result<DiffractOptions>::success(o);
}

}  // namespace wavecam::front
