#include "wavecam/output_layout.h"

#include <OpenImageIO/strutil.h>

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

OIIO::ImageSpec output_header(const OIIO::ImageSpec& input, const RenderChannels& ch) {
    OIIO::ImageSpec spec = input;
    spec.extra_attribs.clear();
    for (const OIIO::ParamValue& p : input.extra_attribs)
        if (!is_stale_camera_attribute(p.name().string())) spec.extra_attribs.push_back(p);
    spec.channelnames = {input.channelnames[ch.r], input.channelnames[ch.g], input.channelnames[ch.b]};
    spec.alpha_channel = -1;
    if (ch.alpha >= 0) {
        spec.alpha_channel = 3;
        spec.channelnames.push_back(input.channelnames[ch.alpha]);
    }
    spec.z_channel = int(spec.channelnames.size());
    spec.channelnames.push_back(input.channelnames[ch.depth]);
    spec.nchannels = int(spec.channelnames.size());
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    // level 0 alone, as scanlines: a MIP-mapped or tiled input's other levels are not remade
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    return spec;
}

Result<bool> fill_output(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const RenderChannels& ch, int margin,
                         const float* rgb) {
    // each channel written once, straight into dst: R, G, B from `rgb`, then alpha and depth
    // from the same pixels of the source, inside its overscan margin
    const OIIO::ImageSpec& spec = dst.spec();
    const OIIO::stride_t pixel = spec.nchannels * sizeof(float), row = pixel * spec.width;
    if (!dst.set_pixels(OIIO::ROI(spec.x, spec.x + spec.width, spec.y, spec.y + spec.height, 0, 1, 0, 3),
                        OIIO::TypeDesc::FLOAT, rgb))
        return Result<bool>::failure("cannot fill the output image: " + dst.geterror());
    const OIIO::ImageSpec& in = src.spec();
    int to = 3;
    for (int from : {ch.alpha, ch.depth}) {
        if (from < 0) continue;
        const OIIO::ROI region(in.x + margin, in.x + margin + spec.width, in.y + margin, in.y + margin + spec.height,
                               0, 1, from, from + 1);
        if (!src.get_pixels(region, OIIO::TypeDesc::FLOAT, dst.pixeladdr(spec.x, spec.y, 0, to++), pixel, row))
            return Result<bool>::failure("cannot read the alpha and depth channels: " + src.geterror());
    }
    return Result<bool>::success(true);
}

}  // namespace wavecam
