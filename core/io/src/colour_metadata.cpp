#include "colour_metadata.h"

#include <OpenImageIO/strutil.h>

#include <cmath>

namespace wavecam::detail {
namespace {

// Primaries and white (x, y of red, green, blue, white), as OpenEXR's chromaticities attribute
// holds them, of the linear spaces wavecam's config defines. Rec. 709: ITU-R BT.709; AP1 and
// AP0 with the ACES white: SMPTE ST 2065-1 and the ACEScg specification (S-2014-004); CIE XYZ:
// unit primaries, equal-energy white (RGB 1, 1, 1 is X = Y = Z = 1).
struct KnownSpace {
    const char* name;
    float xy[8];
};
constexpr KnownSpace kKnownSpaces[] = {
    {"lin_rec709", {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f}},
    {"ACEScg", {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f}},
    {"ACES2065-1", {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.0770f, 0.32168f, 0.33767f}},
    {"CIE-XYZ-D65", {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f / 3, 1.0f / 3}},
};
constexpr float kTolerance = 0.002f;

const KnownSpace* known(const std::string& canonical) {
    for (const KnownSpace& k : kKnownSpaces)
        if (canonical == k.name) return &k;
    return nullptr;
}

}  // namespace

Result<std::string> header_colour_space(const FileColour& file, const ColourConfig& config) {
    using R = Result<std::string>;
    if (file.chromaticities.size() == 8) {
        for (const KnownSpace& k : kKnownSpaces) {
            bool same = true;
            for (int i = 0; i < 8; ++i) same = same && std::fabs(file.chromaticities[i] - k.xy[i]) <= kTolerance;
            if (same && config.has_colorspace(k.name)) return R::success(config.canonical_name(k.name));
        }
        std::string xy;
        for (float v : file.chromaticities) xy += (xy.empty() ? "" : ", ") + OIIO::Strutil::fmt::format("{:g}", v);
        std::string names;
        for (const KnownSpace& k : kKnownSpaces) names += (names.empty() ? "" : ", ") + std::string(k.name);
        return R::failure("chromaticities (" + xy + ") are the primaries and white of no colour space wavecam knows (" +
                              names + "); expected one of them, or the input-colorspace setting naming the file's space",
                          ErrorKind::Invalid, "input-colorspace");
    }
    if (file.aces_container && config.has_colorspace("ACES2065-1"))
        return R::success(config.canonical_name("ACES2065-1"));
    return R::success(std::string());
}

void write_colour_attributes(OIIO::ImageSpec& spec, const std::string& space, const ColourConfig& config) {
    const std::string canonical = config.canonical_name(space);
    spec.attribute("oiio:ColorSpace", canonical.empty() ? space : canonical);
    if (const KnownSpace* k = known(canonical))
        spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), k->xy);
    else
        spec.erase_attribute("chromaticities");
    if (canonical == "ACES2065-1") spec.attribute("acesImageContainerFlag", 1);
    else spec.erase_attribute("acesImageContainerFlag");
}

}  // namespace wavecam::detail
