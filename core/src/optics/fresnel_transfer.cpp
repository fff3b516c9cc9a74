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
    p.mirror_even = p.symmetric && q.aperture.even_in_x() && q.aperture.even_in_y();
    p.h = q.pixel_pitch / (p.sub * fa);
    // the larger axis's A + |C| or B + |C| (see transfer())
    const double zr = 1.0 / g.ar, zt = 1.0 / g.at, C = std::fabs(g.er_x * g.er_y * (zr - zt));
    const double rate = std::max(zr * g.er_x * g.er_x + zt * g.er_y * g.er_y, zr * g.er_y * g.er_y + zt * g.er_x * g.er_x) + C;
    const double shift = q.wavelength * rate / (2 * p.h), margin = kWrapMargin * std::sqrt(q.wavelength * zr);
    const double kernel_half = (q.radius + 0.5) * q.pixel_pitch / fa, pupil_half = 0.5 * g.span;
    const double period = kernel_half + pupil_half + shift + margin;
    // (a grid beyond 2^28 points across is never cheaper than the matrix transform: kept
    // finite, it only loses the cost comparison)
    p.n = std::max(q.transfer_grid, detail::fft_friendly_size(int(std::min(std::ceil(period / p.h) + 2, double(1 << 29)))));
    return p;
}

