#include "settings.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>
#include <sstream>

#include "wavecam/aperture_mask.h"
#include "wavecam/share_files.h"
#include "wavecam/spectrum.h"
#include "wavecam/units.h"

namespace wavecam::front {
namespace {

using Ok = Result<bool>;

Ok fail(const std::string& name, const std::string& expected, const std::string& text) {
    return Ok::failure(name + ": expected " + expected + ", got '" + text + "'");
}

template <class T, class U>
Ok take(const Result<T>& r, U& dst) {
    if (!r.ok()) return Ok::failure(r);
    dst = static_cast<U>(r.value);
    return Ok::success(true);
}

Result<bool> parse_bool(const std::string& name, const std::string& v) {
    if (v == "true" || v == "1" || v == "yes" || v == "on") return Result<bool>::success(true);
    if (v == "false" || v == "0" || v == "no" || v == "off") return Result<bool>::success(false);
    return fail(name, "true or false", v);
}

// A length > 0 (pinhole, film distance).
Result<double> parse_size(const std::string& name, const std::string& v) {
    auto l = parse_length(v, name);
    if (l.ok() && !(l.value > 0)) return Result<double>::failure(fail(name, "a length > 0", v).error);
    return l;
}

// A setting whose value is its text.
Ok copy_text(const std::string& v, std::string& dst) {
    dst = v;
    return Ok::success(true);
}

// `choices`: a braced list of (word, value), or any such range (summation_choices).
template <class E, class Choices = std::initializer_list<std::pair<const char*, E>>>
Ok parse_choice(const std::string& name, const std::string& v, const Choices& choices, E& dst) {
    std::string list;
    for (const auto& [word, value] : choices) {
        if (v == word) {
            dst = value;
            return Ok::success(true);
        }
        list += (list.empty() ? "'" : ", '") + std::string(word) + "'";
    }
    return fail(name, "one of " + list, v);
}

// "16" = that many wavelengths over the visible range; "450nm,550nm,650nm" = a list. Checked
// here as the diffraction will sample them.
Ok parse_wavelengths(const std::string& text, const std::string& name, DiffractOptions& o) {
    o.wavelengths.clear();
    if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
        auto n = parse_whole_number(text, name, 1, 1000);
        if (!n.ok()) return fail(name, "a count 1-1000 or a list such as 450nm,550nm,650nm", text);
        o.wavelength_count = static_cast<int>(n.value);
        return Ok::success(true);
    }
    const std::string expected = "a count 1-1000 or a list such as 450nm,550nm,650nm";
    if (text.find(',') == std::string::npos && !parse_length(text, name).ok()) return fail(name, expected, text);
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        item.erase(0, item.find_first_not_of(' '));
        auto l = parse_length(item, name);
        if (!l.ok()) return Ok::failure(l);
        // light, not X-rays or radio: the pinhole, film and depth checks are made against it
        if (!(l.value >= 100e-9 && l.value <= 10e-6)) return fail(name, "wavelengths from 100nm to 10um", item);
        o.wavelengths.push_back(l.value);
    }
    if (o.wavelengths.empty()) return fail(name, expected, text);
    if (auto s = explicit_sampling(o.wavelengths); !s.ok())  // "wavelengths: expected ..."
        return Ok::failure(name + s.error.substr(s.error.find(':')));
    return Ok::success(true);
}

