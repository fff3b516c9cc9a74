// Which channels are the render: the radiance layer chosen as a whole, its alpha, and a depth
// channel from the same layer or view layer (render_input.h, RenderChannels).
//
// A channel's layer is its name up to the last dot ("ViewLayer.Combined.R" is in layer
// "ViewLayer.Combined", "R" in the unnamed layer); a layer's view layer is its own name up to the
// last dot ("ViewLayer"). The radiance is the layer that holds R, G and B: the only one, else the
// unnamed layer (OpenEXR's default layer is the beauty), else the one layer named Combined
// (Blender) or beauty (most renderers). Anything else is ambiguous and refused, naming the
// candidates: two view layers' Combined, or AOV layers and no beauty.
#include "wavecam/render_input.h"

#include <OpenImageIO/strutil.h>

#include <map>

namespace wavecam {
namespace {
namespace Strutil = OIIO::Strutil;

std::string layer_of(const std::string& name) {
    const size_t dot = name.rfind('.');
    return dot == std::string::npos ? std::string() : name.substr(0, dot);
}

std::string last_word(const std::string& name) {
    const size_t dot = name.rfind('.');
    return dot == std::string::npos ? name : name.substr(dot + 1);
}

std::string shown(const std::string& layer) { return layer.empty() ? "R, G, B (no layer name)" : "'" + layer + "'"; }

struct ColourLayer {
    int r = -1, g = -1, b = -1, a = -1;
    bool complete() const { return r >= 0 && g >= 0 && b >= 0; }
};

std::map<std::string, ColourLayer> colour_layers(const OIIO::ImageSpec& spec) {
    std::map<std::string, ColourLayer> layers;
    for (int c = 0; c < spec.nchannels; ++c) {
        const std::string& n = spec.channelnames[c];
        const std::string word = last_word(n);
        ColourLayer& l = layers[layer_of(n)];
        if (word == "R") l.r = c;
        else if (word == "G") l.g = c;
        else if (word == "B") l.b = c;
        else if (word == "A") l.a = c;
    }
    for (auto it = layers.begin(); it != layers.end();) it = it->second.complete() ? std::next(it) : layers.erase(it);
    return layers;
}

// The radiance layer's name, or why none could be chosen.
Result<std::string> choose_radiance_layer(const std::map<std::string, ColourLayer>& layers, const std::string& asked) {
    using R = Result<std::string>;
    std::string names;
    for (const auto& [name, l] : layers) names += (names.empty() ? "" : ", ") + shown(name);
    if (!asked.empty()) {
        if (layers.count(asked)) return R::success(asked);
        return R::failure("layer '" + asked + "': no such layer holds R, G and B (" +
                              (layers.empty() ? std::string("none does") : "layers with R, G, B: " + names) +
                              "); expected one of them",
                          ErrorKind::Invalid, "layer");
    }
    if (layers.size() == 1) return R::success(layers.begin()->first);
    if (layers.count("")) return R::success(std::string());  // the unnamed layer: the file's beauty
    std::vector<std::string> beauty;
    for (const auto& [name, l] : layers)
        if (Strutil::iequals(last_word(name), "Combined") || Strutil::iequals(last_word(name), "beauty"))
            beauty.push_back(name);
    if (beauty.size() == 1) return R::success(beauty.front());
    return R::failure(std::to_string(layers.size()) + " layers could be the radiance (" + names + ")" +
                          (beauty.size() > 1 ? ", " + std::to_string(beauty.size()) + " of them a beauty pass" : "") +
                          "; expected one: choose it with the layer setting, e.g. " + shown(layers.rbegin()->first),
                      ErrorKind::Missing, "layer");
}

// The depth channel: a full name as given, else `want` in the radiance layer, else in its view
// layer (one only), else the unnamed `want`; for a radiance layer with no view layer, any one
// channel ending ".want".
Result<int> choose_depth(const OIIO::ImageSpec& spec, const std::string& layer, const std::string& want) {
    std::vector<int> in_view, anywhere;
    int exact = -1;
    const std::string view = layer_of(layer);
    for (int c = 0; c < spec.nchannels; ++c) {
        const std::string& n = spec.channelnames[c];
        if (n == want) exact = c;
        if (!layer.empty() && n == layer + "." + want) return Result<int>::success(c);
        if (!Strutil::ends_with(n, "." + want)) continue;
        anywhere.push_back(c);
        if (!view.empty() && Strutil::starts_with(n, view + ".")) in_view.push_back(c);
    }
    if (exact >= 0 && (want.find('.') != std::string::npos || in_view.empty())) return Result<int>::success(exact);
    const std::vector<int>& found = view.empty() ? anywhere : in_view;
    if (found.size() == 1) return Result<int>::success(found.front());
    if (found.empty()) return Result<int>::success(-1);
    std::string names;
    for (int c : found) names += (names.empty() ? "'" : ", '") + spec.channelnames[c] + "'";
    return Result<int>::failure("channel '" + want + "': " + std::to_string(found.size()) + " channels could be the depth (" +
                                    names + "); expected one: name it in full with the depth-channel setting",
                                ErrorKind::Missing, "depth-channel");
}

}  // namespace

Result<RenderChannels> find_render_channels(const OIIO::ImageSpec& spec, const RenderReadOptions& opt) {
    using R = Result<RenderChannels>;
    const auto layers = colour_layers(spec);
    RenderChannels ch;
    if (layers.empty() && opt.layer.empty()) return R::success(ch);  // (load_render says what is missing)
    auto layer = choose_radiance_layer(layers, opt.layer);
    if (!layer.ok()) return R::failure(layer);
    const ColourLayer& l = layers.at(layer.value);
    ch.layer = layer.value;
    ch.r = l.r;
    ch.g = l.g;
    ch.b = l.b;
    ch.alpha = l.a;
    auto depth = choose_depth(spec, ch.layer, opt.depth_channel);
    if (!depth.ok()) return R::failure(depth);
    ch.depth = depth.value;
    if (ch.alpha == ch.depth) ch.alpha = -1;  // depth channel A: depth, not alpha
    return R::success(ch);
}

}  // namespace wavecam