namespace {

// The pupil's spectrum on an n x n grid of pitch h: it depends on neither the wavelength nor
// the field angle (the chirp is all in the transfer function), so requests at one depth on one
// grid share it (share_transfer_grids gives a table's requests a few common grids). Each thread
// keeps the last kSpectraKept.
struct PupilSpectrum {
    std::string aperture;
    const void* mask = nullptr;
    double diameter = 0, h = 0, o = 0;
    int n = 0;
    long used = 0;  // when last used, for replacing the least recently used
    // A point-symmetric pupil centred on index (0, 0) modulo n has a real, even spectrum (the
    // transform of a real even function): its real part at columns kx <= n/2 is kept, row ky at
    // even_value[ky * (n/2 + 1)], a quarter of the complex grid's bytes. Otherwise the whole
    // spectrum, row ky, column kx.
    bool even = false;
    std::vector<float> even_value;
    std::vector<std::complex<float>> value;
    bool serves(const Aperture& a, double hh, double oo, int nn) const {
        return a.name() == aperture && a.mask.get() == mask && a.diameter == diameter && hh == h && oo == o && nn == n;
    }
};

// Scratch that only grows: a thread's arrays keep their pages from one request to the next (a
// fresh array would zero-fill and fault in megabytes a request).
std::complex<float>* scratch(std::vector<std::complex<float>>& v, size_t size) {
    if (v.size() < size) v.resize(size);
    return v.data();
}

// The spectrum of a pupil even in x and in y about the grid's centre (index n/2, which is index
// 0 modulo n for even n): its rows are real and even, so their spectra are real (and even), and
// so are the columns of those spectra and theirs. Two real lines then share one complex
// transform, one as its real part and one as its imaginary part, and each comes back as that
// part of the result: the rows n/2 - reach ... n/2 in pairs (the others are zero or their
// mirror images), then the columns kx <= n/2 of their spectra in pairs. A third of the
// transforms of the whole grid's rows and half columns. open_fraction(ix, iy): the cell's value.
template <class OpenFraction>
void even_pupil_spectrum(int n, int reach, OpenFraction open_fraction, std::vector<float>& even_value) {
    const int rows = reach + 1, pairs = (rows + 1) / 2, half = n / 2 + 1, packed = (half + 1) / 2;
    thread_local std::vector<std::complex<float>> lines, columns, work;
    // row n/2 - reach + k as part k % 2 of line k / 2; the lines as the columns of an n x pairs
    // array (line p at lines[ix * pairs + p])
    lines.assign(size_t(n) * pairs, 0.0f);
    float* open_parts = reinterpret_cast<float*>(lines.data());
    for (int k = 0; k < rows; ++k)
        for (int ix = n / 2 - reach; ix <= n / 2; ++ix) {
            const float v = open_fraction(ix, n / 2 - reach + k);
            open_parts[2 * (size_t(ix) * pairs + k / 2) + k % 2] = v;
            open_parts[2 * (size_t(n - ix) * pairs + k / 2) + k % 2] = v;  // (ix = n/2: itself)
        }
    const float* line_parts = reinterpret_cast<const float*>(
        ColumnFft(n, false).transform_where(lines.data(), scratch(work, size_t(n) * pairs), pairs, 0, pairs));
    // row iy's spectrum at columns 2j and 2j + 1 as the parts of columns[iy * packed + j] (rows
    // beyond the pupil zero; rows past n/2 their mirror images), moved in blocks of a few
    // lines and columns so that both sides stay in the cache
    constexpr int kBlock = 16;
    columns.assign(size_t(n) * packed, 0.0f);
    float* column_parts = reinterpret_cast<float*>(columns.data());
    for (int k0 = 0; k0 < rows; k0 += kBlock)
        for (int j0 = 0; j0 < packed; j0 += kBlock)
            for (int k = k0; k < std::min(rows, k0 + kBlock); ++k) {
                float* to = column_parts + 2 * size_t(n / 2 - reach + k) * packed;
                for (int kx = 2 * j0; kx < std::min(half, 2 * (j0 + kBlock)); ++kx)
                    to[kx] = line_parts[2 * (size_t(kx) * pairs + k / 2) + k % 2];
            }
    for (int iy = n / 2 + 1; iy <= n / 2 + reach; ++iy)
        std::copy_n(&columns[size_t(n - iy) * packed], packed, &columns[size_t(iy) * packed]);
    const float* spectrum_parts = reinterpret_cast<const float*>(
        ColumnFft(n, false).transform_where(columns.data(), scratch(work, size_t(n) * packed), packed, 0, packed));
    even_value.resize(size_t(n) * half);
    for (int ky = 0; ky < n; ++ky)
        std::copy_n(spectrum_parts + 2 * size_t(ky) * packed, half, &even_value[size_t(ky) * half]);
}

const PupilSpectrum& pupil_spectrum(const FieldPsfRequest& q, const FieldGeometry& g, const TransferPlan& plan,
                                    double o) {
    thread_local PupilSpectrum kept_spectra[kSpectraKept];
    thread_local long clock = 0;
    thread_local std::vector<std::complex<float>> work;
    for (PupilSpectrum& s : kept_spectra)
        if (s.serves(q.aperture, plan.h, o, plan.n)) {
            s.used = ++clock;
            return s;
        }
    PupilSpectrum& kept = *std::min_element(std::begin(kept_spectra), std::end(kept_spectra),
                                            [](const PupilSpectrum& x, const PupilSpectrum& y) { return x.used < y.used; });
    // the pupil's open fractions, cell (ix, iy) centred at ((ix - n/2 + o) h, (iy - n/2 + o) h)
    // in image axes; (x, y): image (column, row), pupil +x lands at column -x (as in the matrix
    // transform)
    const int n = plan.n;
    const double h = plan.h;
    const int reach = std::min(n / 2 - 1, int(std::ceil(0.5 * g.span / h)) + 1), row0 = n / 2 - reach;
    auto open_fraction = [&](int ix, int iy) {
        const double x = (ix - n / 2 + o) * h, y = (iy - n / 2 + o) * h;
        double cx, cy;
        return float(q.aperture.coverage(-x - 0.5 * h, -x + 0.5 * h, y - 0.5 * h, y + 0.5 * h, cx, cy));
    };
    // (cells centred on the axes, o = 0, of an aperture even in x or y: the mirror image's
    // cells, n - ix or n - iy, hold the same fractions)
    const bool mirror_x = o == 0.0 && q.aperture.even_in_x(), mirror_y = o == 0.0 && q.aperture.even_in_y();
    kept.even = plan.symmetric && o == 0.0;
    if (kept.even && plan.mirror_even) {
        even_pupil_spectrum(n, reach, open_fraction, kept.even_value);
        std::vector<std::complex<float>>().swap(kept.value);
    } else {
        thread_local std::vector<std::complex<float>> grid;
        grid.assign(size_t(n) * n, 0.0f);
        for (int iy = row0; iy <= n / 2 + reach; ++iy) {
            std::complex<float>* row = &grid[size_t(iy) * n];
            if (mirror_y && iy > n / 2) {
                std::copy_n(&grid[size_t(n - iy) * n], n, row);
                continue;
            }
            for (int ix = n / 2 - reach; ix <= n / 2 + reach; ++ix)
                row[ix] = mirror_x && ix > n / 2 ? row[n - ix] : open_fraction(ix, iy);
        }
        // the rows (the others are zero), then down the columns: the spectrum in natural order,
        // row ky, column kx (an even spectrum's columns kx <= n/2 only)
        const int columns = kept.even ? n / 2 + 1 : n;
        detail::LineFft(n, false).transform(2 * reach + 1, [&](int k) { return &grid[size_t(row0 + k) * n]; });
        ColumnFft(n, false).transform(grid.data(), scratch(work, size_t(n) * n), n, 0, columns);
        if (kept.even) {
            kept.even_value.resize(size_t(n) * columns);
            for (int ky = 0; ky < n; ++ky)
                for (int kx = 0; kx < columns; ++kx)
                    kept.even_value[size_t(ky) * columns + kx] = grid[size_t(ky) * n + kx].real();
            std::vector<std::complex<float>>().swap(kept.value);
        } else {
            std::vector<float>().swap(kept.even_value);
            kept.value.swap(grid);  // (the grid takes the kept spectrum's old array)
        }
    }
    kept.aperture = q.aperture.name();
    kept.mask = q.aperture.mask.get();
    kept.diameter = q.aperture.diameter;
    kept.h = h;
    kept.o = o;
    kept.n = n;
    kept.used = ++clock;
    return kept;
}

// The spectrum times the transfer function with the pupil cells' box response divided out, a
// block of columns at a time (frequency nu = k / L, k taken in [-n/2, n/2)). In image axes the
// exponent is a quadratic form, -pi lambda (A nx^2 + B ny^2 + 2 C nx ny) with A = zr ex^2 + zt
// ey^2, B = zr ey^2 + zt ex^2, C = ex ey (zr - zt) (e the radial unit vector): a factor per axis
// times exp(-2 pi i lambda C nx ny), which along a row is a geometric sequence in kx (complex
// multiplications instead of a sine and cosine a point; kCrossChains interleaved sequences, so
// that the loop vectorises). A run of columns (kx from 0, or from n/2: the signed index jumps
// there) goes in blocks, each row's sequences carried from one block to the next.
constexpr int kCrossChains = 8;
constexpr int kPrefetchRows = 4;
class TransferFunction {
public:
    // `block`: the width of the blocks apply() is given (a multiple of kCrossChains)
    TransferFunction(const PupilSpectrum& spectrum, double wavelength, const FieldGeometry& g, int block)
        : spectrum_(spectrum), n_(spectrum.n), fx_re_(n_), fx_im_(n_), fy_(n_), beta_(n_), re_(size_t(n_) * kCrossChains),
          im_(size_t(n_) * kCrossChains), step_(n_), block_step_(n_) {
        const double h = spectrum.h, L = n_ * h, zr = 1.0 / g.ar, zt = 1.0 / g.at;
        const double A = zr * g.er_x * g.er_x + zt * g.er_y * g.er_y, B = zr * g.er_y * g.er_y + zt * g.er_x * g.er_x;
        const double C = g.er_x * g.er_y * (zr - zt);
        for (int k = 0; k < n_; ++k) {
            const double nu = signed_index(k) / L, cells = 1.0 / box_response(nu * h);
            const std::complex<double> fx = std::polar(cells, -M_PI * wavelength * A * nu * nu);
            fx_re_[k] = float(fx.real());
            fx_im_[k] = float(fx.imag());
            fy_[k] = std::polar(cells, -M_PI * wavelength * B * nu * nu);
            beta_[k] = -2 * M_PI * wavelength * C * signed_index(k) / (L * L);
            step_[k] = std::polar(1.0f, float(beta_[k] * kCrossChains));
            block_step_[k] = std::polar(1.0, beta_[k] * block);
        }
    }