const std::vector<SettingKey> kKeys = {
    {"pinhole", "0.25mm", "pinhole diameter, e.g. 0.25mm (default: the optimum 1.9 sqrt(f lambda) at 550nm)", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) { return take(parse_size(n, v), o.pinhole); }},
    {"aperture", "polygon:6", "circle, square, polygon:N[:ROTATIONdeg] (vertex on +x at 0deg), mask:FILE (greyscale "
     "amplitude transmission, width = pinhole), zoneplate:N (N zones, outer diameter = pinhole) or "
     "sieve:N[:Kx][:FILL%][:SEED] (photon sieve: holes K zone widths wide, default 1.5x, covering FILL of each ring, "
     "default 50%)", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) { return take(load_aperture(v, n), o.aperture); }},
    {"film-distance", "50mm", "pinhole to film, e.g. 50mm", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return take(parse_film_distance(v, n), o.film_distance);
     }},
    {"fov", "50deg", "the render's horizontal field of view, e.g. 50deg (default: from the file)", false,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         auto a = parse_angle(v, n);
         if (a.ok() && !(a.value > 0 && a.value < M_PI)) return fail(n, "an angle between 0 and 180deg", v);
         return take(a, o.read.fov_h);
     }},
    {"depth-channel", "ViewLayer.Depth.Z", "depth channel name (default Z; Blender: ViewLayer.Depth.Z)", true,
     [](const std::string& v, const std::string&, DiffractOptions& o) { return copy_text(v, o.read.depth_channel); }},
    {"depth-scale", "1cm", "how long one unit of the render's depth channel is, e.g. 1cm for a scene modelled in "
     "centimetres (default 1m: depth in metres); depth >= 1e9 stays sky", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         auto l = parse_length(v, n);
         if (l.ok() && !(l.value > 0 && std::isfinite(l.value)))
             return fail(n, "a length > 0 (one depth unit of the render, e.g. 1cm)", v);
         return take(l, o.read.depth_scale);
     }},
    {"depth", "planar", "depth meaning: planar (along the view axis) or ray", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, {{"planar", DepthMeaning::Planar}, {"ray", DepthMeaning::Ray}}, o.depth_meaning);
     }},
    {"wavelengths", "16", "a count over 400-700nm (e.g. 16) or a list: 450nm,550nm,650nm", true, parse_wavelengths},
    {"monochrome", "true", "true: every channel diffracted with the same light (the wavelengths' mean PSF), grey in, "
     "grey out; automatic for fewer than 3 wavelengths", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) { return take(parse_bool(n, v), o.monochrome); }},
    {"runs", "256", "random-phase runs averaged: a count, or auto (the default: from the PSF's size in pixels, 64 to "
     "1024, for every colour channel's noise within 2%; the job line says the count)", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         o.runs_from_psf = v == "auto";
         return o.runs_from_psf ? Result<bool>::success(true)
                                : take(parse_whole_number(v, n, 1, 100000), o.scene_sum.runs);
     }},
    {"method", "random-phase", "convolution (the default: PSF-grid convolution), random-phase (the seed paper's "
     "random-phase runs) or incoherent (every source propagated alone: the infinite-run limit)",
     true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v,
                             {{"convolution", DiffractMethod::Convolution}, {"random-phase", DiffractMethod::RandomPhase},
                              {"incoherent", DiffractMethod::Incoherent}},
                             o.method);
     }},
    {"summation", "direct", "how the random-phase and incoherent methods evaluate their two sums: auto (default: kernel where "
     "it applies and is cheaper, else the cheaper of direct and nufft by the work estimate), direct (term by term, the reference), nufft (NUFFTs "
     "over the pinhole lattice, relative error ~3e-4) or kernel (each run a convolution with amplitude PSFs that the "
     "sums compute at field anchors and depth layers; sources at pixel centres)",
     true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, summation_choices(), o.scene_sum.summation);  // the evaluators' table's words
     }},
    {"device", "gpu", "where the random-phase and incoherent methods run their direct sums and kernel runs: cpu (default), gpu "
     "(a Vulkan device, a discrete GPU first, running every sum; an error if there is none, and for summation nufft, "
     "which has no GPU evaluator) or auto (a discrete GPU when there is one, else the CPU, said in the job line); "
     "the machine's choice, never a source's metadata",
     false,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, {{"cpu", Device::Cpu}, {"gpu", Device::Gpu}, {"auto", Device::Auto}},
                             o.device);
     }},
    {"phases", "independent", "random-phase runs' phases: coded (run k offsets class m by 2 pi k m / runs, so "
     "that different classes cancel exactly; default) or independent (the seed paper's; noise ~ 1/sqrt(runs))",
     true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, {{"coded", true}, {"independent", false}}, o.scene_sum.coded_phases);
     }},
    {"seed", "7", "random seed: the same seed gives the same image", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return take(parse_whole_number(v, n, 0, 1L << 62), o.scene_sum.seed);
     }},
    {"film-subsamples", "3", "n: each film pixel averages n x n points over its area (0 = enough to resolve the PSF)",
     true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return take(parse_whole_number(v, n, 0, 16), o.scene_sum.film_subsamples);
     }},
    {"jitter", "true", "true: move the sources within their pixels (coded phases: all by one random offset; "
     "independent: each anew every run); default false, sources at pixel centres as the convolution method has them", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return take(parse_bool(n, v), o.scene_sum.jitter);
     }},
    {"vignetting", "false", "true: keep the natural cos^4 fall-off; false divides it out", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) { return take(parse_bool(n, v), o.vignetting); }},
    {"colorconfig", "config.ocio", "OpenColorIO config (default: wavecam's own)", true,
     [](const std::string& v, const std::string&, DiffractOptions& o) { return copy_text(v, o.colorconfig); }},
    {"input-colorspace", "ACEScg", "colour space of the input (default: from the file, else lin_rec709)", false,
     [](const std::string& v, const std::string&, DiffractOptions& o) { return copy_text(v, o.input_colorspace); }},
    {"output-colorspace", "ACEScg", "colour space of the output (default: the input's)", true,
     [](const std::string& v, const std::string&, DiffractOptions& o) { return copy_text(v, o.output_colorspace); }},
    {"out-of-gamut", "keep", "desaturate (default): a colour the output space cannot hold (a negative channel) is "
     "pulled toward the grey of the same luminance until that channel is 0; keep: written as it is", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         bool desaturate = true;
         auto c = parse_choice(n, v, {{"desaturate", true}, {"keep", false}}, desaturate);
         o.desaturate_out_of_gamut = desaturate;
         return c;
     }},
    {"max-terms", "1e14", "refuse scene-sum jobs (or shares) beyond this many terms (default 4e12); the estimate "
     "and its time at the measured rate print before work", false,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         char* end = nullptr;
         const double t = std::strtod(v.c_str(), &end);
         if (v.empty() || *end != '\0' || !(t > 0) || !std::isfinite(t))
             return fail(n, "a number of terms > 0 such as 4e12 (not inf or nan)", v);
         o.max_terms = t;
         return Ok::success(true);
     }},
    {"max-memory", "32GiB", "refuse jobs estimated to need more memory, e.g. 16GiB (the default), 512MiB", false,
     [](const std::string& v, const std::string& n, DiffractOptions& o) { return take(parse_bytes(v, n), o.max_memory); }},
    {"layer", "ViewLayer.Combined", "the radiance layer, by name: the channels LAYER.R, LAYER.G, LAYER.B (and LAYER.A); "
     "default: the only layer with R, G, B, else the unnamed one, else the one named Combined or beauty (several are "
     "refused, naming them)", true,
     [](const std::string& v, const std::string&, DiffractOptions& o) { return copy_text(v, o.read.layer); }},
    {"other-channels", "drop", "keep (default): every channel beside the radiance layer (depth, AOVs, Cryptomatte, "
     "IDs) passes through unchanged; drop: the output holds the radiance layer and depth only", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, {{"keep", true}, {"drop", false}}, o.other_channels);
     }},
    {"negative", "clamp", "negative radiance or alpha: refuse (default; the message names the pixel) or clamp (set to "
     "0; the output says how many values)", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, {{"refuse", false}, {"clamp", true}}, o.read.clamp_negative);
     }},
    {"pixel-type", "half", "the diffracted channels' type in an OpenEXR output: keep (default: the input's), half or "
     "float; every other channel keeps its own", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, {{"keep", OIIO::TypeDesc(OIIO::TypeUnknown)}, {"half", OIIO::TypeDesc(OIIO::TypeHalf)},
                                    {"float", OIIO::TypeDesc(OIIO::TypeFloat)}},
                             o.pixel_type);
     }},
    {"half-overflow", "clamp", "an OpenEXR output's diffracted channels written as half that hold values beyond "
     "half's range (65504), which half would write as inf: float (default: those channels written as float), clamp "
     "(set to 65504) or refuse (nothing written); the command says how many values and the largest", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return parse_choice(n, v, {{"float", HalfOverflow::Float}, {"clamp", HalfOverflow::Clamp},
                                    {"refuse", HalfOverflow::Refuse}},
                             o.half_overflow);
     }},
    {"compression", "zip", "the OpenEXR output's compression: keep (default: the input's), none, rle, zips, zip, piz, "
     "pxr24, b44, b44a, dwaa or dwab (pxr24, b44 and dwa are lossy)", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         for (const char* c : {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"})
             if (v == c) return copy_text(v, o.compression);
         if (v == "keep") return copy_text("", o.compression);
         return fail(n, "keep, none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa or dwab", v);
     }},
    {"diffract-again", "true", "true: diffract a file wavecam wrote (its header names the first job) once more; "
     "default false refuses it, as blurring twice is rarely meant", false,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return take(parse_bool(n, v), o.read.diffract_again);
     }},
    {"subimage", "NAME", "the part (subimage) of a multi-part file to read, by its name; a file of several parts "
     "is refused without it (the message names them)", false,
     [](const std::string& v, const std::string&, DiffractOptions& o) { return copy_text(v, o.read.subimage); }},
    {"overscan", "32", "pixels of margin the render has on every side: light sources, cropped from the output "
     "(the fov describes the whole input); for a file without its own windows (an OpenEXR data window beyond "
     "its display window is overscan read from the file)", true,
     [](const std::string& v, const std::string& n, DiffractOptions& o) {
         return take(parse_whole_number(v, n, 0, 100000), o.overscan);
     }},
};

