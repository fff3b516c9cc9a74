#include "pixel_aspect.h"

#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "wavecam/output_layout.h"

namespace wavecam::detail {
namespace {

// One row of `from.size()` pixels resampled by area to `to.size()`: pixel k of the new row
// covers [k n / m, (k + 1) n / m) of the old, and is the mean of the old pixels over that span.
void resample_row(const float* from, size_t n, float* to, size_t m, size_t stride) {
    const double width = double(n) / m;
    for (size_t k = 0; k < m; ++k) {
        const double a = k * width, b = (k + 1) * width;
        double sum = 0;
        for (size_t i = size_t(a); i < n && i < b; ++i)
            sum += from[i * stride] * (std::min(b, double(i + 1)) - std::max(a, double(i)));
        to[k * stride] = float(sum / width);
    }
}

// Every channel of `image` as floats, pixel-interleaved.
std::vector<float> pixels_of(const OIIO::ImageBuf& image) {
    const OIIO::ImageSpec& s = image.spec();
    std::vector<float> px(size_t(s.width) * s.height * s.nchannels);
    image.get_pixels(image.roi(), OIIO::TypeDesc::FLOAT, px.data());
    return px;
}

// `pixels` (width w, same height and channels as `like`) resampled to `like` with width `m`:
// channels with `by_area` set by area, the others from the old pixel under each new centre.
OIIO::ImageBuf resampled(const OIIO::ImageSpec& like, const std::vector<float>& pixels, int w, int m,
                         const std::vector<bool>& by_area) {
    OIIO::ImageSpec spec = like;
    spec.width = spec.full_width = m;
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    const int nc = spec.nchannels, h = spec.height;
    std::vector<float> out(size_t(m) * h * nc);
    for (int j = 0; j < h; ++j)
        for (int c = 0; c < nc; ++c) {
            const float* row = &pixels[(size_t(j) * w) * nc + c];
            float* dst = &out[(size_t(j) * m) * nc + c];
            if (by_area[c]) resample_row(row, size_t(w), dst, size_t(m), size_t(nc));
            else
                for (int k = 0; k < m; ++k) dst[size_t(k) * nc] = row[size_t(std::min(w - 1, int((k + 0.5) * w / m))) * nc];
        }
    OIIO::ImageBuf buf(spec);
    buf.set_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, out.data());
    return buf;
}

}  // namespace

double pixel_aspect(const OIIO::ImageSpec& spec) {
    const float a = spec.get_float_attribute("PixelAspectRatio", 1.0f);
    return a > 0 && std::isfinite(a) ? a : 1.0;
}

Result<OIIO::ImageBuf> to_square_pixels(const OIIO::ImageBuf& src, const RenderChannels& ch, double aspect) {
    const OIIO::ImageSpec& s = src.spec();
    if (s.x != s.full_x || s.y != s.full_y || s.width != s.full_width || s.height != s.full_height)
        return Result<OIIO::ImageBuf>::failure(
            "pixel aspect ratio " + OIIO::Strutil::fmt::format("{:g}", aspect) +
            " with a data window other than the display window: expected square pixels (PixelAspectRatio 1) "
            "for a cropped or overscanned frame, or the whole frame");
    std::vector<bool> by_area(s.nchannels, false);
    for (int c : {ch.r, ch.g, ch.b, ch.alpha})
        if (c >= 0) by_area[c] = true;
    const int m = std::max(2, int(std::lround(s.width * aspect)));
    OIIO::ImageBuf square = resampled(s, pixels_of(src), s.width, m, by_area);
    square.specmod().attribute("PixelAspectRatio", 1.0f);
    return Result<OIIO::ImageBuf>::success(std::move(square));
}

Result<OIIO::ImageBuf> to_file_pixels(const OIIO::ImageBuf& square, const OIIO::ImageBuf& src, double aspect) {
    const OIIO::ImageSpec& s = square.spec();
    const std::vector<std::string> diffracted =
        OIIO::Strutil::splits(s.get_string_attribute(kDiffractedChannelsAttribute), ",");
    std::vector<bool> by_area(s.nchannels, false);
    for (int c = 0; c < s.nchannels; ++c)
        by_area[c] = std::find(diffracted.begin(), diffracted.end(), s.channelnames[c]) != diffracted.end();
    OIIO::ImageBuf out = resampled(s, pixels_of(square), s.width, src.spec().width, by_area);
    out.specmod().x = out.specmod().full_x = src.spec().x;
    out.specmod().attribute("PixelAspectRatio", float(aspect));
    // every channel wavecam did not diffract is the input's own, untouched by the stretch
    for (int c = 0; c < s.nchannels; ++c) {
        const int from = src.spec().channelindex(s.channelnames[c]);
        if (by_area[c] || from < 0) continue;
        std::vector<float> channel(size_t(src.spec().width) * src.spec().height);
        OIIO::ROI in = src.roi(), to = out.roi();
        in.chbegin = from, in.chend = from + 1, to.chbegin = c, to.chend = c + 1;
        if (!src.get_pixels(in, OIIO::TypeDesc::FLOAT, channel.data()) ||
            !out.set_pixels(to, OIIO::TypeDesc::FLOAT, channel.data()))
            return Result<OIIO::ImageBuf>::failure("cannot copy channel '" + s.channelnames[c] + "'");
    }
    return Result<OIIO::ImageBuf>::success(std::move(out));
}

}  // namespace wavecam::detail
