#include "optics/fresnel_transfer.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <string>
#include <vector>

#include "fft/column_fft.h"
#include "fft/line_fft.h"

namespace wavecam::detail {

// ---- Many zones: Fresnel transfer function on a grid at a fraction of a film pixel ----------
//
// Completing the square in wavecam/fresnel_psf.h's phase, |PSF(d)| = |(P * K)(s)| with
// s = d / (f alpha) (the shadow is the pupil magnified by f alpha = 1 + f/z, in every
// direction) and the chirp
// K(xi) = exp(i pi/lambda (ar xi_r^2 + at xi_t^2)): Fresnel propagation of the pupil over the
// distances z_r = 1/ar, z_t = 1/at, done here as FFT(P) x H, H(nu) = exp(-i pi lambda (z_r nu_r^2
// + z_t nu_t^2)) (Goodman, Introduction to Fourier Optics, 3rd ed., sec. 5.1). |H| = 1, so the
// grid's power equals the sampled pupil's (Parseval) and nothing is renormalised.
// Sampling, on a grid of pitch h (pupil plane) = film pitch / (f alpha), in image axes:
//  - film: h f alpha = pixel / sub, so each kernel pixel sums sub x sub grid points (its area
//    average) and the cost is set by the kernel's extent in film pixels, not by the zone count.
//  - pupil: each cell holds its open fraction (the pupil box-filtered over the cell), and the
//    box's sinc(nu h) is divided out of the spectrum, so the spectrum is the true one up to
//    frequency 1/(2h); beyond that it aliases. Frequency nu leaves the pupil at a lateral
//    shift lambda z nu, so what is misplaced is light diffracted farther than lambda z_r / (2h)
//    (~ 8 film pixels at 3 cells per pixel with the optimum's lambda f / pixel^2 = 5.4): the far
//    tail of the pupil's spectrum, at most ~ 4 h / (pi^2 D) of the power for a sharp edge (the
//    Airy tail 2 / (pi x) at nu = 1/(2h)); kMinCellsAcross cells across the pupil keep that
//    below 0.7%. It includes the rim's edge wave where it crosses farther than that, e.g. its
//    focus on the axis of a round pinhole whose shadow is wider than ~16 px: at 2.5 mm, f = 50
//    mm (a 35 px shadow) the central 9 pixels get 1.8% less than the exact sum with 9 x 9 film
//    points per pixel, the central 6 px radius 0.7% less; the total is within 0.3%.
//  - wrap-around: the grid is periodic, so the inverse transform convolves the pupil with the
//    chirp band-limited to the grid and summed over the period's copies. Along the column axis
//    the band-limited chirp reaches shift = lambda (A + |C|) / (2h), along the row axis lambda
//    (B + |C|) / (2h) (A, B, C the quadratic form's coefficients, see transfer() below): the
//    lateral shift of the grid's highest frequency on that axis, whatever the other axis's.
//    A pupil point (half-width a) and a kernel pixel (half-width E) are at most E + a apart
//    on an axis, so a copy one period L away stays off every such pair while L >= E + a +
//    shift. (H's phase may then step by more than pi between frequency samples: those steps
//    are the copies, which land outside the kernel.) The band edge rings beyond `shift`,
//    decaying as the distance: kWrapMargin Fresnel lengths sqrt(lambda z_r) more keep the
//    kernel within ~5e-4 of its peak of one on a grid twice as wide at 1080p, 2e-3 on coarse
//    pixels (0.6-5 mm, 400-700 nm, on axis and at 50deg).
// This is the many-zone regime's tool: its grid is never coarser than the chirp needs there;
// with few zones (small pinholes) the grid those conditions demand is large and the matrix
// Fourier transform is cheaper; field_psf_kernel picks the cheaper of the two.
constexpr int kMinCellsAcross = 64;
constexpr double kWrapMargin = 6;

namespace {

// Cells holding their open fraction (the pupil box-filtered over a cell of width h) multiply
// the pupil's spectrum by sinc(nu h) per axis; the transfer function divides it out, which
// restores the near tail (light diffracted a few pixels past the rim, ~0.5% of the power at
// 4x the optimum). sinc(x) = sin(pi x) / (pi x).
double box_response(double nu_h) { return std::fabs(nu_h) < 1e-9 ? 1.0 : std::sin(M_PI * nu_h) / (M_PI * nu_h); }

}  // namespace

TransferPlan plan_transfer(const FieldPsfRequest& q, const FieldGeometry& g) {
    TransferPlan p;
    const double fa = q.film_distance * g.alpha;
    p.sub = std::max(q.subsamples, int(std::min(std::ceil(kMinCellsAcross * q.pixel_pitch / (g.span * fa)), 1e6)));
    // a point-symmetric pupil on a grid with a point at the centre (odd sub) gives a
    // point-symmetric field: half of the inverse transform is the other half mirrored
    p.symmetric = point_symmetric(q.aperture);
    if (p.symmetric && p.sub % 2 == 0) ++p.sub;
    p.h = q.pixel_pitch / (p.sub * fa);
    // the larger axis's A + |C| or B + |C| (see transfer())
    const double zr = 1.0 / g.ar, zt = 1.0 / g.at, C = std::fabs(g.er_x * g.er_y * (zr - zt));
    const double rate = std::max(zr * g.er_x * g.er_x + zt * g.er_y * g.er_y, zr * g.er_y * g.er_y + zt * g.er_x * g.er_x) + C;
    const double shift = q.wavelength * rate / (2 * p.h), margin = kWrapMargin * std::sqrt(q.wavelength * zr);
    const double kernel_half = (q.radius + 0.5) * q.pixel_pitch / fa, pupil_half = 0.5 * g.span;
    const double period = kernel_half + pupil_half + shift + margin;
    // (a grid beyond 2^28 points across is never cheaper than the matrix transform: kept
    // finite, it only loses the cost comparison)
    p.n = detail::fft_friendly_size(int(std::min(std::ceil(period / p.h) + 2, double(1 << 29))));
    return p;
}

namespace {

// The pupil's spectrum on an n x n grid of pitch h: it depends on neither the wavelength nor
// the field angle (the chirp is all in the transfer function), so a table's requests at one
// depth share it. Each thread keeps the last kSpectraKept; a request whose grid must be at
// least n reuses the narrowest kept spectrum up to kWiderGrid n^2 in area (a wider period only
// moves the wrap-around farther away): its inverse transform then costs at most that much
// more, where a new forward transform would cost about twice the inverse one.
constexpr double kWiderGrid = 1.25;

struct PupilSpectrum {
    std::string aperture;
    const void* mask = nullptr;
    double diameter = 0, h = 0, o = 0;
    int n = 0;
    long used = 0;  // when last used, for replacing the least recently used
    std::vector<std::complex<float>> value;  // row ky, column kx
    bool serves(const Aperture& a, double hh, double oo, int n_min) const {
        return a.name() == aperture && a.mask.get() == mask && a.diameter == diameter && hh == h && oo == o &&
               n >= n_min && double(n) * n <= kWiderGrid * n_min * n_min;
    }
};

// Scratch that only grows: a thread's arrays keep their pages from one request to the next (a
// fresh array would zero-fill and fault in megabytes a request).
std::complex<float>* scratch(std::vector<std::complex<float>>& v, size_t size) {
    if (v.size() < size) v.resize(size);
    return v.data();
}

const PupilSpectrum& pupil_spectrum(const FieldPsfRequest& q, const FieldGeometry& g, const TransferPlan& plan,
                                    double o) {
    thread_local PupilSpectrum kept_spectra[kSpectraKept];
    thread_local long clock = 0;
    thread_local std::vector<std::complex<float>> work;
    PupilSpectrum* best = nullptr;
    for (PupilSpectrum& s : kept_spectra)
        if (s.serves(q.aperture, plan.h, o, plan.n) && (!best || s.n < best->n)) best = &s;
    if (best) {
        best->used = ++clock;
        return *best;
    }
    PupilSpectrum& kept = *std::min_element(std::begin(kept_spectra), std::end(kept_spectra),
                                            [](const PupilSpectrum& x, const PupilSpectrum& y) { return x.used < y.used; });
    // the pupil's open fractions, cell (ix, iy) centred at ((ix - n/2 + o) h, (iy - n/2 + o) h)
    // in image axes; (x, y): image (column, row), pupil +x lands at column -x (as in the matrix
    // transform)
    const int n = plan.n;
    const double h = plan.h;
    const int reach = std::min(n / 2 - 1, int(std::ceil(0.5 * g.span / h)) + 1), row0 = n / 2 - reach;
    std::vector<std::complex<float>>& pupil = kept.value;
    pupil.assign(size_t(n) * n, 0.0f);
    for (int iy = row0; iy <= n / 2 + reach; ++iy)
        for (int ix = n / 2 - reach; ix <= n / 2 + reach; ++ix) {
            const double x = (ix - n / 2 + o) * h, y = (iy - n / 2 + o) * h;
            double cx, cy;
            pupil[size_t(iy) * n + ix] = float(q.aperture.coverage(-x - 0.5 * h, -x + 0.5 * h, y - 0.5 * h, y + 0.5 * h, cx, cy));
        }
    // the rows (the others are zero), then down the columns: the spectrum in natural order, row
    // ky, column kx
    detail::LineFft(n, false).transform(2 * reach + 1, [&](int k) { return &pupil[size_t(row0 + k) * n]; });
    ColumnFft(n, false).transform(pupil.data(), scratch(work, size_t(n) * n), n, 0, n);
    kept.aperture = q.aperture.name();
    kept.mask = q.aperture.mask.get();
    kept.diameter = q.aperture.diameter;
    kept.h = h;
    kept.o = o;
    kept.n = n;
    kept.used = ++clock;
    return kept;
}

// The spectrum times the transfer function with the pupil cells' box response divided out,
// columns kx < `lines` of each row ky (frequency nu = k / L, k taken in [-n/2, n/2)), into
// field[ky * lines + kx]. In image axes the exponent is a quadratic form, -pi lambda (A nx^2 +
// B ny^2 + 2 C nx ny) with A = zr ex^2 + zt ey^2, B = zr ey^2 + zt ex^2, C = ex ey (zr - zt)
// (e the radial unit vector): a factor per axis times exp(-2 pi i lambda C nx ny), which along a
// row is a geometric sequence in kx (complex multiplications instead of a sine and cosine a
// point; kCrossChains interleaved sequences, so that the loop vectorises).
constexpr int kCrossChains = 8;
__attribute__((target_clones("avx2", "default"))) void transfer(const PupilSpectrum& spectrum, int lines,
                                                                double wavelength, const FieldGeometry& g,
                                                                std::complex<float>* field) {
    const int n = spectrum.n;
    const double h = spectrum.h;
    const double L = n * h, zr = 1.0 / g.ar, zt = 1.0 / g.at;
    const double A = zr * g.er_x * g.er_x + zt * g.er_y * g.er_y, B = zr * g.er_y * g.er_y + zt * g.er_x * g.er_x;
    const double C = g.er_x * g.er_y * (zr - zt);
    auto signed_index = [n](int k) { return k < n / 2 ? k : k - n; };
    auto axis = [&](double rate) {
        std::vector<std::complex<double>> f(n);
        for (int k = 0; k < n; ++k) {
            const double nu = signed_index(k) / L;
            f[k] = std::polar(1.0 / box_response(nu * h), -M_PI * wavelength * rate * nu * nu);
        }
        return f;
    };
    const std::vector<std::complex<double>> fx = axis(A), fy = axis(B);
    // (complex products written out: std::complex's keeps a NaN-recovery call that stops the
    // loops vectorising; the same values otherwise)
    std::vector<double> re(lines), im(lines);
    for (int ky = 0; ky < n; ++ky) {
        // fy exp(i beta kx') for kx' = 0 ... n/2 - 1, then -n/2 ...: each run of kx' from its
        // first value, kCrossChains values apart (fy a constant factor of the sequence), then
        // times fx
        const double beta = -2 * M_PI * wavelength * C * signed_index(ky) / (L * L);
        for (int run0 : {0, n / 2}) {
            const int run1 = run0 == 0 ? std::min(lines, n / 2) : lines;
            if (run0 >= run1) continue;
            for (int k = run0; k < std::min(run1, run0 + kCrossChains); ++k) {
                const std::complex<double> z = fy[ky] * std::polar(1.0, beta * signed_index(k));
                re[k] = z.real();
                im[k] = z.imag();
            }
            const double sr = std::cos(beta * kCrossChains), si = std::sin(beta * kCrossChains);
#pragma GCC ivdep
            for (int k = run0 + kCrossChains; k < run1; ++k) {
                re[k] = re[k - kCrossChains] * sr - im[k - kCrossChains] * si;
                im[k] = re[k - kCrossChains] * si + im[k - kCrossChains] * sr;
            }
        }
        const float* in = reinterpret_cast<const float*>(&spectrum.value[size_t(ky) * n]);
        float* out = reinterpret_cast<float*>(&field[size_t(ky) * lines]);
        const double* x = reinterpret_cast<const double*>(fx.data());
        for (int kx = 0; kx < lines; ++kx) {
            const float br = float(x[2 * kx] * re[kx] - x[2 * kx + 1] * im[kx]);
            const float bi = float(x[2 * kx] * im[kx] + x[2 * kx + 1] * re[kx]);
            const float ar = in[2 * kx], ai = in[2 * kx + 1];
            out[2 * kx] = ar * br - ai * bi;
            out[2 * kx + 1] = ar * bi + ai * br;
        }
    }
}

// The kernel's image rows, one per column of `rows`: window[kx * rows + k] = the row y[k]'s value
// at frequency kx, for kx >= lines the mirror's (row mirror_y[k] at n - kx). Blocks of kRowBlock
// rows: the reads run along their rows, the writes fill a cache line at a time; each value
// moved as one 8-byte word (a complex<float> copy compiles to two scalar moves).
void gather_rows(const std::complex<float>* field, int n, int lines, const std::vector<int>& y,
                 const std::vector<int>& mirror_y, std::complex<float>* window) {
    constexpr int kRowBlock = 16;
    const int rows = int(y.size());
    const char* from[kRowBlock];
    const char* mirror[kRowBlock];
    char* to = reinterpret_cast<char*>(window);
    constexpr size_t kValue = sizeof(std::complex<float>);
    for (int k0 = 0; k0 < rows; k0 += kRowBlock) {
        const int k1 = std::min(rows, k0 + kRowBlock), m = k1 - k0;
        for (int k = 0; k < m; ++k) {
            from[k] = reinterpret_cast<const char*>(field + size_t(y[k0 + k]) * lines);
            mirror[k] = reinterpret_cast<const char*>(field + size_t(mirror_y[k0 + k]) * lines);
        }
        for (int kx = 0; kx < lines; ++kx)
            for (int k = 0; k < m; ++k)
                std::memcpy(to + (size_t(kx) * rows + k0 + k) * kValue, from[k] + size_t(kx) * kValue, kValue);
        for (int kx = lines; kx < n; ++kx)
            for (int k = 0; k < m; ++k)
                std::memcpy(to + (size_t(kx) * rows + k0 + k) * kValue, mirror[k] + size_t(n - kx) * kValue, kValue);
    }
}

}  // namespace

std::vector<float> kernel_by_transfer(const FieldPsfRequest& q, const FieldGeometry& g, const TransferPlan& plan) {
    const int sub = plan.sub, R = q.radius;
    const double h = plan.h;
    // Grid index i sits at (i - n/2 + o) h, o = 1/2 for even sub, so that kernel pixel a's
    // sub points are indices n/2 + a sub - sub/2 + [0, sub).
    const double o = sub % 2 == 0 ? 0.5 : 0.0;
    const PupilSpectrum& spectrum = pupil_spectrum(q, g, plan, o);
    const int n = spectrum.n;
    // A point-symmetric pupil centred on index (0, 0) modulo n (odd sub) has a spectrum even in
    // (kx, ky); so has the transfer function, so the field is even too: u(-x, -y) = u(x, y).
    // Then column -kx is column kx upside down, only columns [0, n/2] are transformed, and only
    // the kernel's lower half (rows b >= 0) is computed, its upper half being it turned 180deg.
    const bool even = plan.symmetric && o == 0.0;
    const int lines = even ? n / 2 + 1 : n;
    // the image rows the kernel reads (kx >= lines: the mirror's)
    const int b0 = even ? 0 : -R;
    const int row0 = n / 2 + b0 * sub - sub / 2, rows = (R - b0 + 1) * sub;
    auto wrap = [n](int i) { return ((i % n) + n) % n; };
    std::vector<int> y(rows), mirror_y(rows);
    for (int k = 0; k < rows; ++k) {
        y[k] = wrap(row0 + k);
        mirror_y[k] = wrap(-y[k]);
    }
    // scratch, reused: the spectrum's columns kx < lines (row ky), then image row y at frequency
    // kx; the kernel's rows transposed (one column each); the transforms' work
    thread_local std::vector<std::complex<float>> field_scratch, window_scratch, work_scratch;
    std::complex<float>* field = scratch(field_scratch, size_t(n) * lines);
    std::complex<float>* window = scratch(window_scratch, size_t(n) * rows);
    std::complex<float>* work = scratch(work_scratch, size_t(n) * std::max(lines, rows));
    transfer(spectrum, lines, q.wavelength, g, field);
    const ColumnFft inverse(n, true);
    inverse.transform(field, work, lines, 0, lines);  // along ky: image row y, frequency kx
    gather_rows(field, n, lines, y, mirror_y, window);
    inverse.transform(window, work, rows, 0, rows);  // along kx: window[x * rows + k], image column x
    // Each pixel: sum of |U|^2 h^2 over its points / transmitted power (the aperture's area);
    // the unnormalised forward-inverse pair scales by n^2. Column a's points summed per row
    // first (contiguous), then each pixel's sub rows.
    const int w = 2 * R + 1;
    std::vector<double> sum(size_t(w) * w, 0.0), column(rows);
    for (int a = -R; a <= R; ++a) {
        std::fill(column.begin(), column.end(), 0.0);
        for (int t = 0; t < sub; ++t) {
            const std::complex<float>* x = &window[size_t(wrap(n / 2 + a * sub - sub / 2 + t)) * rows];
            for (int k = 0; k < rows; ++k) column[k] += std::norm(x[k]);
        }
        for (int k = 0; k < rows; ++k) sum[size_t(b0 + R + k / sub) * w + (a + R)] += column[k];
    }
    const double scale = h * h / (double(n) * n * double(n) * n) / g.area;
    std::vector<float> weight(size_t(w) * w);
    for (int b = b0; b <= R; ++b)
        for (int a = -R; a <= R; ++a) {
            const float v = float(sum[size_t(b + R) * w + (a + R)] * scale);
            weight[size_t(b + R) * w + (a + R)] = v;
            if (even) weight[size_t(R - b) * w + (R - a)] = v;
        }
    return weight;
}

}  // namespace wavecam::detail