// Words a setting had before its present vocabulary: still taken, with a note naming the new one.
struct OldSpelling {
    const char *key, *old_word, *word;
};
constexpr OldSpelling kOldSpellings[] = {
    {"method", "fast", "convolution"},
    {"method", "exact", "random-phase"},
    {"summation", "fast", "auto"},
    {"summation", "psf", "kernel"},
};

// The present word for `text`, and a note when it is an old spelling.
std::string present_word(const std::string& key, const std::string& text, const std::string& name,
                         std::vector<std::string>& notes) {
    for (const OldSpelling& o : kOldSpellings)
        if (key == o.key && text == o.old_word) {
            notes.push_back(name + ": '" + text + "' is now called '" + o.word + "'");
            return o.word;
        }
    return text;
}

}  // namespace

Result<double> parse_film_distance(const std::string& text, const std::string& name) {
    auto l = parse_length(text, name);
    if (l.ok() && !(l.value >= 0.1e-3))
        return Result<double>::failure(fail(name, "a film distance of 0.1mm or more", text).error);
    return l;
}

namespace {

const SettingKey* find_key(const std::string& key) {
    for (const SettingKey& k : kKeys)
        if (k.key == key) return &k;
    return nullptr;
}

// What wavecam and its tools write into headers beside the settings: records of a run (the
// output's, a share file's `wavecam.share` and `wavecam.share.*`, `wavecam psf`'s, the compare
// sheet's) and of the scene (the tracer's, the POV-Ray harness's). Read back from a source they
// are known, and set nothing.
constexpr const char* kRecordedAttributes[] = {
    "fov", "fov-from", "film-width", "cropped-overscan", "light", "summation-chosen", "alpha", "negative-clamped",
    "out-of-gamut-mapped", "fresnel-number", "summary", "job", "diffracted-channels", "edge", "half-overflow-written",
    "views", "scene", "scene-unit", "ray-pinhole", "ray-film-distance", "pov-frame", "pov-clock", "display", "view",
    "quantity", "zoneplate-focus", "source-angle", "source-distance", "wavelength", "film-size", "pixel-pitch",
    "film-centre", "sample-pitch", "sample-count", "orientation"};

// A share file's records (share_files.h): share, share.NAME, and part.NAME, their other spelling.
bool is_share_record(const std::string& key) { return key == "share" || key.rfind("share.", 0) == 0; }
bool is_old_share_record(const std::string& key) { return key.rfind("part.", 0) == 0; }

bool is_recorded_attribute(const std::string& key) {
    if (is_share_record(key) || is_old_share_record(key)) return true;
    for (const char* r : kRecordedAttributes)
        if (key == r) return true;
    return false;
}

// Levenshtein distance: the edits that make a into b.
size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

}  // namespace

