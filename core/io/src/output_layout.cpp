#include "wavecam/output_layout.h"

#include <OpenImageIO/strutil.h>

#include "wavecam/atomic_write.h"

#include <algorithm>
#include <cmath>

namespace wavecam {
namespace Strutil = OIIO::Strutil;

bool is_stale_camera_attribute(const std::string& name) {
    if (Strutil::istarts_with(name, "wavecam."))  // the depth channel is copied: its unit stays true
        return !Strutil::iequals(name, "wavecam.scene") && !Strutil::iequals(name, kSceneUnitAttribute);
    if (Strutil::istarts_with(name, "cycles.") || Strutil::iequals(name, "oiio:subimages")) return true;
    // a texture's MIP and lookup description and its pixels' statistics (oiiotool -otex, maketx)
    for (const char* texture : {"textureformat", "wrapmodes", "fovcot", "uvslopes_scale", "openexr:levelmode",
                                "openexr:roundingmode", "oiio:AverageColor", "oiio:ConstantColor", "oiio:SHA-1"})
        if (Strutil::iequals(name, texture)) return true;
    // lens and camera geometry under any naming: Blender's Lens, EXIF's FocalLength/FNumber/
    // LensModel/ApertureValue/SubjectDistance, OpenEXR's focus/aperture/worldToCamera/worldToNDC
    for (const char* part : {"lens", "focal", "aperture", "fnumber", "focus", "subjectdistance", "worldto"})
        if (Strutil::icontains(name, part)) return true;
    return false;
}

namespace {

bool is_diffracted(const RenderChannels& ch, int c) { return c == ch.r || c == ch.g || c == ch.b || c == ch.alpha; }

// The input channels the output holds, in the input's order.
std::vector<int> kept_channels(const OIIO::ImageSpec& input, const RenderChannels& ch, bool other_channels) {
    std::vector<int> kept;
    for (int c = 0; c < input.nchannels; ++c)
        if (other_channels || is_diffracted(ch, c) || c == ch.depth) kept.push_back(c);
    return kept;
}

}  // namespace

OIIO::ImageSpec output_header(const OIIO::ImageSpec& input, const RenderChannels& ch, bool other_channels) {
    OIIO::ImageSpec spec = input;
    spec.extra_attribs.clear();
    for (const OIIO::ParamValue& p : input.extra_attribs) {
        const std::string name = p.name().string();
        // Cryptomatte's manifest describes its channels: stale once they are dropped
        if (is_stale_camera_attribute(name) || (!other_channels && Strutil::istarts_with(name, "cryptomatte/"))) continue;
        spec.extra_attribs.push_back(p);
    }
    spec.channelnames.clear();
    spec.alpha_channel = spec.z_channel = -1;
    std::string diffracted;
    for (int c : kept_channels(input, ch, other_channels)) {
        if (c == ch.alpha) spec.alpha_channel = int(spec.channelnames.size());
        if (c == ch.depth) spec.z_channel = int(spec.channelnames.size());
        if (is_diffracted(ch, c)) diffracted += (diffracted.empty() ? "" : ",") + input.channelnames[c];
        spec.channelnames.push_back(input.channelnames[c]);
    }
    spec.nchannels = int(spec.channelnames.size());
    spec.set_format(OIIO::TypeDesc::FLOAT);  // in memory; the file's types: file_channel_formats
    spec.channelformats.clear();
    // level 0 alone, as scanlines: a MIP-mapped or tiled input's other levels are not remade
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    spec.attribute(kDiffractedChannelsAttribute, diffracted);
    return spec;
}

std::vector<OIIO::TypeDesc> file_channel_formats(const OIIO::ImageSpec& input, const OIIO::ImageSpec& output,
                                                 OIIO::TypeDesc diffracted_type) {
    const std::vector<std::string> diffracted =
        Strutil::splits(output.get_string_attribute(kDiffractedChannelsAttribute), ",");
    std::vector<OIIO::TypeDesc> formats;
    for (const std::string& name : output.channelnames) {
        const int c = input.channelindex(name);
        OIIO::TypeDesc t = c < 0 ? OIIO::TypeDesc::FLOAT : input.channelformat(c);
        if (diffracted_type != OIIO::TypeUnknown && std::find(diffracted.begin(), diffracted.end(), name) != diffracted.end())
            t = diffracted_type;
        formats.push_back(t);
    }
    return formats;
}

Result<bool> fill_output(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const RenderChannels& ch, int margin,
                         const float* rgb, const float* alpha) {
    // each channel written once, straight into dst: R, G, B from `rgb`, alpha from `alpha`, every
    // other kept channel from the same pixels of the source, inside its overscan margin
    const OIIO::ImageSpec& spec = dst.spec();
    const OIIO::ImageSpec& in = src.spec();
    const OIIO::stride_t pixel = spec.nchannels * sizeof(float), row = pixel * spec.width;
    const size_t n = size_t(spec.width) * spec.height;
    for (int to = 0; to < spec.nchannels; ++to) {
        const int from = in.channelindex(spec.channelnames[to]);
        float* at = static_cast<float*>(dst.pixeladdr(spec.x, spec.y, 0, to));
        if (from == ch.r || from == ch.g || from == ch.b) {
            const int k = from == ch.r ? 0 : from == ch.g ? 1 : 2;
            for (size_t p = 0; p < n; ++p) at[p * spec.nchannels] = rgb[3 * p + k];
        } else if (from == ch.alpha) {
            for (size_t p = 0; p < n; ++p) at[p * spec.nchannels] = alpha[p];
        } else {
            const OIIO::ROI region(in.x + margin, in.x + margin + spec.width, in.y + margin, in.y + margin + spec.height,
                                   0, 1, from, from + 1);
            if (!src.get_pixels(region, OIIO::TypeDesc::FLOAT, at, pixel, row))
                return Result<bool>::failure("cannot read channel '" + in.channelnames[from] + "': " + src.geterror());
        }
    }
    return Result<bool>::success(true);
}

namespace {

// The values of `image`'s half channels beyond half's range: how many, the largest, and where.
struct HalfExcess {
    size_t count = 0;
    float largest = 0;
    int x = 0, y = 0, channel = -1;
};

HalfExcess half_excess(const OIIO::ImageBuf& image, const std::vector<OIIO::TypeDesc>& formats) {
    HalfExcess e;
    const OIIO::ImageSpec& spec = image.spec();
    for (int c = 0; c < spec.nchannels; ++c) {
        if (formats[c] != OIIO::TypeDesc::HALF) continue;
        for (int y = spec.y; y < spec.y + spec.height; ++y)
            for (int x = spec.x; x < spec.x + spec.width; ++x) {
                const float v = *static_cast<const float*>(image.pixeladdr(x, y, 0, c));
                if (!(std::fabs(v) > kHalfMax) || !std::isfinite(v)) continue;
                ++e.count;
                if (std::fabs(v) > std::fabs(e.largest)) e = {e.count, v, x, y, c};
            }
    }
    return e;
}

}  // namespace

Result<std::string> write_plate(const OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& path,
                                OIIO::TypeDesc diffracted_type, HalfOverflow overflow, double max_bytes) {
    using R = Result<std::string>;
    std::vector<OIIO::ImageBuf> others;  // the other parts, as the file has them
    std::vector<PartToWrite> parts;
    const int chosen = src.subimage(), count = std::max(1, src.nsubimages());
    others.reserve(count + 1);
    std::string done;
    for (int s = 0; s < count; ++s) {
        if (s == chosen) {
            std::vector<OIIO::TypeDesc> formats = file_channel_formats(src.nativespec(), dst.spec(), diffracted_type);
            const HalfExcess e = half_excess(dst, formats);
            if (e.count == 0) {
                parts.push_back({&dst, formats});
                continue;
            }
            const std::string what = std::to_string(e.count) + " values beyond half's range of 65504 (the largest " +
                                     Strutil::fmt::format("{:g}", e.largest) + " in channel '" +
                                     dst.spec().channelnames[e.channel] + "' at pixel (" + std::to_string(e.x) + ", " +
                                     std::to_string(e.y) + "))";
            if (overflow == HalfOverflow::Refuse)
                return R::failure(path + ": " + what + ", which half would write as inf; nothing written. Expected "
                                  "values within half's range: write float (--pixel-type float, or the half-overflow "
                                  "setting float) or clamp them (half-overflow clamp)",
                                  ErrorKind::Invalid, "half-overflow");
            OIIO::ImageBuf fitted;
            fitted.copy(dst);
            if (overflow == HalfOverflow::Float) {
                done = what + ": the diffracted channels written as float (half-overflow float)";
                const std::vector<std::string> diffracted =
                    Strutil::splits(dst.spec().get_string_attribute(kDiffractedChannelsAttribute), ",");
                for (int c = 0; c < dst.nchannels(); ++c)
                    if (std::find(diffracted.begin(), diffracted.end(), dst.spec().channelnames[c]) != diffracted.end())
                        formats[c] = OIIO::TypeDesc::FLOAT;
            } else {
                done = what + ": clamped to +-65504 (half-overflow clamp)";
                for (int c = 0; c < fitted.nchannels(); ++c)
                    if (formats[c] == OIIO::TypeDesc::HALF)
                        for (OIIO::ImageBuf::Iterator<float> it(fitted); !it.done(); ++it)
                            if (std::isfinite(it[c])) it[c] = std::clamp(float(it[c]), -kHalfMax, kHalfMax);
            }
            fitted.specmod().attribute("wavecam.half-overflow-written", done);
            others.push_back(std::move(fitted));
            parts.push_back({&others.back(), formats});
            continue;
        }
        auto part = read_image(src.name(), max_bytes, s);
        if (!part.ok()) return R::failure(part);
        others.push_back(std::move(part.value));
        // OpenEXR holds one chromaticities per file (a shared attribute): the diffracted part's
        OIIO::ImageSpec& spec = others.back().specmod();
        if (const OIIO::ParamValue* c = dst.spec().find_attribute("chromaticities")) spec.attribute(c->name(), c->type(), c->data());
        else spec.erase_attribute("chromaticities");
        const OIIO::ImageSpec& native = others.back().nativespec();
        std::vector<OIIO::TypeDesc> formats;
        for (int c = 0; c < native.nchannels; ++c) formats.push_back(native.channelformat(c));
        parts.push_back({&others.back(), formats});
    }
    if (auto w = write_parts_atomically(parts, path); !w.ok()) return R::failure(w);
    return R::success(done);
}

}  // namespace wavecam
