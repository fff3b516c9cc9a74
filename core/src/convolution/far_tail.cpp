#include "wavecam/edge_continuation.h"
#include "convolution/far_tail.h"
#include "convolution/direction_cosines.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <complex>
#include <vector>

#include "base/parallel.h"
#include "fft/complex_fft2d.h"

namespace wavecam::detail {

namespace {

// The annulus R <= r <= reach with intensity ~ 1/r^3, integrated over cells of `cell` pixels and
// holding 1 in all; its (2 half + 1)^2 cells round the centre (half may cut the annulus short
// where the grid it spreads over is narrower than the reach).
std::vector<double> tail_kernel(int radius, int reach, int cell, int half) {
    const int w = 2 * half + 1, sub = 6, full = reach / cell + 1;
    std::vector<double> k(size_t(w) * w, 0.0);
    double total = 0;
    for (int b = -full; b <= full; ++b)
        for (int a = -full; a <= full; ++a) {
            double s = 0;
            for (int sb = 0; sb < sub; ++sb)
                for (int sa = 0; sa < sub; ++sa) {
                    const double x = (a + (sa + 0.5) / sub - 0.5) * cell, y = (b + (sb + 0.5) / sub - 0.5) * cell;
                    const double r = std::hypot(x, y);
                    if (r >= radius && r <= reach) s += 1.0 / (r * r * r);
                }
            if (std::abs(a) <= half && std::abs(b) <= half) k[size_t(b + half) * w + (a + half)] = s;
            total += s;
        }
    for (double& x : k) x /= total;
    return k;
}

// The coarse grid the tail is gathered and spread on, in axis pixels: cells of `cell` x `cell`,
// cell (0, 0) from (a0, b0), covering the output's directions widened by the tail's reach.
struct CoarseGrid {
    int cell;
    double a0, b0;
    int cw, ch;
    int column(double ax) const { return int(std::floor((ax - a0) / cell)); }
    int row(double ay) const { return int(std::floor((ay - b0) / cell)); }
};

// sum[k] += weight x the light lit[p] of each primary p times its deficit into XYZ k (def[3 p + k]).
template <class Deficit>
inline void add_deficit(const double lit[3], const Deficit* def, double weight, double sum[3]) {
    for (int k = 0; k < 3; ++k) sum[k] += weight * (lit[0] * def[k] + lit[1] * def[3 + k] + lit[2] * def[6 + k]);
}

// Per coarse cell, the light its sources send beyond their kernels, each source's light (radiance
// x its cos^4 fall-off, a pixel's light as the kernels carry it) times its kernels' missing share
// at its own place, interpolated as the kernels are. The sources are the frame's pixels and,
// beyond its edges, the edge continued: each direction beyond takes the nearest edge pixel's
// radiance (bounded by its neighbours', edge_continuation.h) and depth, a cell's part beyond the
// frame sampled at 4 x 4 points (the light of an area in axis pixels is radiance x that area, as
// a pixel's is radiance x its cos^4).
std::vector<float> missing_light(const KernelTable& t, const SpectralScene& scene, int origin, const CoarseGrid& g,
                                 const DirectionCosines& dc, bool oblique, int nthreads) {
    const PinholeCamera& c = scene.camera;
    const int W = c.width, H = c.height, L = t.layers.count, nkx = int(t.ax.knots.size()), anchors = t.anchors();
    const size_t cells = size_t(g.cw) * g.ch;
    // the missing share of source light (per primary p, into XYZ k) at camera position (x, y),
    // at inverse depth w: the anchors' and layers' deficits interpolated
    auto add_missing = [&](double x, double y, double w, const float* rgb, double light, double ax, double ay,
                           double* into) {
        const int I = g.column(ax), J = g.row(ay);
        if (I < 0 || J < 0 || I >= g.cw || J >= g.ch) return;
        int lower = 0;
        float upper = 0;
        t.layers.locate(w, lower, upper);
        const int kx = std::clamp(int(std::floor(x)) + origin, 0, t.ax.knots.back() - 1);
        const int ky = std::clamp(int(std::floor(y)) + origin, 0, t.ay.knots.back() - 1);
        const int cx = t.ax.cell_of(kx), cy = t.ay.cell_of(ky);
        const double bx = t.ax.upper_weight(cx, kx), by = t.ay.upper_weight(cy, ky);
        // the source's light per primary; its deficits summed in registers, added to the cell once
        const double lit[3] = {light * rgb[0], light * rgb[1], light * rgb[2]};
        double sum[3] = {0, 0, 0};
        for (int corner = 0; corner < 4; ++corner) {
            const int dx = corner & 1, dy = corner >> 1;
            const double phi = (dx ? bx : 1 - bx) * (dy ? by : 1 - by);
            if (phi == 0) continue;
            const int a = (cy + dy) * nkx + (cx + dx);
            for (int layer = lower; layer <= std::min(lower + 1, L - 1); ++layer) {
                const double share = layer == lower ? 1.0 - upper : upper;
                if (share == 0) continue;
                add_deficit(lit, &t.deficit[(size_t(layer) * anchors + a) * 9], phi * share, sum);
            }
        }
        double* m = into + 3 * (size_t(J) * g.cw + I);
        for (int k = 0; k < 3; ++k) m[k] += sum[k];
    };
    auto inverse_depth = [&](int i, int j) {
        const double d = scene.depth[size_t(j) * W + i];
        return d >= kInfiniteDepth ? 0.0 : 1.0 / c.planar_depth(i, j, d, scene.depth_meaning);
    };
    // a grid per thread, summed in order (the same image at any schedule), as many as 64 MiB holds
    const size_t fit = (size_t(64) << 20) / (3 * cells * sizeof(double));
    const int threads = int(std::clamp<size_t>(fit, 1, size_t(std::max(1, nthreads))));
    std::vector<std::vector<double>> part(threads, std::vector<double>(3 * cells, 0.0));
    const EdgeContinuation edge(scene.rgb, 3, W, H);  // a lone bright edge pixel is not copied beyond
    // the frame's pixels' tangents and knot cells along each axis, once
    const std::vector<double> u = column_tangents(c, 0, W), v = row_tangents(c, 0, H);
    std::vector<double> bx(W), by(H);
    std::vector<int> cx(W), cy(H);
    for (int i = 0; i < W; ++i) {
        const int kx = std::clamp(i + origin, 0, t.ax.knots.back() - 1);
        cx[i] = t.ax.cell_of(kx);
        bx[i] = t.ax.upper_weight(cx[i], kx);
    }
    for (int j = 0; j < H; ++j) {
        const int ky = std::clamp(j + origin, 0, t.ay.knots.back() - 1);
        cy[j] = t.ay.cell_of(ky);
        by[j] = t.ay.upper_weight(cy[j], ky);
    }
    parallel_team(threads, [&](Team& team) {
        std::vector<double>& mine = part[size_t(team.rank())];
        // the frame's pixels, each at its centre: a row's deficits interpolated between its two
        // knot rows first (per layer and knot column), then across per pixel
        std::vector<double> row_deficit(size_t(L) * nkx * 9);
        team.for_blocks(0, H, [&](int64_t j64) {
            const int j = int(j64);
            for (int layer = 0; layer < L; ++layer)
                for (int kx = 0; kx < nkx; ++kx)
                    for (int m = 0; m < 9; ++m) {
                        const float* d = &t.deficit[(size_t(layer) * anchors + cy[j] * nkx + kx) * 9 + m];
                        row_deficit[(size_t(layer) * nkx + kx) * 9 + m] = (1 - by[j]) * d[0] + by[j] * d[nkx * 9];
                    }
            for (int i = 0; i < W; ++i) {
                double ax, ay;
                dc.of_tangent(u[i], v[j], ax, ay);
                const int I = g.column(ax), J = g.row(ay);
                if (I < 0 || J < 0 || I >= g.cw || J >= g.ch) continue;
                const double c2 = 1.0 / (1 + u[i] * u[i] + v[j] * v[j]);
                const double light = c2 * c2 * (oblique ? 1 / std::sqrt(c2) : 1.0);
                const float* rgb = &scene.rgb[3 * (size_t(j) * W + i)];
                const double lit[3] = {light * rgb[0], light * rgb[1], light * rgb[2]};
                int lower = 0;
                float upper = 0;
                t.layers.locate(inverse_depth(i, j), lower, upper);
                double sum[3] = {0, 0, 0};
                for (int layer = lower; layer <= std::min(lower + 1, L - 1); ++layer) {
                    const double share = layer == lower ? 1.0 - upper : upper;
                    if (share == 0) continue;
                    const double* d = &row_deficit[(size_t(layer) * nkx + cx[i]) * 9];
                    add_deficit(lit, d, share * (1 - bx[i]), sum);
                    add_deficit(lit, d + 9, share * bx[i], sum);
                }
                double* into = &mine[3 * (size_t(J) * g.cw + I)];
                for (int k = 0; k < 3; ++k) into[k] += sum[k];
            }
        });
        // beyond them, the edge continued
        const double sub = g.cell / 4.0;
        team.for_blocks(0, g.ch, [&](int64_t J) {
            for (int I = 0; I < g.cw; ++I)
                for (int q = 0; q < 16; ++q) {
                    const double ax = g.a0 + I * g.cell + (q % 4 + 0.5) * sub;
                    const double ay = g.b0 + J * g.cell + (q / 4 + 0.5) * sub;
                    double u, v;
                    if (!dc.to_tangent(ax, ay, u, v)) continue;
                    const double x = u / dc.pitch + 0.5 * W, y = 0.5 * H - v / dc.pitch;
                    if (x >= 0 && x < W && y >= 0 && y < H) continue;
                    const int ci = std::clamp(int(std::floor(x)), 0, W - 1);
                    const int cj = std::clamp(int(std::floor(y)), 0, H - 1);
                    const double light = sub * sub * (oblique ? std::sqrt(1 + u * u + v * v) : 1.0);
                    add_missing(x, y, inverse_depth(ci, cj), edge.at(ci, cj), light, ax, ay, mine.data());
                }
        });
    });
    std::vector<float> missing(3 * cells, 0.0f);
    for (size_t q = 0; q < missing.size(); ++q) {
        double sum = 0;
        for (const auto& p : part) sum += p[q];
        missing[q] = float(sum);
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
    // (cells farther apart than the grid is wide join no two of its cells)
    const int half = std::min(reach / g.cell + 1, std::max(g.cw, g.ch)), kw = 2 * half + 1;
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

double film_kernel_edge(int radius, double tan_pitch) {
    // R pixels from the axis are R / sqrt(1 + (R pitch)^2) axis pixels of direction (fewer off
    // the axis, where pixels span less; always inside the disc)
    return radius / std::sqrt(1 + std::pow(radius * tan_pitch, 2));
}

void add_far_tail(const KernelTable& t, double kernel_edge, bool oblique, const SpectralScene& scene, int origin,
                  const OutputWindow& out, float* xyz, int nthreads) {
    const int out_w = out.width, out_h = out.height;
    if (t.deficit.empty()) return;
    const PinholeCamera& c = scene.camera;
    const DirectionCosines dc{c.tan_pitch()};
    const double rho = 1.0 / dc.pitch;  // the disc of directions, in axis pixels
    // The annulus starts where the kernels end
    const int R = std::max(1, int(std::lround(kernel_edge))), reach = kTailReach * R;
    // the output's directions, widened by the reach
    const DirectionBox box = direction_box(c, dc, out.x0 - origin, out.y0 - origin, out_w, out_h);
    const double lo_a = box.lo_a, hi_a = box.hi_a, lo_b = box.lo_b, hi_b = box.hi_b;
    const int cell = std::max(1, R / 3);
    const double a0 = std::max(-rho, lo_a - reach), a1 = std::min(rho, hi_a + reach);
    const double b0 = std::max(-rho, lo_b - reach), b1 = std::min(rho, hi_b + reach);
    const CoarseGrid g{cell, a0, b0, int(std::ceil((a1 - a0) / cell)) + 1, int(std::ceil((b1 - b0) / cell)) + 1};
    const CellWindow read{std::max(0, g.column(lo_a) - 1), std::min(g.cw, g.column(hi_a) + 2),
                          std::max(0, g.row(lo_b) - 1), std::min(g.ch, g.row(hi_b) + 2)};
    const std::vector<float> spread =
        spread_over_annulus(missing_light(t, scene, origin, g, dc, oblique, nthreads), g, {R, reach}, read, nthreads);
    // back to pixels: each pixel takes the cells' light at its direction (bilinearly) over its
    // share of a cell, cos^4 of an axis pixel over the cell's cell^2
    const double per_area = 1.0 / (double(cell) * cell);
    const std::vector<double> us = column_tangents(c, out.x0 - origin, out_w), vs = row_tangents(c, out.y0 - origin, out_h);
    parallel_for(0, out_h, thread_count(nthreads), [&](int64_t j) {
        for (int i = 0; i < out_w; ++i) {
            const double u = us[i], v = vs[j];
            double ax, ay;
            dc.of_tangent(u, v, ax, ay);
            const double fx = (ax - g.a0) / cell - 0.5, fy = (ay - g.b0) / cell - 0.5;
            const int I = std::clamp(int(std::floor(fx)), 0, g.cw - 2);
            const int J = std::clamp(int(std::floor(fy)), 0, g.ch - 2);
            const double tx = std::clamp(fx - I, 0.0, 1.0), ty = std::clamp(fy - J, 0.0, 1.0);
            const double c2 = 1.0 / (1 + u * u + v * v), share = c2 * c2 * per_area * (oblique ? std::sqrt(c2) : 1.0);
            for (int q = 0; q < 3; ++q) {
                auto at = [&](int ii, int jj) { return double(spread[3 * (size_t(jj) * g.cw + ii) + q]); };
                const double value = (1 - ty) * ((1 - tx) * at(I, J) + tx * at(I + 1, J)) +
                                     ty * ((1 - tx) * at(I, J + 1) + tx * at(I + 1, J + 1));
                xyz[3 * (size_t(j) * out_w + i) + q] += float(value * share);
            }
        }
    });
}

}  // namespace wavecam::detail
