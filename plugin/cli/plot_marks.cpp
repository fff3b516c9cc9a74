#include "plot_marks.h"

#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <cstdio>

namespace wavecam::cli {
namespace {
constexpr const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
}

void draw_text(OIIO::ImageBuf& img, int x, int y, const std::string& s, const TextStyle& style) {
    const int size = style.size;
    const Colour& colour = style.colour;
    const Align align = style.align;
    using OIIO::ImageBufAlgo::TextAlignX;
    const TextAlignX a = align == Align::Left ? TextAlignX::Left : align == Align::Centre ? TextAlignX::Center
                                                                                           : TextAlignX::Right;
    const int n = img.nchannels();
    const float c[3] = {colour[0], colour[1], colour[2]};
    const float grey = (colour[0] + colour[1] + colour[2]) / 3;  // one-channel pictures
    OIIO::ImageBufAlgo::render_text(img, x, y, s, size, kFont, n >= 3 ? OIIO::cspan<float>(c, 3) : OIIO::cspan<float>(&grey, 1), a);
}

int text_width(const std::string& s, int size) {
    const OIIO::ROI r = OIIO::ImageBufAlgo::text_size(s, size, kFont);
    return r.defined() ? r.width() : 0;
}

double nice_below(double limit) {
    const double decade = std::pow(10.0, std::floor(std::log10(limit)));
    for (double step : {5.0, 2.0, 1.0})
        if (step * decade <= limit * (1 + 1e-9)) return step * decade;
    return decade;
}

void draw_scale_bar(OIIO::ImageBuf& img, int x, int y, double pitch, int max_pixels, const Colour& colour) {
    const double um = nice_below(max_pixels * pitch * 1e6);
    const int length = std::max(1, int(std::lround(um * 1e-6 / pitch)));
    const int n = img.nchannels();
    const float grey = (colour[0] + colour[1] + colour[2]) / 3;
    const OIIO::cspan<float> c = n >= 3 ? OIIO::cspan<float>(colour.data(), 3) : OIIO::cspan<float>(&grey, 1);
    OIIO::ImageBufAlgo::render_box(img, x, y - 1, x + length - 1, y + 1, c, true);
    OIIO::ImageBufAlgo::render_line(img, x, y - 5, x, y + 1, c);
    OIIO::ImageBufAlgo::render_line(img, x + length - 1, y - 5, x + length - 1, y + 1, c);
    draw_text(img, x, y - 7, tick_label(um) + " um", {12, colour});
}

std::vector<Tick> log_ticks(double lo, double hi) {
    std::vector<Tick> ticks;
    const bool narrow = hi / lo < 3, short_range = hi / lo < 12;
    for (int e = int(std::floor(std::log10(lo))); e <= int(std::ceil(std::log10(hi))); ++e)
        for (int m = 1; m <= 9; ++m) {
            const double v = m * std::pow(10.0, e);
            if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) ticks.push_back({v, narrow || m == 1 || m == 2 || m == 5 ||
                                         (short_range && (m == 3 || m == 4 || m == 6 || m == 8))});
        }
    return ticks;
}

std::string tick_label(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", value);
    return text;
}

}  // namespace wavecam::cli
