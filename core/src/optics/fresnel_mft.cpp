#include "optics/fresnel_mft.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <string>
#include <vector>

namespace wavecam::detail {

// ---- Few zones: matrix Fourier transform of the sampled pupil ----------------------------
//
// The chirp exp(i pi/lambda (ar xi_r^2 + at xi_t^2)) is one factor per axis, so it rides in
// each axis's transform matrix and the sampled pupil stays real (its open fraction):
//   Q(mu_r, mu_t) = sum_r M_r[mu_r][xi_r] sum_t open[xi_r][xi_t] M_t[mu_t][xi_t],
//   M[mu][xi] = exp(i pi a xi^2 / lambda) exp(-2 pi i xi mu)   (a = ar or at).
// A rotationally symmetric pupil (circle, zone plate) is the same in the (r, t) axes of every
// field azimuth and even in xi_r and in xi_t, so Q is even in mu_r and in mu_t: pairing +xi
// with -xi turns M into 2 exp(i pi a xi^2 / lambda) cos(2 pi xi mu) over xi > 0, and only
// mu >= 0 is evaluated: a quarter of the pupil onto a quarter of the grid, the same sums.

namespace {

// The matrix transform's sampled pupil depends on the aperture and the grid only, not on the
// wavelength nor (for a round pupil) on the field angle: a table's requests repeat a few dozen
// grids (their sample counts differ with the wavelength and the field), so each thread keeps the
// last kKept it sampled under their keys.
template <class Grid>
class SampledPupils {
public:
    template <class Sample>
    const Grid& get(const Aperture& a, std::vector<double> key, Sample sample) {
        if (a.mask.get() != mask_ || a.name() != aperture_) {
            kept_.clear();
            aperture_ = a.name();
            mask_ = a.mask.get();
        }
        for (const Entry& e : kept_)
            if (e.key == key) return e.grid;
        if (kept_.size() == kKept) kept_.erase(kept_.begin());
        kept_.push_back({std::move(key), sample()});
        return kept_.back().grid;
    }

private:
    static constexpr size_t kKept = 32;
    struct Entry {
        std::vector<double> key;
        Grid grid;
    };
    std::vector<Entry> kept_;
    std::string aperture_;
    const void* mask_ = nullptr;
};

}  // namespace

MftPlan plan_mft(const FieldPsfRequest& q, const FieldGeometry& g) {
    MftPlan p;
    p.mirrored = mirror_symmetric(q.aperture);
    // The irradiance holds no frequency above span / (lambda f): its finest fringe is
    // lambda f / span. Output points a fraction of a pixel apart and at least eight per finest
    // fringe, so that the sub-pixel points average fringes instead of aliasing them, and the
    // bilinear interpolation onto the pixels (rotated with the field's radial axis) holds a PSF
    // whose core spans about a pixel (a 0.8 px Airy core came 3% off its peak at two per fringe,
    // 2% at four, 1.3% at eight, against a Rayleigh-Sommerfeld integral); where the
    // finest fringe spans pixels (small pinholes, large kernels), 16 points per fringe suffice
    // for the bilinear interpolation (its error on the Airy core, curvature x step^2 / 8, stays
    // near 0.3%), however many pixels that is.
    const double fringe = q.wavelength * q.film_distance / g.span;
    p.step = std::max(fringe / 16, std::min(q.pixel_pitch / q.subsamples, fringe / 8));
    // Where the grid is coarser than a pixel (small pinholes), the bilinear interpolant is one
    // bilinear polynomial over most of a pixel, and its mean over the square pixel (at any
    // rotation) is its value at the pixel's centre: one point per pixel then.
    p.points = p.step >= q.pixel_pitch ? 1 : std::max(q.subsamples, int(std::ceil(q.pixel_pitch / p.step - 1e-6)));
    // The grid covers the kernel square rotated by any angle, or only the PSF's own
    // kPsfKernelEnergy radius where that is smaller (pixels far wider than the PSF): the
    // fringe-fine step over a kernel of such pixels would cost (pixel / fringe)^2.
    const double psf_extent = psf_radius(q.aperture, q.film_distance, q.depth, q.wavelength, g.c) + 2 * fringe;
    const double cover = std::min((q.radius + 1) * q.pixel_pitch, psf_extent) * std::sqrt(2.0);
    p.half = int(std::ceil(cover / p.step));
    const double extent = p.half * p.step;
    // Per axis (film offset d maps to mu = d c^3 / (lambda f) radially, d c / (lambda f)
    // tangentially): the quadratic phase spans N = (span/2)^2 a / lambda half-period zones
    // (a = ar or at); 8 N samples across keep its phase step below pi/2, and never fewer than
    // 64. The sampled pupil's transform repeats every lambda f / (h c^3) (radially; lambda f /
    // (h c) tangentially) on the film: the output grid (half-width `extent`) must fit in one
    // period, n >= 2 span extent c^3 / (lambda f); twice that keeps the cells' box filter
    // (sinc(mu h) >= 0.9 at the grid's edge, where the far tail lands) from dimming the tail:
    // 0.1% of the power at 0.08 mm, f = 50 mm, 99% kernel.
    // Cells hold their open fraction at their centre, so an opening narrower than the pupil
    // (a zone plate's outer zone, a sieve's hole) needs kCellsAcrossFinest cells across it: with
    // 3.5 across sieve:8's smallest hole the focal core came out 6% dim, with 12 within 0.5%.
    constexpr double kCellsAcrossFinest = 12;
    const double finest = 0.5 * kCellsAcrossFinest * g.span / q.aperture.finest_width();
    auto samples = [&](double rate, double stretch) {
        if (q.pupil_samples > 0) return q.pupil_samples + (p.mirrored ? q.pupil_samples % 2 : 0);
        const double zones = 0.25 * g.span * g.span * rate / q.wavelength;
        const double period = 2.2 * g.span * extent * stretch / (q.wavelength * q.film_distance);
        return 2 * int(std::clamp(std::ceil(std::max({4 * zones, period, finest})), 32.0, 1024.0));
    };
    p.nr = samples(g.ar, g.c * g.c * g.c);
    p.nt = samples(g.at, g.c);
    return p;
}

namespace {

// The pupil's open fraction on an nr x nt grid of cells hr x ht in (r, t) axes (the
// aperture's own x, y axes rotated by the field azimuth), from 4 x 4 points per cell; for a
// mirrored plan only the cells at xi_r > 0, xi_t > 0.
struct PupilGrid {
    std::vector<double> xi_r, xi_t;  // cell centres kept (m)
    double hr = 0, ht = 0;           // cell sides (m)
    std::vector<float> open;         // xi_r.size() x xi_t.size()
};

PupilGrid sample_pupil(const FieldPsfRequest& q, const FieldGeometry& g, const MftPlan& plan) {
    PupilGrid pupil;
    pupil.hr = g.span / plan.nr;
    pupil.ht = g.span / plan.nt;
    auto centres = [&](int n, double h) {
        std::vector<double> xi;
        for (int k = n - plan.kept(n); k < n; ++k) xi.push_back((k - 0.5 * (n - 1)) * h);
        return xi;
    };
    pupil.xi_r = centres(plan.nr, pupil.hr);
    pupil.xi_t = centres(plan.nt, pupil.ht);
    const size_t nr = pupil.xi_r.size(), nt = pupil.xi_t.size();
    pupil.open.resize(nr * nt);
    constexpr int kSub = 4;  // sub-sampled coverage of the rotated cell
    for (size_t ir = 0; ir < nr; ++ir)
        for (size_t it = 0; it < nt; ++it) {
            double open = 0;
            for (int s = 0; s < kSub * kSub; ++s) {
                const double r = pupil.xi_r[ir] + ((s % kSub) + 0.5 - 0.5 * kSub) * pupil.hr / kSub;
                const double t = pupil.xi_t[it] + ((s / kSub) + 0.5 - 0.5 * kSub) * pupil.ht / kSub;
                const double x = r * g.er_x - t * g.er_y, y = r * g.er_y + t * g.er_x;
                open += q.aperture.transmission(-x, y);  // (x, y): image (column, row); pupil +x lands at column -x
            }
            pupil.open[ir * nt + it] = float(open / (kSub * kSub));
        }
    return pupil;
}

// Columns of the stages' register blocks: the tangential matrix's rows and the intermediate's are
// padded (with zeros) to a whole number of them.
constexpr int kBlockColumns = 8;

// One axis's matrix M[o][p] (see above), real and imaginary parts: by output, row o at
// [o * pupil cells], or by pupil cell, row p at [p * `stride`] (the outputs padded to whole blocks).
struct AxisMatrix {
    std::vector<float> re, im;
};
enum class MatrixRows { by_output, by_pupil_cell };

// The axis's matrix for film offsets d_o = (o - offset) step whose frequency is
// mu_o = d_o stretch / (lambda f).
AxisMatrix axis_matrix(const std::vector<double>& xi, double rate, const FieldPsfRequest& q, const MftPlan& plan,
                       double stretch, MatrixRows rows) {
    const int m = plan.grid(), offset = plan.mirrored ? 0 : plan.half;
    const size_t n = xi.size(), stride = size_t(m + kBlockColumns - 1) / kBlockColumns * kBlockColumns;
    const size_t size = rows == MatrixRows::by_output ? size_t(m) * n : n * stride;
    AxisMatrix matrix{std::vector<float>(size), std::vector<float>(size)};
    auto at = [&](int o, size_t p) { return rows == MatrixRows::by_output ? size_t(o) * n + p : p * stride + o; };
    // Along o the phase xi mu steps by a fixed amount, so exp(-2 pi i xi mu) is the previous
    // column's times that step's: a complex multiply where a sine and a cosine were (written
    // out: std::complex's keeps a NaN-recovery call). In double, m < 2^12 steps drift below
    // 1e-12 of a turn.
    const double dmu = plan.step * stretch / (q.wavelength * q.film_distance);
    std::vector<double> chirp_re(n), chirp_im(n), turn_re(n), turn_im(n), step_re(n), step_im(n);
    for (size_t p = 0; p < n; ++p) {
        const std::complex<double> chirp = std::polar(1.0, M_PI * std::remainder(rate * xi[p] * xi[p] / q.wavelength, 2.0));
        const std::complex<double> turn = std::polar(1.0, -2 * M_PI * std::remainder(xi[p] * (-offset) * dmu, 1.0));
        const std::complex<double> step = std::polar(1.0, -2 * M_PI * std::remainder(xi[p] * dmu, 1.0));
        chirp_re[p] = chirp.real();
        chirp_im[p] = chirp.imag();
        turn_re[p] = turn.real();
        turn_im[p] = turn.imag();
        step_re[p] = step.real();
        step_im[p] = step.imag();
    }
    for (int o = 0; o < m; ++o)
        for (size_t p = 0; p < n; ++p) {
            double er, ei;
            if (plan.mirrored) {
                er = 2 * turn_re[p] * chirp_re[p];
                ei = 2 * turn_re[p] * chirp_im[p];
            } else {
                er = turn_re[p] * chirp_re[p] - turn_im[p] * chirp_im[p];
                ei = turn_re[p] * chirp_im[p] + turn_im[p] * chirp_re[p];
            }
            matrix.re[at(o, p)] = float(er);
            matrix.im[at(o, p)] = float(ei);
            const double tr = turn_re[p] * step_re[p] - turn_im[p] * step_im[p];
            turn_im[p] = turn_re[p] * step_im[p] + turn_im[p] * step_re[p];
            turn_re[p] = tr;
        }
    return matrix;
}

// The output grid's columns [lo[o], hi[o]) of each row o that the pixel averages read; the others
// are left zero.
struct ReadColumns {
    std::vector<int> lo, hi;
};

// The pixel averages read the grid's four nodes round each point, so at most sqrt(2) steps from
// a point; the points fill the square |x|, |y| <= extent (grid steps, image axes), and a node is
// read only if it lies within that square widened by 1.5 steps, node (r, t) being at
// (x, y) = r er + t (-er_y, er_x). Mirrored, node (r, t) stands for (+-r, +-t) and the square's
// point symmetry leaves (r, t) and (r, -t). A square at any rotation leaves about half the grid
// unread.
ReadColumns read_columns(const MftPlan& plan, const FieldGeometry& g, double extent) {
    const int m = plan.grid();
    const double offset = plan.mirrored ? 0 : plan.half, wide = extent + 1.5;
    ReadColumns read{std::vector<int>(m, 0), std::vector<int>(m, 0)};
    for (int o = 0; o < m; ++o) {
        const double r = o - offset;
        // |r er_x - t er_y| <= wide and |r er_y + t er_x| <= wide: t within two intervals
        double lo = -INFINITY, hi = INFINITY;
        auto within = [&](double base, double slope) {  // |base + t slope| <= wide
            if (std::fabs(slope) < 1e-12) {
                if (std::fabs(base) > wide) lo = INFINITY;
                return;
            }
            const double a = (-wide - base) / slope, b = (wide - base) / slope;
            lo = std::max(lo, std::min(a, b));
            hi = std::min(hi, std::max(a, b));
        };
        within(r * g.er_x, -g.er_y);
        within(r * g.er_y, g.er_x);
        if (lo > hi) continue;
        if (plan.mirrored) {  // (r, t) or (r, -t) within: |t| <= max(hi, -lo)
            hi = std::max(hi, -lo);
            lo = 0;
            if (hi < 0) continue;
        }
        read.lo[o] = std::clamp(int(std::floor(lo + offset)), 0, m);
        read.hi[o] = std::clamp(int(std::ceil(hi + offset)) + 1, 0, m);
    }
    return read;
}

// The tangential transform: tmp[ir][ot] = sum_it open[ir][it] M_t[ot][it] (M_t by pupil cell,
// `stride` outputs a row), four pupil rows by eight outputs at a time held in registers as in
// radial_power, each value's terms added in the order of it.
__attribute__((target_clones("avx2", "default"))) void tangential_stage(const float* open, int nr, int nt,
                                                                         const AxisMatrix& mt, size_t stride,
                                                                         float* tmp_re, float* tmp_im) {
    constexpr int kRows = 4, kCols = kBlockColumns;
    typedef float Lanes __attribute__((vector_size(kCols * sizeof(float))));
    for (int r0 = 0; r0 < nr; r0 += kRows)
        for (size_t c0 = 0; c0 < stride; c0 += kCols) {
            const float* row[kRows];
            for (int k = 0; k < kRows; ++k) row[k] = &open[size_t(std::min(r0 + k, nr - 1)) * nt];
            Lanes vr[kRows] = {}, vi[kRows] = {};
            for (int it = 0; it < nt; ++it) {
                Lanes br, bi;
                std::memcpy(&br, &mt.re[size_t(it) * stride + c0], sizeof br);
                std::memcpy(&bi, &mt.im[size_t(it) * stride + c0], sizeof bi);
                for (int k = 0; k < kRows; ++k) {
                    vr[k] += row[k][it] * br;
                    vi[k] += row[k][it] * bi;
                }
            }
            for (int k = 0; k < std::min(kRows, nr - r0); ++k) {
                std::memcpy(&tmp_re[size_t(r0 + k) * stride + c0], &vr[k], sizeof vr[k]);
                std::memcpy(&tmp_im[size_t(r0 + k) * stride + c0], &vi[k], sizeof vi[k]);
            }
        }
}

// The radial transform and its power: power[or][ot] = |sum_ir M_r[or][ir] tmp[ir][ot]|^2, four
// output rows by eight columns at a time held in registers, in GCC's vector extension (one AVX
// register, or two SSE ones in the baseline clone); each value's terms are added in the same
// order as one row at a time, so the sums are the same. Only the blocks that hold columns the
// pixel averages read. tmp's rows are `stride` long (m padded to whole blocks); a block's rows
// past the last repeat it, and what they and the padding give is not written.
__attribute__((target_clones("avx2", "default"))) void radial_power(const AxisMatrix& mr, const float* tmp_re,
                                                                     const float* tmp_im, int nr, int m,
                                                                     size_t stride, const ReadColumns& read,
                                                                     float* power) {
    constexpr int kRows = 4, kCols = kBlockColumns;
    typedef float Lanes __attribute__((vector_size(kCols * sizeof(float))));
    for (int o0 = 0; o0 < m; o0 += kRows) {
        int lo = m, hi = 0;
        for (int k = 0; k < std::min(kRows, m - o0); ++k)
            if (read.lo[o0 + k] < read.hi[o0 + k]) {
                lo = std::min(lo, read.lo[o0 + k]);
                hi = std::max(hi, read.hi[o0 + k]);
            }
        for (int c0 = lo / kCols * kCols; c0 < hi; c0 += kCols) {
            const float *row_re[kRows], *row_im[kRows];
            for (int k = 0; k < kRows; ++k) {
                row_re[k] = &mr.re[size_t(std::min(o0 + k, m - 1)) * nr];
                row_im[k] = &mr.im[size_t(std::min(o0 + k, m - 1)) * nr];
            }
            Lanes vr[kRows] = {}, vi[kRows] = {};
            for (int ir = 0; ir < nr; ++ir) {
                Lanes br, bi;
                std::memcpy(&br, tmp_re + size_t(ir) * stride + c0, sizeof br);
                std::memcpy(&bi, tmp_im + size_t(ir) * stride + c0, sizeof bi);
                for (int k = 0; k < kRows; ++k) {
                    const float ar = row_re[k][ir], ai = row_im[k][ir];
                    vr[k] += ar * br - ai * bi;
                    vi[k] += ar * bi + ai * br;
                }
            }
            for (int k = 0; k < std::min(kRows, m - o0); ++k)
                for (int j = 0; j < std::min(kCols, m - c0); ++j)
                    power[size_t(o0 + k) * m + c0 + j] = vr[k][j] * vr[k][j] + vi[k][j] * vi[k][j];
        }
    }
}

// |Q|^2 on the output grid (grid x grid, rows radial): tmp[ir][ot] = sum_it open[ir][it]
// M_t[ot][it], then Q[or][ot] = sum_ir M_r[or][ir] tmp[ir][ot].
std::vector<float> transform_power(const PupilGrid& pupil, const AxisMatrix& mr, const AxisMatrix& mt, int m,
                                   const ReadColumns& read) {
    const int nr = int(pupil.xi_r.size()), nt = int(pupil.xi_t.size());
    const size_t stride = size_t(m + kBlockColumns - 1) / kBlockColumns * kBlockColumns;
    std::vector<float> tmp_re(nr * stride), tmp_im(nr * stride);
    tangential_stage(pupil.open.data(), nr, nt, mt, stride, tmp_re.data(), tmp_im.data());
    std::vector<float> power(size_t(m) * m);
    radial_power(mr, tmp_re.data(), tmp_im.data(), nr, m, stride, read, power.data());
    return power;
}

// |Q|^2 on the (r, t) grid, read by bilinear interpolation (zero beyond it); `density` times it
// is the power per film area.
struct FilmGrid {
    const MftPlan& plan;
    std::vector<float> power;  // grid x grid, rows radial
    double density;
};

// The film grid at the points (x[p], y), p in [first, last), added to sum[p]; x and y in grid
// steps along the image's columns and rows, (er_x, er_y) the radial axis. Eight points at a time
// in GCC's vector extension (one AVX register, two SSE ones in the baseline clone), in float: a
// point's cell and its place within it to 2^-24 of the grid's extent (the kernel moves by about
// 1e-7 of its sum); a point off the grid reads a clamped cell and is replaced by zero. The
// last few points take the same arithmetic one at a time.
__attribute__((target_clones("avx2", "default"))) void film_row(const FilmGrid& film, float er_x, float er_y,
                                                                 const float* x, float y, int first, int last,
                                                                 float* sum) {
    constexpr int kLanes = 8;
    typedef float Lanes __attribute__((vector_size(kLanes * sizeof(float))));
    typedef int Indices __attribute__((vector_size(kLanes * sizeof(int))));
    const int m = film.plan.grid();
    const bool mirrored = film.plan.mirrored;
    const float offset = mirrored ? 0.0f : float(film.plan.half), top = float(m - 1);
    const float* d = film.power.data();
    auto one = [&](float xp) {
        float r = xp * er_x + y * er_y, t = y * er_x - xp * er_y;
        if (mirrored) {
            r = std::fabs(r);
            t = std::fabs(t);
        }
        const float fr = r + offset, ft = t + offset;
        if (!(fr >= 0 && ft >= 0 && fr < top && ft < top)) return 0.0f;
        const int i0 = int(fr), j0 = int(ft);
        const float a = fr - float(i0), b = ft - float(j0);
        const float* c = &d[size_t(i0) * m + j0];
        return (1 - a) * ((1 - b) * c[0] + b * c[1]) + a * ((1 - b) * c[m] + b * c[m + 1]);
    };
    int p = first;
    for (; p + kLanes <= last; p += kLanes) {
        Lanes xp;
        std::memcpy(&xp, x + p, sizeof xp);
        Lanes r = xp * er_x + y * er_y, t = y * er_x - xp * er_y;
        if (mirrored) {
            r = r < 0 ? -r : r;
            t = t < 0 ? -t : t;
        }
        const Lanes fr = r + offset, ft = t + offset;
        const Indices inside = (fr >= 0) & (ft >= 0) & (fr < top) & (ft < top);
        const Lanes zero = {}, last_cell = zero + (top - 1);
        const Indices i0 = __builtin_convertvector(fr > 0 ? (fr < last_cell ? fr : last_cell) : zero, Indices);
        const Indices j0 = __builtin_convertvector(ft > 0 ? (ft < last_cell ? ft : last_cell) : zero, Indices);
        const Lanes a = fr - __builtin_convertvector(i0, Lanes), b = ft - __builtin_convertvector(j0, Lanes);
        Lanes d00, d01, d10, d11;
        for (int l = 0; l < kLanes; ++l) {
            const float* c = &d[size_t(i0[l]) * m + size_t(j0[l])];
            d00[l] = c[0];
            d01[l] = c[1];
            d10[l] = c[m];
            d11[l] = c[m + 1];
        }
        const Lanes v = (1 - a) * ((1 - b) * d00 + b * d01) + a * ((1 - b) * d10 + b * d11);
        Lanes into;
        std::memcpy(&into, sum + p, sizeof into);
        into += inside ? v : zero;
        std::memcpy(sum + p, &into, sizeof into);
    }
    for (; p < last; ++p) sum[p] += one(x[p]);
}

// The grid is zero beyond |r|, |t| < half steps, so beyond |x|, |y| < sqrt(2) half steps at any
// rotation: the film offset (m) beyond which the pixel averages' points read nothing.
double grid_reach(const MftPlan& plan) { return std::sqrt(2.0) * (plan.half + 1) * plan.step; }

// Each kernel pixel's power: the area average of the film grid over the pixel (points x
// points bilinear samples) times the pixel's area.
std::vector<float> average_over_pixels(const FieldPsfRequest& q, const FieldGeometry& g, const FilmGrid& film) {
    const int w = 2 * q.radius + 1, sub = film.plan.points;
    std::vector<float> weight(size_t(w) * w, 0.0f);
    const double pixel_area = q.pixel_pitch * q.pixel_pitch;
    // the points' image offsets (column or row) in metres on the film, kernel pixel k's at
    // [k sub, (k + 1) sub), and in grid steps
    std::vector<double> offset(size_t(w) * sub);
    for (int k = 0; k < w; ++k)
        for (int s = 0; s < sub; ++s) offset[size_t(k) * sub + s] = (k - q.radius + (s + 0.5) / sub - 0.5) * q.pixel_pitch;
    std::vector<float> steps(offset.size());
    for (size_t k = 0; k < offset.size(); ++k) steps[k] = float(offset[k] / film.plan.step);
    // Only the points within the grid's reach are summed (pixels far wider than the PSF - a
    // long film distance, a tiny frame - would otherwise cost points^2 each).
    const double reach = grid_reach(film.plan);
    // the points of [begin, end) within that reach: [first, last) (the offsets increase)
    auto within = [&](int begin, int end, int& first, int& last) {
        first = begin;
        last = end;
        while (first < end && offset[first] < -reach) ++first;
        while (last > first && offset[last - 1] > reach) --last;
    };
    const int n = w * sub;
    int first, last;  // along a row
    within(0, n, first, last);
    std::vector<int> p0(w), p1(w);  // pixel k's
    for (int k = 0; k < w; ++k) within(k * sub, (k + 1) * sub, p0[k], p1[k]);
    // each pixel row's points summed down its rows of points (at most `points` in each
    // column's float sum), then each pixel's columns of points in double. A mirrored plan's
    // |Q|^2 is even in r and in t, so the PSF is point-symmetric about the kernel's centre (its
    // points at (-x, -y) read the grid where those at (x, y) do): the rows to the centre, and
    // the others as their point images.
    std::vector<float> column(n);
    const double scale = film.density / (sub * sub) * pixel_area;
    const int rows = film.plan.mirrored ? q.radius + 1 : w;
    for (int b = 0; b < rows; ++b) {
        std::fill(column.begin() + first, column.begin() + last, 0.0f);
        for (int pb = p0[b]; pb < p1[b]; ++pb)
            film_row(film, float(g.er_x), float(g.er_y), steps.data(), steps[pb], first, last, column.data());
        for (int a = 0; a < w; ++a) {
            double sum = 0;
            for (int pa = p0[a]; pa < p1[a]; ++pa) sum += column[pa];
            weight[size_t(b) * w + a] = float(sum * scale);
        }
    }
    for (int b = rows; b < w; ++b)
        for (int a = 0; a < w; ++a) weight[size_t(b) * w + a] = weight[size_t(w - 1 - b) * w + (w - 1 - a)];
    return weight;
}

}  // namespace

std::vector<float> kernel_by_mft(const FieldPsfRequest& q, const FieldGeometry& g, const MftPlan& plan) {
    thread_local SampledPupils<PupilGrid> pupils;
    const PupilGrid& pupil =
        pupils.get(q.aperture,
                 {q.aperture.diameter, double(plan.nr), double(plan.nt), double(plan.mirrored),
                  plan.mirrored ? 0.0 : g.er_x, plan.mirrored ? 0.0 : g.er_y},
                 [&] { return sample_pupil(q, g, plan); });
    const double c = g.c;
    const AxisMatrix mr = axis_matrix(pupil.xi_r, g.ar, q, plan, c * c * c, MatrixRows::by_output);
    const AxisMatrix mt = axis_matrix(pupil.xi_t, g.at, q, plan, c, MatrixRows::by_pupil_cell);
    // the pixel averages' points reach (radius + 1/2) pixels from the centre, or the grid's
    // reach where that is less (average_over_pixels), in grid steps
    const double extent = std::min((q.radius + 0.5) * q.pixel_pitch, grid_reach(plan)) / plan.step;
    // Power per film area. The transform is Q(mu) = sum_p Q_p exp(-2 pi i xi_p mu) without
    // its cell area hr ht; Parseval gives int |Q|^2 d^2mu = aperture area, and d^2mu =
    // c^4 / (lambda f)^2 d^2(film), so the fraction of the transmitted power per film area is
    // |Q|^2 (hr ht)^2 c^4 / ((lambda f)^2 area).
    const double density = std::pow(pupil.hr * pupil.ht * c * c / (q.wavelength * q.film_distance), 2) / g.area;
    const FilmGrid film{plan, transform_power(pupil, mr, mt, plan.grid(), read_columns(plan, g, extent)), density};
    return average_over_pixels(q, g, film);
}

}  // namespace wavecam::detail
