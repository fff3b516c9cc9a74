#include "far_tail.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <complex>
#include <vector>

#include "complex_fft2d.h"
#include "real_fft2d.h"

namespace wavecam::detail {

namespace {

// Sum of the cos^4 fall-off 1 / (1 + u^2 + v^2)^2 over pixels of tangent width `pitch` spanning
// u0..u1 at fixed v, by its integral (the midpoint sum differs by about pitch^2 / 24 of its
// second derivative: 1e-7 here): int du / (a^2 + u^2)^2 = u / (2 a^2 (a^2 + u^2)) +
// atan(u / a) / (2 a^3), a^2 = 1 + v^2.
double cos4_sum(double u0, double u1, double v, double pitch) {
    const double a2 = 1 + v * v, a = std::sqrt(a2);
    auto G = [&](double u) { return u / (2 * a2 * (a2 + u * u)) + std::atan(u / a) / (2 * a2 * a); };
    return (G(u1) - G(u0)) / pitch;
}

// The sources as the far tail sees them: the frame's pixels, and beyond its edges the edge
// continued (each missing pixel takes the nearest edge pixel's radiance and depth, at its own
// field position, so with its own cos^4 fall-off).
class FrameSources {
public:
    FrameSources(const KernelTable& t, const SpectralScene& scene)
        : scene_(scene), c_(scene.camera), pitch_(c_.tan_pitch()) {
        const size_t n = size_t(c_.width) * c_.height;
        lower_.resize(n);
        upper_.resize(n);
        for (int j = 0; j < c_.height; ++j)
            for (int i = 0; i < c_.width; ++i) {
                const size_t q = size_t(j) * c_.width + i;
                const double d = scene.depth[q];
                const double w = d >= kInfiniteDepth ? 0.0 : 1.0 / c_.planar_depth(i, j, d, scene.depth_meaning);
                int lower = 0;
                t.layers.locate(w, lower, upper_[q]);
                lower_[q] = uint8_t(lower);
            }
    }

    // Adds to light[layer][primary] the light of the cell x cell block of camera pixels from
    // (x0, y0), which may reach beyond the frame: inside it pixel by pixel, beyond it the edge
    // pixel's light times the fall-off summed along the run of pixels that repeat it.
    void add_block(int x0, int y0, int cell, std::vector<double>& light) const {
        const int W = c_.width, H = c_.height;
        // runs along each axis: before the frame, inside it, after it
        const int xa_[3] = {x0, std::max(x0, 0), std::max(x0, W)};
        const int xb_[3] = {std::min(x0 + cell, 0), std::min(x0 + cell, W), x0 + cell};
        const int ya_[3] = {y0, std::max(y0, 0), std::max(y0, H)};
        const int yb_[3] = {std::min(y0 + cell, 0), std::min(y0 + cell, H), y0 + cell};
        for (int ry = 0; ry < 3; ++ry) {
            const int ya = ya_[ry], yb = yb_[ry];
            for (int rx = 0; rx < 3; ++rx) {
                const int xa = xa_[rx], xb = xb_[rx];
                if (xa >= xb || ya >= yb) continue;
                if (rx != 1) {  // columns beyond the frame: per row, the edge pixel times the run's fall-off
                    const int ci = rx == 0 ? 0 : W - 1;
                    for (int y = ya; y < yb; ++y)
                        add(ci, std::clamp(y, 0, H - 1), cos4_sum(u(xa), u(xb), v(y + 0.5), pitch_), light);
                } else if (ry != 1) {  // rows beyond the frame: per column, likewise
                    const int cj = ry == 0 ? 0 : H - 1;
                    for (int x = xa; x < xb; ++x) add(x, cj, cos4_sum(v(yb), v(ya), u(x + 0.5), pitch_), light);
                } else {
                    for (int y = ya; y < yb; ++y) {
                        const double vy = v(y + 0.5);
                        for (int x = xa; x < xb; ++x) {
                            const double ux = u(x + 0.5), c2 = 1.0 / (1.0 + ux * ux + vy * vy);
                            add(x, y, c2 * c2, light);
                        }
                    }
                }
            }
        }
    }

private:
    double u(double x) const { return (x - 0.5 * c_.width) * pitch_; }
    double v(double y) const { return (0.5 * c_.height - y) * pitch_; }
    void add(int ci, int cj, double falloff, std::vector<double>& light) const {
        const size_t q = size_t(cj) * c_.width + ci;
        const int lower = lower_[q];
        const double upper = upper_[q];
        for (int p = 0; p < 3; ++p) {
            const double x = falloff * scene_.rgb[3 * q + p];
            light[size_t(lower) * 3 + p] += (1.0 - upper) * x;
            if (upper > 0) light[size_t(lower + 1) * 3 + p] += upper * x;
        }
    }

