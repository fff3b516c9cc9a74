#include "wavecam/output_layout.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cctype>
#include <vector>

namespace wavecam {

bool is_stale_camera_attribute(const std::string& name) {
    std::string n = name;
    std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    auto starts = [&n](const char* p) { return n.rfind(p, 0) == 0; };
    if (starts("wavecam.")) return n != "wavecam.scene";
    if (starts("cycles.") || n == "oiio:subimages") return true;
    // lens and camera geometry under any naming: Blender's Lens, EXIF's FocalLength/FNumber/
    // LensModel/ApertureValue/SubjectDistance, OpenEXR's focus/aperture/worldToCamera/worldToNDC
    for (const char* part : {"lens", "focal", "aperture", "fnumber", "focus", "subjectdistance", "worldto"})
        if (n.find(part) != std::string::npos) return true;
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
    return spec;
}

Result<bool> fill_output(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const RenderChannels& ch, int margin,
                         const float* rgb) {
    const OIIO::ImageSpec& spec = dst.spec();
    const size_t n = size_t(spec.width) * spec.height;
    const int nc = spec.nchannels;
    // alpha and depth from the source, in the output's channel order
    std::vector<int> passed = {ch.depth};
    if (ch.alpha >= 0) passed.insert(passed.begin(), ch.alpha);
    const int np = int(passed.size());
    std::vector<float> kept(n * np);
    const OIIO::ImageBuf src_kept = OIIO::ImageBufAlgo::channels(src, np, passed);
    // the output's pixels in the source: inside its overscan margin
    const OIIO::ImageSpec& in = src.spec();
    const OIIO::ROI region(in.x + margin, in.x + margin + spec.width, in.y + margin, in.y + margin + spec.height, 0, 1,
                           0, np);
    if (!src_kept.get_pixels(region, OIIO::TypeDesc::FLOAT, kept.data()))
        return Result<bool>::failure("cannot read the alpha and depth channels: " + src_kept.geterror());
    std::vector<float> out(n * nc);
    for (size_t p = 0; p < n; ++p) {
        for (int k = 0; k < 3; ++k) out[nc * p + k] = rgb[3 * p + k];
        for (int k = 0; k < np; ++k) out[nc * p + 3 + k] = kept[np * p + k];
    }
    if (!dst.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, out.data()))
        return Result<bool>::failure("cannot fill the output image: " + dst.geterror());
    return Result<bool>::success(true);
}

}  // namespace wavecam
