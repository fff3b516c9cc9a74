#include "render_windows.h"

#include "wavecam/edge_continuation.h"

#include <algorithm>
#include <cmath>

namespace wavecam::detail {
namespace {

// One axis: the frame [begin, begin + size) centred on the display [d0, d0 + dn) and holding it
// and the data [x0, x0 + n). In half pixels the centre is 2 d0 + dn, so the frame's size is
// max(dn, centre - 2 x0, 2 (x0 + n) - centre): a whole number of the display size's parity, and
// its first pixel whole.
void frame_axis(int d0, int dn, int x0, int n, int& begin, int& size) {
    const long centre2 = 2L * d0 + dn;
    size = int(std::max({long(dn), centre2 - 2L * x0, 2L * (x0 + n) - centre2}));
    begin = int((centre2 - size) / 2);
}

std::string window_text(const OIIO::ROI& r) {
    return "(" + std::to_string(r.xbegin) + ", " + std::to_string(r.ybegin) + ")-(" + std::to_string(r.xend - 1) +
           ", " + std::to_string(r.yend - 1) + ")";
}

}  // namespace

Result<bool> place_on_frame(const OIIO::ImageSpec& spec, RenderInput& in) {
    FrameWindows& w = in.windows;
    w.data = OIIO::ROI(spec.x, spec.x + spec.width, spec.y, spec.y + spec.height);
    w.display = spec.full_width > 0 && spec.full_height > 0
                    ? OIIO::ROI(spec.full_x, spec.full_x + spec.full_width, spec.full_y, spec.full_y + spec.full_height)
                    : w.data;
    w.declared = w.data != w.display;
    in.display_fov_h = in.fov_h;
    in.x0 = spec.x;
    in.y0 = spec.y;
    in.width = spec.width;
    in.height = spec.height;
    if (!w.declared) return Result<bool>::success(true);

    int fx, fw, fy, fh;
    frame_axis(w.display.xbegin, w.display.width(), spec.x, spec.width, fx, fw);
    frame_axis(w.display.ybegin, w.display.height(), spec.y, spec.height, fy, fh);
    const double frame = double(fw) * fh;
    if (frame > 4 * std::max(double(w.data.npixels()), double(w.display.npixels())))
        return Result<bool>::failure(
            "data window " + window_text(w.data) + " lies far from the display window " + window_text(w.display) +
            ": the frame about the display window's centre (the optical axis) that holds it would be " +
            std::to_string(fw) + "x" + std::to_string(fh) +
            " pixels; expected a data window in or around the display window (a crop, or an overscan margin)");
    // the same pixel pitch, 2 tan(fov / 2) / width, across the wider frame
    in.fov_h = 2 * std::atan(std::tan(0.5 * in.display_fov_h) * fw / w.display.width());

    const int dw = spec.width, dh = spec.height, ox = spec.x - fx, oy = spec.y - fy;
    std::vector<float> rgb(3 * size_t(fw) * fh), depth(size_t(fw) * fh), alpha(in.alpha.empty() ? 0 : depth.size());
    const EdgeContinuation edge(in.rgb.data(), 3, dw, dh);  // a lone bright edge pixel is not copied beyond
    for (int j = 0; j < fh; ++j)
        for (int i = 0; i < fw; ++i) {
            const size_t from = size_t(std::clamp(j - oy, 0, dh - 1)) * dw + std::clamp(i - ox, 0, dw - 1);
            const size_t to = size_t(j) * fw + i;
            const float* light = edge.light(i - ox, j - oy);
            std::copy(light, light + 3, &rgb[3 * to]);
            depth[to] = in.depth[from];
            if (!alpha.empty()) alpha[to] = in.alpha[from];
        }
    in.rgb = std::move(rgb);
    in.depth = std::move(depth);
    in.alpha = std::move(alpha);
    in.x0 = fx;
    in.y0 = fy;
    in.width = fw;
    in.height = fh;
    return Result<bool>::success(true);
}

}  // namespace wavecam::detail