    // Each row's sequences at columns c0 ... c0 + kCrossChains - 1: fy exp(i beta kx'), kx' the
    // signed index.
    void start(int c0) {
        for (int ky = 0; ky < n_; ++ky) {
            const std::complex<double> c = std::polar(1.0, beta_[ky]);
            std::complex<double> z = fy_[ky] * std::polar(1.0, beta_[ky] * signed_index(c0));
            for (int j = 0; j < kCrossChains; ++j, z *= c) {
                re_[size_t(ky) * kCrossChains + j] = z.real();
                im_[size_t(ky) * kCrossChains + j] = z.imag();
            }
        }
    }

    // Columns [c0, c1) of every row ky into block[ky * (c1 - c0) + kx - c0]; c0 is where start()
    // or the previous block left off, c1 - c0 the block width except at a run's end. Within a
    // block the sequences run in float (a few steps: their rounding stays near 1e-7); each row's
    // start moves on to the next block in double.
    __attribute__((target_clones("avx2", "default"))) void apply(int c0, int c1, std::complex<float>* block) {
        if (spectrum_.even)
            apply_rows<true>(c0, c1, block);
        else
            apply_rows<false>(c0, c1, block);
    }

private:
    // (even: the spectrum is real, row ky at even_value[ky * (n/2 + 1)]). The kCrossChains
    // sequences are one vector of GCC's vector extension (8 floats), so the loop is vectorised
    // whatever the compiler's own analysis finds; complex values are deinterleaved on loading
    // and interleaved on storing.
    template <bool even>
    __attribute__((always_inline)) inline void apply_rows(int c0, int c1, std::complex<float>* block) {
        typedef float Lanes __attribute__((vector_size(4 * kCrossChains)));
        typedef int LaneIndex __attribute__((vector_size(4 * kCrossChains)));
        static_assert(kCrossChains == 8, "the shuffles below take 8 lanes");
        auto load = [](Lanes& v, const float* p) { std::memcpy(&v, p, sizeof v); };
        const int cols = c1 - c0, whole = c0 + cols / kCrossChains * kCrossChains;
        const size_t row_values = even ? size_t(n_ / 2 + 1) : 2 * size_t(n_);  // floats a spectrum row
        const float* spectrum = even ? spectrum_.even_value.data() : reinterpret_cast<const float*>(spectrum_.value.data());
        for (int ky = 0; ky < n_; ++ky) {
            double* row_re = &re_[size_t(ky) * kCrossChains];
            double* row_im = &im_[size_t(ky) * kCrossChains];
            Lanes zr, zi;
            for (int j = 0; j < kCrossChains; ++j) {
                zr[j] = float(row_re[j]);
                zi[j] = float(row_im[j]);
            }
            const float sr = step_[ky].real(), si = step_[ky].imag();
            const float* in = spectrum + size_t(ky) * row_values;
            // the block's run of a row a few rows ahead, one cache line at a time (runs a
            // row apart are too far apart for the hardware's prefetch to follow)
            if (ky + kPrefetchRows < n_)
                for (int k = (even ? 1 : 2) * c0; k < (even ? 1 : 2) * c1; k += 16)
                    __builtin_prefetch(in + kPrefetchRows * row_values + k);
            float* out = reinterpret_cast<float*>(block + size_t(ky) * cols) - 2 * c0;
            for (int k = c0; k < whole; k += kCrossChains) {
                Lanes xr, xi;
                load(xr, &fx_re_[k]);
                load(xi, &fx_im_[k]);
                const Lanes br = xr * zr - xi * zi, bi = xr * zi + xi * zr;
                Lanes vr, vi;
                if (even) {
                    Lanes a;
                    load(a, in + k);
                    vr = a * br;
                    vi = a * bi;
                } else {
                    Lanes lo, hi;
                    load(lo, in + 2 * k);
                    load(hi, in + 2 * k + kCrossChains);
                    const Lanes ar = __builtin_shuffle(lo, hi, LaneIndex{0, 2, 4, 6, 8, 10, 12, 14});
                    const Lanes ai = __builtin_shuffle(lo, hi, LaneIndex{1, 3, 5, 7, 9, 11, 13, 15});
                    vr = ar * br - ai * bi;
                    vi = ar * bi + ai * br;
                }
                const Lanes lo = __builtin_shuffle(vr, vi, LaneIndex{0, 8, 1, 9, 2, 10, 3, 11});
                const Lanes hi = __builtin_shuffle(vr, vi, LaneIndex{4, 12, 5, 13, 6, 14, 7, 15});
                std::memcpy(out + 2 * k, &lo, sizeof lo);
                std::memcpy(out + 2 * k + kCrossChains, &hi, sizeof hi);
                const Lanes r = zr * sr - zi * si;
                zi = zr * si + zi * sr;
                zr = r;
            }
            // a run's last few columns
            for (int j = 0; whole + j < c1; ++j) {
                const int kx = whole + j;
                const float br = fx_re_[kx] * zr[j] - fx_im_[kx] * zi[j], bi = fx_re_[kx] * zi[j] + fx_im_[kx] * zr[j];
                const float ar = even ? in[kx] : in[2 * kx], ai = even ? 0.0f : in[2 * kx + 1];
                out[2 * kx] = ar * br - ai * bi;
                out[2 * kx + 1] = ar * bi + ai * br;
            }
            const double br = block_step_[ky].real(), bi = block_step_[ky].imag();
            for (int j = 0; j < kCrossChains; ++j) {
                const double r = row_re[j] * br - row_im[j] * bi;
                row_im[j] = row_re[j] * bi + row_im[j] * br;
                row_re[j] = r;
            }
        }
    }