std::string nearest_key(const std::string& unknown) {
    std::string spelled = unknown;  // film_distance, FILM-DISTANCE: the same key
    for (char& c : spelled) c = c == '_' ? '-' : char(std::tolower(static_cast<unsigned char>(c)));
    std::string best;
    size_t least = std::max<size_t>(3, spelled.size() / 3) + 1;  // beyond a third of the word: no guess
    for (const SettingKey& k : kKeys)
        if (const size_t d = edit_distance(spelled, k.key); d < least) {
            least = d;
            best = k.key;
        }
    return best;
}

std::string unknown_key_message(const std::string& name, const std::string& key) {
    std::string known;
    for (const SettingKey& s : kKeys) known += (known.empty() ? "" : ", ") + s.key;
    const std::string nearest = nearest_key(key);
    return name + ": unknown key" + (nearest.empty() ? "" : "; did you mean '" + nearest + "'?") + " (known: " + known +
           ")";
}

namespace {

// A metadata value as the text a person would type: strings as they are, numbers printed.
Result<std::string> attribute_text(const OIIO::ParamValue& p) {
    const OIIO::TypeDesc t = p.type();
    if (t == OIIO::TypeDesc::STRING) return Result<std::string>::success(p.get_string());
    if (t.aggregate == OIIO::TypeDesc::SCALAR && t.arraylen == 0 && t.basetype >= OIIO::TypeDesc::UINT8 &&
        t.basetype <= OIIO::TypeDesc::DOUBLE)
        return Result<std::string>::success(t.is_floating_point() ? p.get_string() : std::to_string(p.get_int()));
    return Result<std::string>::failure(p.name().string() + ": expected a string or a number, got a value of type " +
                                        t.c_str());
}

}  // namespace

