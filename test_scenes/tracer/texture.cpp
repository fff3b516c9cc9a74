#include "texture.h"
#include <cmath>
#include "bitmap_font.h"

namespace wavecam::trace {

namespace {
double checker(double u, double v, int count) {
    const long s = static_cast<long>(std::floor(u * count)) + static_cast<long>(std::floor(v * count));
    return (s & 1) ? 1.0 : 0.0;
}

// Three bars of width p/2 at period p, starting at `start` along `along`.
bool three_bars(double along, double start, double period) {
    const double x = (along - start) / period;
    return x >= 0 && x < 2.5 && x - std::floor(x) < 0.5;
}

double bars(double u, double v, int count) {
    if (u < 0 || u >= 1 || v < 0 || v >= 1) return 0;
    const int k = static_cast<int>(u * count);
    const double a = u * count - k;  // across the element, 0..1
    const double period = 0.16 * std::pow(2.0, -0.5 * k);
    const double extent = 2.5 * period;  // three bars and two gaps
    if (v >= 0.5) {  // vertical bars (resolve detail along u), 0.4 tall
        const bool in_band = v >= 0.55 && v < 0.95;
        return in_band && three_bars(a, 0.5 - extent / 2, period) ? 1 : 0;
    }
    const bool in_band = a >= 0.3 && a < 0.7;  // horizontal bars, 0.4 wide
    return in_band && three_bars(v, 0.25 - extent / 2, period) ? 1 : 0;
}

double siemens_star(double u, double v, int spokes) {
    const double x = u - 0.5, y = v - 0.5;
    if (x * x + y * y > 0.25) return 0;
    return std::sin(spokes * std::atan2(y, x)) > 0 ? 1 : 0;
}

// Cells of 6 x 9 font pixels: the glyph's 5 x 7 with a column and a row above and below.
double text(double u, double v, const std::string& s) {
    if (s.empty() || u < 0 || u >= 1 || v < 0 || v >= 1) return 0;
    const double cells = u * static_cast<double>(s.size());
    const auto cell = static_cast<std::size_t>(cells);
    const int column = static_cast<int>((cells - cell) * 6);
    const int row = static_cast<int>((1 - v) * 9) - 1;  // row 0 at the top
    return glyph_pixel(s[cell], column, row) ? 1 : 0;
}
}  // namespace

double ink_coverage(const Texture& t, double u, double v) {
    switch (t.kind) {
        case TextureKind::None: return 0;
        case TextureKind::Checker: return checker(u, v, t.count);
        case TextureKind::Bars: return bars(u, v, t.count);
        case TextureKind::SiemensStar: return siemens_star(u, v, t.count);
        case TextureKind::Text: return text(u, v, t.text);
    }
    return 0;
}

Vec3 textured_albedo(Vec3 albedo, const Texture& texture, double u, double v) {
    const double c = ink_coverage(texture, u, v);
    return albedo * (1 - c) + texture.ink * c;
}

}  // namespace wavecam::trace