    int signed_index(int k) const { return k < n_ / 2 ? k : k - n_; }
    const PupilSpectrum& spectrum_;
    int n_;
    std::vector<float> fx_re_, fx_im_;
    std::vector<std::complex<double>> fy_;
    std::vector<double> beta_, re_, im_;  // per row: beta; its sequences at the next block's start
    std::vector<std::complex<float>> step_;         // per row: exp(i beta kCrossChains)
    std::vector<std::complex<double>> block_step_;  // per row: exp(i beta block)
};

// Columns [c0, c1) of the first inverse transform's result (u[y * (c1 - c0) + kx - c0]: image
// row y at frequency kx) into the kernel's rows, one per column of `window`: window[kx * rows +
// k] = row y[k]'s value; columns past `lines` are the mirror's, window[(n - kx) * rows + k] = row
// mirror_y[k]'s value at kx. Blocks of kRowBlock rows: the reads run along their rows, the writes
// fill a cache line at a time; each value moved as one 8-byte word (a complex<float> copy
// compiles to two scalar moves).
void gather_rows(const std::complex<float>* u, int c0, int c1, int n, int lines, const std::vector<int>& y,
                 const std::vector<int>& mirror_y, std::complex<float>* window) {
    constexpr int kRowBlock = 16;
    constexpr size_t kValue = sizeof(std::complex<float>);
    const int rows = int(y.size()), cols = c1 - c0;
    // the columns whose mirror image lies past `lines`: kx in [m0, m1)
    const int m0 = std::max(c0, 1), m1 = std::min(c1, n - lines + 1);
    const char* from[kRowBlock];
    const char* mirror[kRowBlock];
    char* to = reinterpret_cast<char*>(window);
    for (int k0 = 0; k0 < rows; k0 += kRowBlock) {
        const int m = std::min(rows, k0 + kRowBlock) - k0;
        for (int k = 0; k < m; ++k) {
            from[k] = reinterpret_cast<const char*>(u + size_t(y[k0 + k]) * cols - c0);
            mirror[k] = reinterpret_cast<const char*>(u + size_t(mirror_y[k0 + k]) * cols - c0);
        }
        for (int kx = c0; kx < c1; ++kx)
            for (int k = 0; k < m; ++k)
                std::memcpy(to + (size_t(kx) * rows + k0 + k) * kValue, from[k] + size_t(kx) * kValue, kValue);
        for (int kx = m0; kx < m1; ++kx)
            for (int k = 0; k < m; ++k)
                std::memcpy(to + (size_t(n - kx) * rows + k0 + k) * kValue, mirror[k] + size_t(kx) * kValue, kValue);
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
    const bool even = spectrum.even;
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
    // scratch, reused: a block of the spectrum's columns (row ky) and its transform's work; the
    // kernel's rows transposed (one column each); the second transform's work
    const ColumnFft inverse(n, true);
    const int block = ColumnFft::block_columns(n);
    thread_local std::vector<std::complex<float>> block_scratch, window_scratch, work_scratch;
    std::complex<float>* columns = scratch(block_scratch, 2 * size_t(n) * block);
    std::complex<float>* window = scratch(window_scratch, size_t(n) * rows);
    std::complex<float>* work = scratch(work_scratch, size_t(n) * rows);
    // Along ky a block of columns at a time (the transfer function written into it, transformed
    // and its kernel rows gathered while it is in the cache): image row y, frequency kx.
    TransferFunction transfer(spectrum, q.wavelength, g, block);
    for (int run0 : {0, n / 2}) {
        const int run1 = run0 == 0 ? std::min(lines, n / 2) : lines;
        if (run0 < run1) transfer.start(run0);
        for (int c0 = run0; c0 < run1; c0 += block) {
            const int c1 = std::min(run1, c0 + block);
            transfer.apply(c0, c1, columns);
            gather_rows(inverse.transform_where(columns, columns + size_t(n) * block, c1 - c0, 0, c1 - c0), c0, c1, n, lines, y,
                        mirror_y, window);
        }
    }
    // along kx: field[x * rows + k], image column x (in the window or the work array)
    const std::complex<float>* field = inverse.transform_where(window, work, rows, 0, rows);
    // Each pixel: sum of |U|^2 h^2 over its points / transmitted power (the aperture's area);
    // the unnormalised forward-inverse pair scales by n^2. Column a's points summed per row
    // first (contiguous; floats: a few terms of one size), then each pixel's sub rows (double).
    const int w = 2 * R + 1;
    std::vector<double> sum(size_t(w) * w, 0.0);
    std::vector<float> column(rows);
    for (int a = -R; a <= R; ++a) {
        std::fill(column.begin(), column.end(), 0.0f);
        for (int t = 0; t < sub; ++t) {
            const float* x = reinterpret_cast<const float*>(&field[size_t(wrap(n / 2 + a * sub - sub / 2 + t)) * rows]);
            float* c = column.data();
#pragma omp simd
            for (int k = 0; k < rows; ++k) c[k] += x[2 * k] * x[2 * k] + x[2 * k + 1] * x[2 * k + 1];
        }
        for (int b = 0; b < rows / sub; ++b) {
            double pixel = 0;
            for (int t = 0; t < sub; ++t) pixel += column[size_t(b) * sub + t];
            sum[size_t(b0 + R + b) * w + (a + R)] = pixel;
        }
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
