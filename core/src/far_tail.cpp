#include "far_tail.h"

#include <algorithm>
#include <cmath>

namespace wavecam::detail {

namespace {

// The annulus R <= r <= reach with intensity ~ 1/r^3, integrated over cells of `cell` pixels,
// holding 1 - R / reach (the share of a 1/r tail beyond R that lies within reach); (2 half + 1)^2 cells.
std::vector<double> tail_kernel(int radius, int reach, int cell, int half) {
    const int w = 2 * half + 1, sub = 6;
    std::vector<double> k(size_t(w) * w, 0.0);
    double total = 0;
    for (int b = -half; b <= half; ++b)
        for (int a = -half; a <= half; ++a) {
            double s = 0;
            for (int sb = 0; sb < sub; ++sb)
                for (int sa = 0; sa < sub; ++sa) {
                    const double r = std::hypot((a + (sa + 0.5) / sub - 0.5) * cell, (b + (sb + 0.5) / sub - 0.5) * cell);
                    if (r >= radius && r <= reach) s += 1.0 / (r * r * r);
                }
            k[size_t(b + half) * w + (a + half)] = s;
            total += s;
        }
    for (double& x : k) x *= (1.0 - double(radius) / reach) / total;
    return k;
}

}  // namespace

void add_far_tail(const PsfTable& t, const SpectralScene& scene, int origin, int out_x0, int out_y0, int out_w,
                  int out_h, float* xyz, int nthreads) {
    const int R = t.radius, reach = kTailReach * R;
    if (R < 2 || t.deficit.empty()) return;
    const PinholeCamera& c = scene.camera;
    const int cell = std::max(1, R / 3), half = reach / cell + 1, L = t.layers.count;
    // the coarse grid covers the output widened by the tail's reach
    const int x0 = out_x0 - reach, y0 = out_y0 - reach;  // domain coordinates of coarse cell (0, 0)
    const int cw = (out_w + 2 * reach + cell - 1) / cell, ch = (out_h + 2 * reach + cell - 1) / cell;
    const int nkx = int(t.ax.knots.size()), anchors = t.anchors();
    std::vector<float> missing(3 * size_t(cw) * ch, 0.0f);
#pragma omp parallel num_threads(nthreads)
    {
        std::vector<double> light(size_t(L) * 3);  // a cell's light per layer and primary
#pragma omp for
        for (int J = 0; J < ch; ++J)
            for (int I = 0; I < cw; ++I) {
                std::fill(light.begin(), light.end(), 0.0);
                for (int y = y0 + J * cell; y < y0 + (J + 1) * cell; ++y)
                    for (int x = x0 + I * cell; x < x0 + (I + 1) * cell; ++x) {
                        // the source: the input where it reaches, its edge continued beyond
                        const int ci = std::clamp(x - origin, 0, c.width - 1);
                        const int cj = std::clamp(y - origin, 0, c.height - 1);
                        const size_t q = size_t(cj) * c.width + ci;
                        const double d = scene.depth[q];
                        const double w =
                            d >= kInfiniteDepth ? 0.0 : 1.0 / c.planar_depth(ci, cj, d, scene.depth_meaning);
                        int lower = 0;
                        float upper = 0;
                        t.layers.locate(w, lower, upper);
                        double u, v;
                        c.tangent(x - origin + 0.5, y - origin + 0.5, u, v);
                        const double c4 = std::pow(1.0 / (1.0 + u * u + v * v), 2);
                        for (int p = 0; p < 3; ++p) {
                            light[size_t(lower) * 3 + p] += (1.0 - upper) * c4 * scene.rgb[3 * q + p];
                            if (upper > 0) light[size_t(lower + 1) * 3 + p] += upper * c4 * scene.rgb[3 * q + p];
                        }
                    }
                // the kernels' missing shares at the cell's centre, interpolated as the kernels are
                const int kx = std::clamp(x0 + I * cell + cell / 2, 0, t.ax.knots.back() - 1);
                const int ky = std::clamp(y0 + J * cell + cell / 2, 0, t.ay.knots.back() - 1);
                const int cx = t.ax.cell_of(kx), cy = t.ay.cell_of(ky);
                const double bx = t.ax.upper_weight(cx, kx), by = t.ay.upper_weight(cy, ky);
                float* m = &missing[3 * (size_t(J) * cw + I)];
                for (int corner = 0; corner < 4; ++corner) {
                    const int dx = corner & 1, dy = corner >> 1;
                    const double phi = (dx ? bx : 1 - bx) * (dy ? by : 1 - by);
                    if (phi == 0) continue;
                    const int a = (cy + dy) * nkx + (cx + dx);
                    for (int l = 0; l < L; ++l) {
                        const float* def = &t.deficit[(size_t(l) * anchors + a) * 9];
                        for (int p = 0; p < 3; ++p)
                            for (int k = 0; k < 3; ++k) m[k] += float(phi * light[size_t(l) * 3 + p] * def[3 * p + k]);
                    }
                }
            }
    }
    // spread over the annulus (a direct sum: the coarse kernel is small), only where the output is
    const std::vector<double> k = tail_kernel(R, reach, cell, half);
    const int kw = 2 * half + 1;
    const int I0 = std::max(0, reach / cell - 1), I1 = std::min(cw, (reach + out_w) / cell + 2);
    const int J0 = std::max(0, reach / cell - 1), J1 = std::min(ch, (reach + out_h) / cell + 2);
    std::vector<float> spread(3 * size_t(cw) * ch, 0.0f);
#pragma omp parallel for num_threads(nthreads)
    for (int J = J0; J < J1; ++J)
        for (int I = I0; I < I1; ++I) {
            double acc[3] = {0, 0, 0};
            for (int b = -half; b <= half; ++b) {
                const int sj = J - b;
                if (sj < 0 || sj >= ch) continue;
                for (int a = -half; a <= half; ++a) {
                    const int si = I - a;
                    if (si < 0 || si >= cw) continue;
                    const double kk = k[size_t(b + half) * kw + (a + half)];
                    for (int q = 0; q < 3; ++q) acc[q] += kk * missing[3 * (size_t(sj) * cw + si) + q];
                }
            }
            for (int q = 0; q < 3; ++q) spread[3 * (size_t(J) * cw + I) + q] = float(acc[q]);
        }
    // back to pixels: each coarse cell's light over its cell x cell pixels, bilinearly
    const float per_pixel = 1.0f / float(cell * cell);
#pragma omp parallel for num_threads(nthreads)
    for (int j = 0; j < out_h; ++j) {
        const double fy = (j + reach + 0.5) / cell - 0.5;
        const int J = std::clamp(int(std::floor(fy)), 0, ch - 2);
        const double ty = std::clamp(fy - J, 0.0, 1.0);
        for (int i = 0; i < out_w; ++i) {
            const double fx = (i + reach + 0.5) / cell - 0.5;
            const int I = std::clamp(int(std::floor(fx)), 0, cw - 2);
            const double tx = std::clamp(fx - I, 0.0, 1.0);
            for (int q = 0; q < 3; ++q) {
                auto s = [&](int ii, int jj) { return double(spread[3 * (size_t(jj) * cw + ii) + q]); };
                const double v = (1 - ty) * ((1 - tx) * s(I, J) + tx * s(I + 1, J)) +
                                 ty * ((1 - tx) * s(I, J + 1) + tx * s(I + 1, J + 1));
                xyz[3 * (size_t(j) * out_w + i) + q] += float(v * per_pixel);
            }
        }
    }
}

}  // namespace wavecam::detail
