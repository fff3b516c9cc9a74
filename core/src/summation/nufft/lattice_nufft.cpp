// Gridding NUFFT on the pinhole lattice (lattice_nufft.h; docs/summation.md).
//
// Type 1: spread a_s onto a periodic grid of M points, spacing 2 pi / M, with the kernel
// phi(x) = es(x / alpha), alpha = w pi / M; by Poisson summation
//   sum_l phi(2 pi l / M - x) exp(-i k 2 pi l / M) = (M / 2 pi) phihat(k) exp(-i k x) + aliases,
// so one FFT of the grid divided by (M / 2 pi) phihat(k) gives the sum at mode k. Type 2 is the
// transpose: divide the modes by (M / 2 pi) phihat(k), FFT, interpolate with the same kernel.
// Modes are centred (k = m - nx/2), the offset is a phase per point.
#include "summation/nufft/lattice_nufft.h"

#include <algorithm>
#include <cmath>

#include "base/parallel.h"
#include "fft/column_fft.h"
#include "fft/line_fft.h"

namespace wavecam::detail {
namespace {

// This thread's line transform of length n, kept between calls (its buffers fault in once).
LineFft& kept_line_fft(int n, bool inverse) {
    thread_local std::vector<std::pair<bool, LineFft>> kept;
    for (auto& [dir, fft] : kept)
        if (fft.length() == n && dir == inverse) return fft;
    if (kept.size() >= 4) kept.erase(kept.begin());
    return kept.emplace_back(inverse, LineFft(n, inverse)).second;
}

// (M / 2 pi) phihat(k) = (w / 2) int_-1^1 es(z) cos(pi k w z / M) dz (midpoint rule; es is smooth
// inside and e^-beta at the ends).
std::vector<double> deconvolution(int n, int m, int w, double beta) {
    constexpr int kNodes = 512;
    std::vector<double> es(kNodes), z(kNodes);
    for (int i = 0; i < kNodes; ++i) {
        z[i] = -1.0 + (i + 0.5) * 2.0 / kNodes;
        es[i] = std::exp(beta * (std::sqrt(1.0 - z[i] * z[i]) - 1.0));
    }
    std::vector<double> d(n);
    for (int mode = 0; mode < n; ++mode) {
        const double k = mode - n / 2;
        double s = 0;
        for (int i = 0; i < kNodes; ++i) s += es[i] * std::cos(M_PI * k * w * z[i] / m);
        d[mode] = 1.0 / (0.5 * w * s * 2.0 / kNodes);
    }
    return d;
}

// The kernel tabulated at kTable points per unit of z on [-1, 1], read with linear interpolation
// (error about (1 / kTable)^2 beta / 8 ~ 1e-7, far below the tolerances used).
constexpr int kTable = 4096;
std::vector<float> kernel_table(double beta) {
    std::vector<float> t(2 * kTable + 2);
    for (int i = 0; i <= 2 * kTable + 1; ++i) {
        const double z = std::min(1.0, -1.0 + double(i) / kTable), r = 1.0 - z * z;
        t[i] = r > 0 ? float(std::exp(beta * (std::sqrt(r) - 1.0))) : 0.0f;
    }
    return t;
}

// The w kernel weights along one axis for a point at grid position g (grid units, any real),
// and the first grid index they apply to (not yet wrapped).
inline long kernel_weights(double g, int w, const float* table, float* weights) {
    const long first = long(std::ceil(g - 0.5 * w));
    const double scale = 2.0 / w * kTable;
    for (int i = 0; i < w; ++i) {
        const double t = ((double(first + i) - g) * scale) + kTable;  // z = (first + i - g) 2 / w
        const int k = std::clamp(int(t), 0, 2 * kTable);
        const float frac = float(t - k);
        weights[i] = table[k] + frac * (table[k + 1] - table[k]);
    }
    return first;
}

inline long wrap(long i, long m) {
    i %= m;
    return i < 0 ? i + m : i;
}

constexpr int kMaxWidth = 16;

// One point's kernel spread onto the grid (rows of `stride`), w x w taps: W fixed at compile time
// for the common widths, else the run-time w. A row's 2w floats (re, im interleaved) at once:
// p[k] = v x wx (each weight twice), then row += wy[j] p, a loop the compiler vectorises.
template <int W>
inline void spread(cfloat* grid, size_t stride, const float* wx, const float* wy, cfloat v, int w) {
    const int n = W > 0 ? W : w;
    float p[2 * kMaxWidth];
    for (int i = 0; i < n; ++i) {
        p[2 * i] = v.real() * wx[i];
        p[2 * i + 1] = v.imag() * wx[i];
    }
    for (int j = 0; j < n; ++j) {
        float* row = reinterpret_cast<float*>(grid + size_t(j) * stride);
        const float y = wy[j];
        for (int k = 0; k < 2 * n; ++k) row[k] += y * p[k];
    }
}

// One point's kernel read from the grid: the rows summed with wy first (2w floats at once), then
// across with wx.
template <int W>
inline cfloat interpolate(const cfloat* grid, size_t stride, const float* wx, const float* wy, int w) {
    const int n = W > 0 ? W : w;
    float column[2 * kMaxWidth] = {};
    for (int j = 0; j < n; ++j) {
        const float* row = reinterpret_cast<const float*>(grid + size_t(j) * stride);
        const float y = wy[j];
        for (int k = 0; k < 2 * n; ++k) column[k] += y * row[k];
    }
    float re = 0, im = 0;
    for (int i = 0; i < n; ++i) {
        re += wx[i] * column[2 * i];
        im += wx[i] * column[2 * i + 1];
    }
    return {re, im};
}

// The points `index` (count of them) spread onto `batch` grids, strengths a[s * batch + q]. In the
// AVX2 clone on CPUs that have it (the taps are most of a transform's work); the common widths
// compiled for their own.
template <int W>
inline void spread_points(const PlacedPoints& points, const size_t* index, size_t count, const cfloat* a, int batch,
                          cfloat* const* grids, size_t stride, int w) {
    for (size_t k = 0; k < count; ++k) {
        const size_t s = index[k];
        const float *wx = &points.weight_x[s * size_t(w)], *wy = &points.weight_y[s * size_t(w)];
        const size_t at = size_t(points.first_y[s]) * stride + size_t(points.first_x[s]);
        for (int q = 0; q < batch; ++q) spread<W>(grids[q] + at, stride, wx, wy, a[s * batch + q], w);
    }
}
__attribute__((target_clones("arch=x86-64-v3", "default")))
void spread_points(const PlacedPoints& points, const size_t* index, size_t count, const cfloat* a, int batch,
                   cfloat* const* grids, size_t stride, int w) {
    switch (w) {
        case 4: return spread_points<4>(points, index, count, a, batch, grids, stride, w);
        case 5: return spread_points<5>(points, index, count, a, batch, grids, stride, w);
        case 6: return spread_points<6>(points, index, count, a, batch, grids, stride, w);
        case 7: return spread_points<7>(points, index, count, a, batch, grids, stride, w);
        case 8: return spread_points<8>(points, index, count, a, batch, grids, stride, w);
        default: return spread_points<0>(points, index, count, a, batch, grids, stride, w);
    }
}

// Points [begin, end) read from `batch` grids, weighted c[(s - begin) * batch + q], into out[s - begin].
template <int W>
inline void interpolate_points(const PlacedPoints& points, size_t begin, size_t end, const cfloat* const* grids,
                               int batch, size_t stride, const cfloat* c, cfloat* out, size_t first, int w) {
    for (size_t s = begin; s < end; ++s) {
        const float *wx = &points.weight_x[s * size_t(w)], *wy = &points.weight_y[s * size_t(w)];
        const size_t at = size_t(points.first_y[s]) * stride + size_t(points.first_x[s]);
        cfloat total = 0;
        for (int q = 0; q < batch; ++q) total += c[(s - first) * batch + q] * interpolate<W>(grids[q] + at, stride, wx, wy, w);
        out[s - first] = total;
    }
}
__attribute__((target_clones("arch=x86-64-v3", "default")))
void interpolate_points(const PlacedPoints& points, size_t begin, size_t end, const cfloat* const* grids, int batch,
                        size_t stride, const cfloat* c, cfloat* out, size_t first, int w) {
    switch (w) {
        case 4: return interpolate_points<4>(points, begin, end, grids, batch, stride, c, out, first, w);
        case 5: return interpolate_points<5>(points, begin, end, grids, batch, stride, c, out, first, w);
        case 6: return interpolate_points<6>(points, begin, end, grids, batch, stride, c, out, first, w);
        case 7: return interpolate_points<7>(points, begin, end, grids, batch, stride, c, out, first, w);
        case 8: return interpolate_points<8>(points, begin, end, grids, batch, stride, c, out, first, w);
        default: return interpolate_points<0>(points, begin, end, grids, batch, stride, c, out, first, w);
    }
}

}  // namespace

LatticeNufft::LatticeNufft(int nx, int ny, double tolerance, int nthreads)
    : nx_(nx), ny_(ny), nthreads_(nthreads) {
    tolerance = std::clamp(tolerance, 1e-7, 1e-2);
    w_ = std::min(kMaxWidth, int(std::ceil(-std::log10(tolerance))) + 1);
    beta_ = 2.30 * w_;
    mx_ = fft_friendly_size(std::max(2 * nx_, 2 * w_));
    my_ = fft_friendly_size(std::max(2 * ny_, 2 * w_));
    table_ = kernel_table(beta_);
    deconvolve_x_ = deconvolution(nx_, mx_, w_, beta_);
    deconvolve_y_ = deconvolution(ny_, my_, w_, beta_);
}

double LatticeNufft::fft_work() const {
    const double n = double(mx_) * my_;
    return 0.75 * n * std::log2(n);  // pruned: a quarter of the line transforms are skipped
}

// In place on a grid of my_ rows of stride mx_ + w_: the rows listed (the others are zero and
// stay so, or are not needed), then the columns listed (likewise). The rows as lines (line_fft.h,
// each thread a share of them), the columns down the grid itself, run by run of neighbours.
void LatticeNufft::fft2d(std::vector<cfloat>& grid, const std::vector<int>& rows, const std::vector<int>& columns) const {
    const size_t stride = size_t(mx_) + w_;
    std::vector<std::pair<int, int>> runs;  // [first, last) of neighbouring columns
    for (const int c : columns)
        if (!runs.empty() && runs.back().second == c)
            ++runs.back().second;
        else
            runs.emplace_back(c, c + 1);
    const ColumnFft column_fft(my_, false);
    column_work_.resize(size_t(my_) * stride);
    parallel_team(thread_count(nthreads_), [&](Team& t) {
        const int team = t.size(), me = t.rank();
        const int per = (int(rows.size()) + team - 1) / team, a = std::min(int(rows.size()), me * per),
                  b = std::min(int(rows.size()), a + per);
        kept_line_fft(mx_, false).transform(b - a, [&](int k) { return grid.data() + size_t(rows[a + k]) * stride; });
        t.barrier();
        for (const auto& [first, last] : runs) {
            const int share = std::max(16, (last - first + team - 1) / team);
            const int x0 = std::min(last, first + me * share), x1 = std::min(last, x0 + share);
            if (x0 < x1) column_fft.transform(grid.data(), column_work_.data(), int(stride), x0, x1);
        }
    });
}

std::vector<int> LatticeNufft::mode_lines(int n, int m) {
    // centred modes -n/2 .. n/2 - 1, wrapped
    std::vector<int> lines(n);
    for (int i = 0; i < n; ++i) lines[i] = i < (n + 1) / 2 ? i : m - (n - i);
    return lines;
}

// `batch` zeroed grids of `plane` values, kept between calls (no page faults per transform).
std::vector<std::vector<cfloat>>& LatticeNufft::workspace(int batch, size_t plane) const {
    if (int(grids_.size()) < batch) grids_.resize(batch);
    for (int q = 0; q < batch; ++q) {
        grids_[q].resize(plane);
        cfloat* g = grids_[q].data();
        parallel_for(0, long(plane), thread_count(nthreads_), [&](int64_t i) {
            g[i] = cfloat(0);
        });
    }
    return grids_;
}

std::complex<double> LatticeNufft::centring(double x, double y) const { return std::polar(1.0, centring_phase(x, y)); }

// The grid lines (of m) that the kernels of points at x (radians per step) touch.
std::vector<int> LatticeNufft::touched(const double* x, size_t count, int m) const {
    std::vector<char> hit(size_t(m), 0);
    const double to_g = m / (2 * M_PI);
    for (size_t s = 0; s < count; ++s) {
        const long first = long(std::ceil(x[s] * to_g - 0.5 * w_));
        for (int i = 0; i < w_; ++i) hit[size_t(wrap(first + i, m))] = 1;
    }
    std::vector<int> lines;
    for (int i = 0; i < m; ++i)
        if (hit[size_t(i)]) lines.push_back(i);
    return lines;
}

PlacedPoints LatticeNufft::place(const LatticePoints& points, bool lines) const {
    PlacedPoints p;
    const size_t count = p.count = points.count;
    const size_t w = size_t(w_);
    p.first_x.resize(count);
    p.first_y.resize(count);
    p.weight_x.resize(count * w);
    p.weight_y.resize(count * w);
    const double to_gx = mx_ / (2 * M_PI), to_gy = my_ / (2 * M_PI);
    parallel_for(0, long(count), thread_count(nthreads_), [&](int64_t s) {
        p.first_x[size_t(s)] = int(wrap(kernel_weights(points.x[s] * to_gx, w_, table_.data(), &p.weight_x[size_t(s) * w]), mx_));
        p.first_y[size_t(s)] = int(wrap(kernel_weights(points.y[s] * to_gy, w_, table_.data(), &p.weight_y[size_t(s) * w]), my_));
    });
    // Rows of the grid in stripes at least w high, each point in the stripe of its first row: the
    // even stripes spread in parallel, then the odd ones, so no two threads write one grid row at
    // once. The grid has w rows and columns of padding beyond the period, folded back afterwards.
    const int stripes = std::max(2, (my_ / (w_ + 1)) & ~1);
    const double stripe_height = double(my_) / stripes;
    p.bucket.resize(size_t(stripes));
    for (size_t s = 0; s < count; ++s)
        p.bucket[size_t(std::min(stripes - 1, int(p.first_y[s] / stripe_height)))].push_back(s);
    if (lines) {
        p.rows = touched(points.y, count, my_);
        p.columns = touched(points.x, count, mx_);
    }
    return p;
}

// Points a block at a time where they come unplaced (a block's placing is a few MB, not a
// frame's hundreds).
constexpr size_t kPlacedBlock = size_t(1) << 16;

void LatticeNufft::to_lattice(const LatticePoints& points, const cfloat* a, int batch, cfloat* const* lattices) const {
    clear(batch);
    for (size_t b = 0; b < points.count; b += kPlacedBlock) {
        const size_t n = std::min(kPlacedBlock, points.count - b);
        spread(place({points.x + b, points.y + b, n}, false), a + b * size_t(batch), batch);
    }
    to_modes(batch, touched(points.y, points.count, my_), lattices);
}

void LatticeNufft::from_lattice(const cfloat* const* lattices, int batch, const LatticePoints& points, const cfloat* c,
                                cfloat* out) const {
    from_modes(lattices, batch, touched(points.x, points.count, mx_));
    for (size_t b = 0; b < points.count; b += kPlacedBlock) {
        const size_t n = std::min(kPlacedBlock, points.count - b);
        interpolate(place({points.x + b, points.y + b, n}, false), 0, n, batch, c + b * size_t(batch), out + b);
    }
}

void LatticeNufft::to_lattice(const PlacedPoints& points, const cfloat* a, int batch, cfloat* const* lattices) const {
    clear(batch);
    spread(points, a, batch);
    to_modes(batch, points.rows, lattices);
}

void LatticeNufft::from_lattice(const cfloat* const* lattices, int batch, const PlacedPoints& points, size_t begin,
                                size_t end, const cfloat* c, cfloat* out) const {
    from_modes(lattices, batch, points.columns);
    interpolate(points, begin, end, batch, c, out);
}

void LatticeNufft::clear(int batch) const {
    const size_t stride = size_t(mx_) + w_;
    workspace(batch, stride * (size_t(my_) + w_));
}

void LatticeNufft::spread(const PlacedPoints& points, const cfloat* a, int batch) const {
    const size_t stride = size_t(mx_) + w_;
    const int stripes = int(points.bucket.size());
    std::vector<cfloat*> grids(grids_.size());
    for (int q = 0; q < batch; ++q) grids[size_t(q)] = grids_[size_t(q)].data();
    for (int parity = 0; parity < 2; ++parity) {
        parallel_for_dynamic(0, (stripes - parity + 1) / 2, 1, thread_count(nthreads_), [&](int64_t k) {
            const std::vector<size_t>& bucket = points.bucket[size_t(parity + 2 * int(k))];
            spread_points(points, bucket.data(), bucket.size(), a, batch, grids.data(), stride, w_);
        });
    }
}

void LatticeNufft::to_modes(int batch, const std::vector<int>& rows, cfloat* const* lattices) const {
    const size_t stride = size_t(mx_) + w_;
    const int cx = nx_ / 2, cy = ny_ / 2;
    // transformed: the rows the points' kernels touch, then the columns of the modes wanted
    const std::vector<int> columns = mode_lines(nx_, mx_);
    for (int q = 0; q < batch; ++q) {
        std::vector<cfloat>& one = grids_[size_t(q)];
        // fold the padding back onto the period: the w columns beyond each row, then the w rows
        // beyond the last (their own padding folded first)
        for (int r = 0; r < my_ + w_; ++r)
            for (int c = mx_; c < mx_ + w_; ++c) one[size_t(r) * stride + c - mx_] += one[size_t(r) * stride + c];
        for (int r = my_; r < my_ + w_; ++r)
            for (int c = 0; c < mx_; ++c) one[size_t(r - my_) * stride + c] += one[size_t(r) * stride + c];
        fft2d(one, rows, columns);
        cfloat* lattice = lattices[q];
        parallel_for(0, ny_, thread_count(nthreads_), [&](int64_t n_) {
            const int n = int(n_);
            for (int m = 0; m < nx_; ++m) {
                const size_t bin = size_t(wrap(n - cy, my_)) * stride + wrap(m - cx, mx_);
                lattice[size_t(n) * nx_ + m] = one[bin] * float(deconvolve_x_[m] * deconvolve_y_[n]);
            }
        });
    }
}

void LatticeNufft::from_modes(const cfloat* const* lattices, int batch, const std::vector<int>& columns) const {
    const size_t stride = size_t(mx_) + w_;
    const int cx = nx_ / 2, cy = ny_ / 2;
    clear(batch);
    // transformed: the rows of the modes given, then the columns the points' kernels read
    const std::vector<int> rows = mode_lines(ny_, my_);
    for (int q = 0; q < batch; ++q) {
        std::vector<cfloat>& one = grids_[size_t(q)];
        const cfloat* lattice = lattices[q];
        parallel_for(0, ny_, thread_count(nthreads_), [&](int64_t n_) {
            const int n = int(n_);
            for (int m = 0; m < nx_; ++m) {
                const size_t bin = size_t(wrap(n - cy, my_)) * stride + wrap(m - cx, mx_);
                one[bin] = lattice[size_t(n) * nx_ + m] * float(deconvolve_x_[m] * deconvolve_y_[n]);
            }
        });
        fft2d(one, rows, columns);
        // periodic padding: w columns beyond each row, then w rows beyond the last, repeat the start
        for (int r = 0; r < my_; ++r)
            for (int col = mx_; col < mx_ + w_; ++col) one[size_t(r) * stride + col] = one[size_t(r) * stride + col - mx_];
        for (int r = my_; r < my_ + w_; ++r)
            std::copy(one.begin() + size_t(r - my_) * stride, one.begin() + size_t(r - my_ + 1) * stride,
                      one.begin() + size_t(r) * stride);
    }
}

void LatticeNufft::interpolate(const PlacedPoints& points, size_t begin, size_t end, int batch, const cfloat* c,
                               cfloat* out) const {
    const size_t stride = size_t(mx_) + w_;
    std::vector<const cfloat*> grids(grids_.size());
    for (int q = 0; q < batch; ++q) grids[size_t(q)] = grids_[size_t(q)].data();
    // blocks of up to 1024 points, at least four a thread
    const int threads = thread_count(nthreads_);
    const size_t block = std::clamp((end - begin) / size_t(4 * threads), size_t(16), size_t(1024));
    parallel_for(0, int64_t((end - begin + block - 1) / block), threads, [&](int64_t b) {
        const size_t s0 = begin + size_t(b) * block, s1 = std::min(end, s0 + block);
        interpolate_points(points, s0, s1, grids.data(), batch, stride, c, out, begin, w_);
    });
}

}  // namespace wavecam::detail