const std::vector<SettingKey>& setting_keys() { return kKeys; }

Result<ResolvedSettings> resolve_settings(const OIIO::ImageSpec& source, const SettingSources& sources) {
    using R = Result<ResolvedSettings>;
    struct Given {
        std::string text, name;
    };
    std::map<std::string, Given> layers;  // each key from the highest layer that gives it
    bool old_share_records = false;        // wavecam.part.* records: read, with a note
    for (const OIIO::ParamValue& p : source.extra_attribs) {
        const std::string attribute = p.name().string();
        if (attribute.rfind("wavecam.", 0) != 0) continue;
        const SettingKey* k = find_key(attribute.substr(8));
        // a typo never falls back to a default: a name that is neither a setting nor a record is refused
        if (!k && !is_recorded_attribute(attribute.substr(8)))
            return R::failure(unknown_key_message(attribute + " (the file's header)", attribute.substr(8)));
        old_share_records |= is_old_share_record(attribute.substr(8));
        if (!k || !k->from_source) continue;
        auto text = attribute_text(p);
        if (!text.ok()) return R::failure(text);
        layers[k->key] = {text.value, attribute};
    }
    // A file wavecam wrote holds pixels in the space it names as its output-colorspace (OpenEXR
    // keeps no oiio:ColorSpace): read back, that is its input's.
    if (auto written = layers.find("output-colorspace"); written != layers.end())
        layers["input-colorspace"] = {written->second.text, "wavecam.output-colorspace"};
    for (const auto& [key, text] : sources.description)
        layers[key] = {text, sources.description_path + ": " + key};
    for (const auto& [key, text] : sources.given) layers[key] = {text, sources.given_name(key)};

    ResolvedSettings r;
    if (old_share_records) r.notes.push_back(kOldShareRecordNote);
    r.options.runs_from_psf = true;  // the fronts' default: runs=auto
    for (const auto& [key, given] : layers) {
        const SettingKey* k = find_key(key);
        if (!k) return R::failure(unknown_key_message(given.name, key));
        const std::string text = present_word(key, given.text, given.name, r.notes);
        if (auto a = k->apply(text, given.name, r.options); !a.ok()) return R::failure(a);
        r.text[key] = text;
    }
    if (auto fov = layers.find("fov"); fov != layers.end())
        r.options.read.fov_from = sources.description.count("fov") && !sources.given.count("fov")
                                      ? "fov in " + sources.description_path
                                      : fov->second.name;
    return R::success(std::move(r));
}

void show_notes(const std::vector<std::string>& notes) {
    static std::mutex lock;
    static std::set<std::string> shown;
    std::lock_guard<std::mutex> guard(lock);
    for (const std::string& n : notes)
        if (shown.insert(n).second) std::fprintf(stderr, "wavecam: %s\n", n.c_str());
}

std::string word_failure(const Result<bool>& f, Front front) {
    const bool command = front == Front::Command;
    auto name = [command](const std::string& key) { return command ? "--" + key : "wavecam:" + key; };
    auto give = [command](const std::string& key) {
        const SettingKey* k = find_key(key);
        const std::string example = k ? k->example : "VALUE";
        return command ? "--" + key + " " + example
                       : "--iconfig wavecam:" + key + " " + example + " or ?" + key + "=" + example + " in the name";
    };
    switch (f.kind) {
        case ErrorKind::Missing: return f.error + "; give it with " + give(f.field);
        case ErrorKind::TooLarge:
            if (f.field == "max-memory")
                return f.error + "; use a smaller image or pinhole, or raise " + name(f.field) + " (e.g. " + give(f.field) + ")";
            return f.error + "; lower " + name("runs") + ", " + name("wavelengths") + " or the image size, raise " +
                   name(f.field) + (command ? ", or share the work out (--share K/N, wavecam farm)" : "");
        case ErrorKind::Invalid: return f.error + " (" + name(f.field) + ")";
        default: return f.error;
    }
}

}  // namespace wavecam::front