    const SpectralScene& scene_;
    const PinholeCamera& c_;
    double pitch_;  // tangent-plane width of a pixel
    std::vector<uint8_t> lower_;
    std::vector<float> upper_;
};

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

// The coarse grid the tail is gathered and spread on: cells of `cell` x `cell` pixels, cell
// (0, 0) at domain pixel (x0, y0), covering the output widened by the tail's reach.
struct CoarseGrid {
    int cell, x0, y0, cw, ch;
};

// Per coarse cell, the light its sources send beyond their kernels: each layer's light times the
// kernels' missing shares at the cell's centre, interpolated as the kernels are.
std::vector<float> missing_light(const KernelTable& t, const SpectralScene& scene, int origin, const CoarseGrid& g,
                                 int nthreads) {
    const int L = t.layers.count, nkx = int(t.ax.knots.size()), anchors = t.anchors();
    std::vector<float> missing(3 * size_t(g.cw) * g.ch, 0.0f);
    const FrameSources frame(t, scene);
#pragma omp parallel num_threads(nthreads)
    {
        std::vector<double> light(size_t(L) * 3);  // a cell's light per layer and primary
#pragma omp for
        for (int J = 0; J < g.ch; ++J)
            for (int I = 0; I < g.cw; ++I) {
                std::fill(light.begin(), light.end(), 0.0);
                frame.add_block(g.x0 + I * g.cell - origin, g.y0 + J * g.cell - origin, g.cell, light);
                const int kx = std::clamp(g.x0 + I * g.cell + g.cell / 2, 0, t.ax.knots.back() - 1);
                const int ky = std::clamp(g.y0 + J * g.cell + g.cell / 2, 0, t.ay.knots.back() - 1);
                const int cx = t.ax.cell_of(kx), cy = t.ay.cell_of(ky);
                const double bx = t.ax.upper_weight(cx, kx), by = t.ay.upper_weight(cy, ky);
                float* m = &missing[3 * (size_t(J) * g.cw + I)];
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
    return missing;
}

// The annulus R <= r <= reach (pixels) the missing light is spread over.
struct Annulus {
    int R, reach;
};

// The coarse cells [I0, I1) x [J0, J1).
struct CellWindow {
    int I0, I1, J0, J1;
};

// The missing light spread over the annulus R..reach by tail_kernel, by transforms (the annulus
// is wide: (2 reach / cell)^2 cells), only read in the cells `read` where the output is. The
// kernel is real, so two channels go through one complex transform, one as its real part, one
// as its imaginary part; channels without light are skipped.
std::vector<float> spread_over_annulus(const std::vector<float>& missing, const CoarseGrid& g, const Annulus& annulus,
                                       const CellWindow& read, int nthreads) {
    const int R = annulus.R, reach = annulus.reach;
    const int I0 = read.I0, I1 = read.I1, J0 = read.J0, J1 = read.J1;
    const int half = reach / g.cell + 1, kw = 2 * half + 1;
    const std::vector<double> k = tail_kernel(R, reach, g.cell, half);
    std::vector<float> spread(3 * size_t(g.cw) * g.ch, 0.0f);
    std::vector<int> lit;
    for (int q = 0; q < 3; ++q)
        for (size_t p = 0; p < missing.size() / 3; ++p)
            if (missing[3 * p + q] != 0) {
                lit.push_back(q);
                break;
            }
    if (lit.empty()) return spread;
    // a period wider than the grid and the kernel's reach: nothing wraps onto the cells read
    const int nx = fft_friendly_size(g.cw + half + 1), ny = fft_friendly_size(g.ch + half + 1);
    const ComplexFft2D fft(nx, ny, nthreads);
    std::vector<std::complex<float>> kernel(fft.size()), grid(fft.size());
    for (int b = -half; b <= half; ++b)
        for (int a = -half; a <= half; ++a)
            kernel[size_t((b + ny) % ny) * nx + (a + nx) % nx] = float(k[size_t(b + half) * kw + (a + half)]);
    fft.forward(kernel.data());
    const float scale = 1.0f / float(fft.size());
    for (size_t pair = 0; pair < lit.size(); pair += 2) {
        const int re = lit[pair], im = pair + 1 < lit.size() ? lit[pair + 1] : -1;
        std::fill(grid.begin(), grid.end(), std::complex<float>(0));
        for (int J = 0; J < g.ch; ++J)
            for (int I = 0; I < g.cw; ++I) {
                const size_t c = size_t(J) * g.cw + I;
                grid[size_t(J) * nx + I] = {missing[3 * c + re], im < 0 ? 0.0f : missing[3 * c + im]};
            }
        fft.forward(grid.data(), g.ch);
        for (size_t q = 0; q < grid.size(); ++q) grid[q] *= kernel[q] * scale;
        fft.inverse(grid.data());
        for (int J = J0; J < J1; ++J)
            for (int I = I0; I < I1; ++I) {
                const std::complex<float> v = grid[size_t(J) * nx + I];
                spread[3 * (size_t(J) * g.cw + I) + re] = v.real();
                if (im >= 0) spread[3 * (size_t(J) * g.cw + I) + im] = v.imag();
            }
    }
    return spread;
}

}  // namespace

void add_far_tail(const KernelTable& t, const SpectralScene& scene, int origin, const OutputWindow& out, float* xyz,
                  int nthreads) {
    const int out_x0 = out.x0, out_y0 = out.y0, out_w = out.width, out_h = out.height;
    const int R = t.radius, reach = kTailReach * R;
    if (t.deficit.empty()) return;
    const int cell = std::max(1, R / 3);
    const CoarseGrid g{cell, out_x0 - reach, out_y0 - reach, (out_w + 2 * reach + cell - 1) / cell,
                       (out_h + 2 * reach + cell - 1) / cell};
    const int cw = g.cw, ch = g.ch;
    const int I0 = std::max(0, reach / cell - 1), I1 = std::min(cw, (reach + out_w) / cell + 2);
    const int J0 = std::max(0, reach / cell - 1), J1 = std::min(ch, (reach + out_h) / cell + 2);
    const std::vector<float> spread =
        spread_over_annulus(missing_light(t, scene, origin, g, nthreads), g, {R, reach}, {I0, I1, J0, J1}, nthreads);
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
