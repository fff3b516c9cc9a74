#include "wavecam/fresnel_psf.h"

#include <kiss_fft.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "real_fft2d.h"

namespace wavecam {
namespace {

// The request's geometry, shared by both evaluations (see the header for the derivation).
struct FieldGeometry {
    double c = 1;              // cos theta
    double alpha = 0;          // 1/z + 1/f
    double ar = 0, at = 0;     // chirp rates c^3 alpha (radial), c alpha (tangential)
    double er_x = 1, er_y = 0;  // radial unit vector in image (column, row) axes
    double span = 0;           // the aperture's largest width
    double area = 0;           // the aperture's area: the transmitted power, per unit irradiance
};

FieldGeometry geometry_of(const FieldPsfRequest& q) {
    FieldGeometry g;
    const double tan2 = q.u * q.u + q.v * q.v;
    g.c = 1.0 / std::sqrt(1.0 + tan2);
    g.alpha = (std::isinf(q.depth) ? 0.0 : 1.0 / q.depth) + 1.0 / q.film_distance;
    g.ar = g.c * g.c * g.c * g.alpha;
    g.at = g.c * g.alpha;
    const double rn = std::sqrt(tan2);  // any axis on axis
    if (rn > 0) {
        g.er_x = q.u / rn;
        g.er_y = -q.v / rn;
    }
    g.span = 2 * q.aperture.bounding_radius();
    g.area = q.aperture.area();
    return g;
}

// The matrix transform's sampled pupil depends on the aperture and the grid only, not on the
// wavelength nor (for a round pupil) on the field angle: a table's requests repeat it, so each
// thread keeps the last one it sampled under its key.
template <class Grid>
struct LastPupil {
    std::vector<double> key;
    std::string aperture;
    const void* mask = nullptr;
    Grid grid;
    template <class Sample>
    const Grid& get(const Aperture& a, std::vector<double> k, Sample sample) {
        if (k != key || a.mask.get() != mask || a.name() != aperture) {
            grid = sample();
            key = std::move(k);
            aperture = a.name();
            mask = a.mask.get();
        }
        return grid;
    }
};

// Film radius (m) holding kPsfKernelEnergy of the PSF: the shadow's radius plus the sharp
// edge's tail, light beyond the rim by s being at most 2 lambda f / (pi^2 D s) of the power,
// stretched 1/cos^3 off axis (see the header).
double psf_radius(const Aperture& aperture, double film_distance, double depth, double wavelength, double cos_theta) {
    const double span = 2 * aperture.bounding_radius();
    const double shadow = 0.5 * span * (1.0 + film_distance / depth);
    const double tail = 2 * wavelength * film_distance / (M_PI * M_PI * aperture.diameter * (1 - kPsfKernelEnergy));
    return shadow + tail / std::pow(cos_theta, 3);
}

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

bool mirror_symmetric(const Aperture& a) {
    return a.shape == ApertureShape::Circle || a.shape == ApertureShape::ZonePlate;
}

// t(-x, -y) = t(x, y): a regular polygon of even N, a square, or any mirror-symmetric pupil.
bool point_symmetric(const Aperture& a) {
    return mirror_symmetric(a) || a.shape == ApertureShape::Square ||
           (a.shape == ApertureShape::Polygon && a.sides % 2 == 0);
}

struct MftPlan {
    int nr = 0, nt = 0;      // pupil samples across, radial and tangential
    int half = 0;            // output grid half-width in steps
    double step = 0;         // output grid spacing on the film (m)
    int points = 0;          // points per kernel pixel side averaged from the grid
    bool mirrored = false;   // evaluated on the halves xi > 0 and mu >= 0 only
    int kept(int n) const { return mirrored ? n / 2 : n; }
    int grid() const { return mirrored ? half + 1 : 2 * half + 1; }
    // real multiply-adds: open x M_t (real x complex), M_r x that (complex x complex), and
    // the matrices' sines and cosines (about 20 each)
    double cost() const {
        const double pr = kept(nr), pt = kept(nt), m = grid();
        return 2 * pr * pt * m + 4 * pr * m * m + 20 * (pr + pt) * m;
    }
};

MftPlan plan_mft(const FieldPsfRequest& q, const FieldGeometry& g) {
    MftPlan p;
    p.mirrored = mirror_symmetric(q.aperture);
    // The irradiance holds no frequency above span / (lambda f): its finest fringe is
    // lambda f / span. Output points a fraction of a pixel apart and at least two per finest
    // fringe, so that the sub-pixel points average fringes instead of aliasing them; where the
    // finest fringe spans pixels (small pinholes, large kernels), 16 points per fringe suffice
    // for the bilinear interpolation (its error on the Airy core, curvature x step^2 / 8, stays
    // near 0.3%), however many pixels that is.
    const double fringe = q.wavelength * q.film_distance / g.span;
    p.step = std::max(fringe / 16, std::min(q.pixel_pitch / q.subsamples, fringe / 2));
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

// One axis's matrix M[o][p] (see above), real and imaginary parts, for film offsets
// d_o = (o - offset) step whose frequency is mu_o = d_o stretch / (lambda f).
void axis_matrix(const std::vector<double>& xi, double rate, const FieldPsfRequest& q, const MftPlan& plan,
                 double stretch, std::vector<float>& re, std::vector<float>& im) {
    const int m = plan.grid(), offset = plan.mirrored ? 0 : plan.half;
    const size_t n = xi.size();
    re.resize(size_t(m) * n);
    im.resize(size_t(m) * n);
    std::vector<std::complex<double>> chirp(n);
    for (size_t p = 0; p < n; ++p) chirp[p] = std::polar(1.0, M_PI * std::remainder(rate * xi[p] * xi[p] / q.wavelength, 2.0));
    for (int o = 0; o < m; ++o) {
        const double mu = (o - offset) * plan.step * stretch / (q.wavelength * q.film_distance);
        for (size_t p = 0; p < n; ++p) {
            const double turns = std::remainder(xi[p] * mu, 1.0);
            const std::complex<double> e = plan.mirrored ? 2 * std::cos(2 * M_PI * turns) * chirp[p]
                                                         : std::polar(1.0, -2 * M_PI * turns) * chirp[p];
            re[size_t(o) * n + p] = float(e.real());
            im[size_t(o) * n + p] = float(e.imag());
        }
    }
}

// |Q|^2 on the output grid (grid x grid, rows radial): tmp[ir][ot] = sum_it open[ir][it]
// M_t[ot][it], then Q[or][ot] = sum_ir M_r[or][ir] tmp[ir][ot].
std::vector<float> transform_power(const PupilGrid& pupil, const std::vector<float>& mr_re,
                                   const std::vector<float>& mr_im, const std::vector<float>& mt_re,
                                   const std::vector<float>& mt_im, int m) {
    const int nr = int(pupil.xi_r.size()), nt = int(pupil.xi_t.size());
    std::vector<float> tmp_re(size_t(nr) * m), tmp_im(size_t(nr) * m);
    for (int ir = 0; ir < nr; ++ir)
        for (int o = 0; o < m; ++o) {
            const float* a = &pupil.open[size_t(ir) * nt];
            const float* br = &mt_re[size_t(o) * nt];
            const float* bi = &mt_im[size_t(o) * nt];
            float sr = 0, si = 0;
#pragma omp simd reduction(+ : sr, si)
            for (int it = 0; it < nt; ++it) {
                sr += a[it] * br[it];
                si += a[it] * bi[it];
            }
            tmp_re[size_t(ir) * m + o] = sr;
            tmp_im[size_t(ir) * m + o] = si;
        }
    std::vector<float> power(size_t(m) * m), row_re(m), row_im(m);
    for (int orr = 0; orr < m; ++orr) {
        std::fill(row_re.begin(), row_re.end(), 0.0f);
        std::fill(row_im.begin(), row_im.end(), 0.0f);
        for (int ir = 0; ir < nr; ++ir) {
            const float ar = mr_re[size_t(orr) * nr + ir], ai = mr_im[size_t(orr) * nr + ir];
            const float* br = &tmp_re[size_t(ir) * m];
            const float* bi = &tmp_im[size_t(ir) * m];
#pragma omp simd
            for (int ot = 0; ot < m; ++ot) {
                row_re[ot] += ar * br[ot] - ai * bi[ot];
                row_im[ot] += ar * bi[ot] + ai * br[ot];
            }
        }
        for (int ot = 0; ot < m; ++ot) power[size_t(orr) * m + ot] = row_re[ot] * row_re[ot] + row_im[ot] * row_im[ot];
    }
    return power;
}

// Power per film area on the (r, t) grid, read by bilinear interpolation (zero beyond it).
struct FilmGrid {
    const MftPlan& plan;
    std::vector<float> density;  // grid x grid, rows radial
    double inverse_step = 1 / plan.step;
    double at(double r, double t) const {
        const int m = plan.grid();
        if (plan.mirrored) {
            r = std::fabs(r);
            t = std::fabs(t);
        }
        const double offset = plan.mirrored ? 0 : plan.half;
        const double fr = r * inverse_step + offset, ft = t * inverse_step + offset;
        if (!(fr >= 0 && ft >= 0 && fr < m - 1 && ft < m - 1)) return 0.0;
        const int i0 = int(fr), j0 = int(ft);
        const double a = fr - i0, b = ft - j0;
        auto I = [&](int i, int j) { return double(density[size_t(i) * m + j]); };
        return (1 - a) * ((1 - b) * I(i0, j0) + b * I(i0, j0 + 1)) + a * ((1 - b) * I(i0 + 1, j0) + b * I(i0 + 1, j0 + 1));
    }
};

// Each kernel pixel's power: the area average of the film grid over the pixel (points x
// points bilinear samples) times the pixel's area.
std::vector<float> average_over_pixels(const FieldPsfRequest& q, const FieldGeometry& g, const FilmGrid& film) {
    const int w = 2 * q.radius + 1, sub = film.plan.points;
    std::vector<float> weight(size_t(w) * w, 0.0f);
    const double pixel_area = q.pixel_pitch * q.pixel_pitch;
    // the points' image offsets (column or row) in metres on the film, kernel pixel k's at
    // [k sub, (k + 1) sub)
    std::vector<double> offset(size_t(w) * sub);
    for (int k = 0; k < w; ++k)
        for (int s = 0; s < sub; ++s) offset[size_t(k) * sub + s] = (k - q.radius + (s + 0.5) / sub - 0.5) * q.pixel_pitch;
    // The grid is zero beyond |r|, |t| < half steps, so beyond |x|, |y| < sqrt(2) half steps
    // at any rotation: only the points within that reach are summed (pixels far wider than
    // the PSF - a long film distance, a tiny frame - would otherwise cost points^2 each).
    const double reach = std::sqrt(2.0) * (film.plan.half + 1) * film.plan.step;
    auto points_within = [&](int k, int& first, int& last) {
        first = 0;
        last = sub;
        while (first < sub && offset[size_t(k) * sub + first] < -reach) ++first;
        while (last > first && offset[size_t(k) * sub + last - 1] > reach) --last;
    };
    for (int b = 0; b < w; ++b)
        for (int a = 0; a < w; ++a) {
            double s = 0;
            int b0, b1, a0, a1;
            points_within(b, b0, b1);
            points_within(a, a0, a1);
            for (int sb = b0; sb < b1; ++sb) {
                const double y = offset[size_t(b) * sub + sb];
                for (int sa = a0; sa < a1; ++sa) {
                    const double x = offset[size_t(a) * sub + sa];
                    s += film.at(x * g.er_x + y * g.er_y, -x * g.er_y + y * g.er_x);
                }
            }
            weight[size_t(b) * w + a] = float(s / (sub * sub) * pixel_area);
        }
    return weight;
}

std::vector<float> kernel_by_mft(const FieldPsfRequest& q, const FieldGeometry& g, const MftPlan& plan) {
    thread_local LastPupil<PupilGrid> last;
    const PupilGrid& pupil =
        last.get(q.aperture,
                 {q.aperture.diameter, double(plan.nr), double(plan.nt), double(plan.mirrored),
                  plan.mirrored ? 0.0 : g.er_x, plan.mirrored ? 0.0 : g.er_y},
                 [&] { return sample_pupil(q, g, plan); });
    const double c = g.c;
    std::vector<float> mr_re, mr_im, mt_re, mt_im;
    axis_matrix(pupil.xi_r, g.ar, q, plan, c * c * c, mr_re, mr_im);
    axis_matrix(pupil.xi_t, g.at, q, plan, c, mt_re, mt_im);
    FilmGrid film{plan, transform_power(pupil, mr_re, mr_im, mt_re, mt_im, plan.grid())};
    // Power per film area. The transform is Q(mu) = sum_p Q_p exp(-2 pi i xi_p mu) without
    // its cell area hr ht; Parseval gives int |Q|^2 d^2mu = aperture area, and d^2mu =
    // c^4 / (lambda f)^2 d^2(film), so the fraction of the transmitted power per film area is
    // |Q|^2 (hr ht)^2 c^4 / ((lambda f)^2 area).
    const double density = std::pow(pupil.hr * pupil.ht * c * c / (q.wavelength * q.film_distance), 2) / g.area;
    for (float& x : film.density) x = float(x * density);
    return average_over_pixels(q, g, film);
}

// ---- Many zones: Fresnel transfer function on a grid at a fraction of a film pixel ----------
//
// Completing the square in the header's phase, |PSF(d)| = |(P * K)(s)| with s = d / (f alpha)
// (the shadow is the pupil magnified by f alpha = 1 + f/z, in every direction) and the chirp
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
//  - H: its phase step between frequency samples, 2 pi shift / L, stays below pi while the
//    largest shift (lambda z_r |nu|max = lambda z_r / (sqrt 2 h)) is below half the period L.
//  - wrap-around: light from the pupil (half-width a) shifted up to that much must not come
//    back round the period into the kernel (half-width E): L >= E + a + shift.
// This is the many-zone regime's tool: its grid is never coarser than the chirp needs there;
// with few zones (small pinholes) the grid those conditions demand is large and the matrix
// Fourier transform is cheaper; field_psf_kernel picks the cheaper of the two.
constexpr int kMinCellsAcross = 64;

// Cells holding their open fraction (the pupil box-filtered over a cell of width h) multiply
// the pupil's spectrum by sinc(nu h) per axis; the transfer function divides it out, which
// restores the near tail (light diffracted a few pixels past the rim, ~0.5% of the power at
// 4x the optimum). sinc(x) = sin(pi x) / (pi x).
double box_response(double nu_h) { return std::fabs(nu_h) < 1e-9 ? 1.0 : std::sin(M_PI * nu_h) / (M_PI * nu_h); }

struct TransferPlan {
    int sub = 0;             // grid points per kernel pixel side
    int n = 0;               // grid size (FFT length), at least
    double h = 0;            // pitch on the pupil plane (m)
    bool symmetric = false;  // the field is point-symmetric: half the inverse transform
    // the inverse transform and the transfer function (the pupil's forward transform is
    // shared by a table's requests at one depth, see PupilSpectrum)
    double cost() const {
        return (symmetric ? 0.5 : 1.0) * (5.0 * double(n) * n * std::log2(double(n)) + 8.0 * double(n) * n);
    }
};

TransferPlan plan_transfer(const FieldPsfRequest& q, const FieldGeometry& g) {
    TransferPlan p;
    const double fa = q.film_distance * g.alpha;
    p.sub = std::max(q.subsamples, int(std::min(std::ceil(kMinCellsAcross * q.pixel_pitch / (g.span * fa)), 1e6)));
    // a point-symmetric pupil on a grid with a point at the centre (odd sub) gives a
    // point-symmetric field: half of the inverse transform is the other half mirrored
    p.symmetric = point_symmetric(q.aperture);
    if (p.symmetric && p.sub % 2 == 0) ++p.sub;
    p.h = q.pixel_pitch / (p.sub * fa);
    const double shift = q.wavelength / g.ar / (std::sqrt(2.0) * p.h);
    const double kernel_half = (q.radius + 0.5) * q.pixel_pitch / fa, pupil_half = 0.5 * g.span;
    const double period = std::max(kernel_half + pupil_half + shift, 2 * shift);
    // (a grid beyond 2^28 points across is never cheaper than the matrix transform: kept
    // finite, it only loses the cost comparison)
    p.n = detail::fft_friendly_size(int(std::min(std::ceil(period / p.h) + 2, double(1 << 29))));
    return p;
}

// Unnormalised 1D complex FFTs (kissfft) of `count` consecutive lines of length n, out of
// place (kissfft in place allocates per call). The 2D transforms below keep their arrays with
// the transformed axis contiguous: the spectrum transposed (one line per kx), the image rows.
class LineFft {
public:
    LineFft(int n, bool inverse) : n_(n), cfg_(kiss_fft_alloc(n, inverse ? 1 : 0, nullptr, nullptr)) {}
    ~LineFft() { kiss_fft_free(cfg_); }
    LineFft(const LineFft&) = delete;
    LineFft& operator=(const LineFft&) = delete;
    void operator()(const std::complex<float>* in, std::complex<float>* out, int count) const {
        for (int k = 0; k < count; ++k)
            kiss_fft(cfg_, reinterpret_cast<const kiss_fft_cpx*>(in + size_t(k) * n_),
                     reinterpret_cast<kiss_fft_cpx*>(out + size_t(k) * n_));
    }

private:
    int n_;
    kiss_fft_cfg cfg_;
};

// The spectrum times the transfer function with the pupil cells' box response divided out,
// for the first `lines` lines kx of the transposed grid (frequency nu = k / L, k taken in
// [-n/2, n/2)). In image axes the exponent is a quadratic form, -pi lambda (A nx^2 + B ny^2 +
// 2 C nx ny) with A = zr ex^2 + zt ey^2, B = zr ey^2 + zt ex^2, C = ex ey (zr - zt) (e the
// radial unit vector): a factor per axis times exp(-2 pi i lambda C nx ny), which along a line
// is a geometric sequence in ky (one complex multiplication per point instead of a sine and
// cosine).
void transfer(const std::vector<std::complex<float>>& spectrum, std::vector<std::complex<float>>& field, int n,
              int lines, double h, double wavelength, const FieldGeometry& g) {
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
    field.resize(size_t(lines) * n);
    std::vector<std::complex<float>> line(n);
    for (int kx = 0; kx < lines; ++kx) {
        // fx exp(i beta ky') fy for ky' = -n/2 ... n/2 - 1, the exponential by repeated
        // multiplication (in double: n steps)
        const double beta = -2 * M_PI * wavelength * C * signed_index(kx) / (L * L);
        const std::complex<double> w = std::polar(1.0, beta);
        std::complex<double> z = fx[kx] * std::polar(1.0, -beta * (n / 2));
        for (int k = -n / 2; k < n - n / 2; ++k, z *= w) line[(k + n) % n] = std::complex<float>(z * fy[(k + n) % n]);
        const std::complex<float>* in = &spectrum[size_t(kx) * n];
        std::complex<float>* out = &field[size_t(kx) * n];
        for (int ky = 0; ky < n; ++ky) out[ky] = in[ky] * line[ky];
    }
}

// The pupil's spectrum on an n x n grid of pitch h: it depends on neither the wavelength nor
// the field angle (the chirp is all in the transfer function), so a table's requests at one
// depth share it. Each thread keeps the last kSpectraKept; a request whose grid must be at
// least n reuses the narrowest kept spectrum up to kWiderGrid n^2 in area (a wider period only
// moves the wrap-around farther away): its inverse transform then costs at most that much
// more, where a new forward transform would cost about twice the inverse one.
constexpr int kSpectraKept = 4;
constexpr double kWiderGrid = 1.25;

struct PupilSpectrum {
    std::string aperture;
    const void* mask = nullptr;
    double diameter = 0, h = 0, o = 0;
    int n = 0;
    long used = 0;  // when last used, for replacing the least recently used
    std::vector<std::complex<float>> value;
    bool serves(const Aperture& a, double hh, double oo, int n_min) const {
        return a.name() == aperture && a.mask.get() == mask && a.diameter == diameter && hh == h && oo == o &&
               n >= n_min && double(n) * n <= kWiderGrid * n_min * n_min;
    }
};

const PupilSpectrum& pupil_spectrum(const FieldPsfRequest& q, const FieldGeometry& g, const TransferPlan& plan,
                                    double o) {
    thread_local PupilSpectrum kept_spectra[kSpectraKept];
    thread_local long clock = 0;
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
    std::vector<std::complex<float>> pupil(size_t(n) * n, 0.0f), rows(size_t(n) * n, 0.0f);
    for (int iy = row0; iy <= n / 2 + reach; ++iy)
        for (int ix = n / 2 - reach; ix <= n / 2 + reach; ++ix) {
            const double x = (ix - n / 2 + o) * h, y = (iy - n / 2 + o) * h;
            double cx, cy;
            pupil[size_t(iy) * n + ix] = float(q.aperture.coverage(-x - 0.5 * h, -x + 0.5 * h, y - 0.5 * h, y + 0.5 * h, cx, cy));
        }
    const LineFft forward(n, false);
    forward(&pupil[size_t(row0) * n], &rows[size_t(row0) * n], 2 * reach + 1);
    for (int y = 0; y < n; ++y)  // transposed: the columns' transforms run along lines
        for (int x = 0; x < n; ++x) pupil[size_t(x) * n + y] = rows[size_t(y) * n + x];
    kept.value.resize(size_t(n) * n);
    forward(pupil.data(), kept.value.data(), n);
    kept.aperture = q.aperture.name();
    kept.mask = q.aperture.mask.get();
    kept.diameter = q.aperture.diameter;
    kept.h = h;
    kept.o = o;
    kept.n = n;
    kept.used = ++clock;
    return kept;
}

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
    thread_local std::vector<std::complex<float>> field, columns;  // scratch, reused
    transfer(spectrum.value, field, n, lines, h, q.wavelength, g);
    const LineFft inverse(n, true);
    columns.resize(size_t(lines) * n);
    inverse(field.data(), columns.data(), lines);  // columns[kx][y]: image row y at frequency kx
    // the image rows the kernel reads, frequency kx along each (kx >= lines: the mirror's)
    const int b0 = even ? 0 : -R;
    const int row0 = n / 2 + b0 * sub - sub / 2, rows = (R - b0 + 1) * sub;
    auto wrap = [n](int i) { return ((i % n) + n) % n; };
    std::vector<int> y(rows), mirror_y(rows);
    for (int k = 0; k < rows; ++k) {
        y[k] = wrap(row0 + k);
        mirror_y[k] = wrap(-y[k]);
    }
    field.resize(size_t(rows) * n);
    for (int kx = 0; kx < n; ++kx) {
        const bool own = kx < lines;
        const std::complex<float>* column = &columns[size_t(own ? kx : n - kx) * n];
        const int* from = own ? y.data() : mirror_y.data();
        for (int k = 0; k < rows; ++k) field[size_t(k) * n + kx] = column[from[k]];
    }
    // Each pixel: sum of |U|^2 h^2 over its points / transmitted power (the aperture's area);
    // kissfft's forward-inverse pair scales by n^2.
    const int w = 2 * R + 1;
    std::vector<int> column_of(size_t(w) * sub);  // kernel column a's grid columns
    for (int a = -R; a <= R; ++a)
        for (int t = 0; t < sub; ++t) column_of[size_t(a + R) * sub + t] = wrap(n / 2 + a * sub - sub / 2 + t);
    std::vector<double> sum(size_t(w) * w, 0.0);
    std::vector<std::complex<float>> row(n);
    for (int k = 0; k < rows; ++k) {
        inverse(&field[size_t(k) * n], row.data(), 1);
        double* dst = &sum[size_t(b0 + R + k / sub) * w];
        for (int a = 0; a < w; ++a)
            for (int t = 0; t < sub; ++t) dst[a] += std::norm(row[column_of[size_t(a) * sub + t]]);
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

}  // namespace

namespace {
bool chooses_transfer(const FieldPsfRequest& q, const MftPlan& mft, const TransferPlan& transfer) {
    return q.method == FieldPsfMethod::TransferFunction ||
           (q.method == FieldPsfMethod::Auto && q.pupil_samples <= 0 && transfer.cost() < mft.cost());
}
}  // namespace

double field_psf_scratch_bytes(const FieldPsfRequest& q) {
    const FieldGeometry g = geometry_of(q);
    const MftPlan mft = plan_mft(q, g);
    const TransferPlan transfer = plan_transfer(q, g);
    const double w = 2.0 * q.radius + 1;
    if (chooses_transfer(q, mft, transfer)) {
        const double n = transfer.n;  // pupil, rows, field, columns, and the spectra kept per thread
        return 8.0 * n * n * (4 + kSpectraKept) + 8.0 * w * w;
    }
    const double pr = mft.kept(mft.nr), pt = mft.kept(mft.nt), m = mft.grid();
    // pupil cells, the two axis matrices and the intermediate (complex), the power grid, the
    // pixel averages' offsets and weights
    return 4.0 * (pr * pt + 2 * m * (pr + pt) + 2 * pr * m + m * m + 2 * m) + 8.0 * w * mft.points + 4.0 * w * w;
}

PsfKernel field_psf_kernel(const FieldPsfRequest& q) {
    const FieldGeometry g = geometry_of(q);
    const MftPlan mft = plan_mft(q, g);
    const TransferPlan transfer = plan_transfer(q, g);
    const bool use_transfer = chooses_transfer(q, mft, transfer);
    PsfKernel k;
    k.radius = q.radius;
    k.weight = use_transfer ? kernel_by_transfer(q, g, transfer) : kernel_by_mft(q, g, mft);
    return k;
}

int psf_kernel_radius(const Aperture& aperture, double film_distance, double nearest_depth, double wavelength,
                      double cos_theta_max, double pixel_pitch, int max_radius) {
    const double r = psf_radius(aperture, film_distance, nearest_depth, wavelength, cos_theta_max) / pixel_pitch;
    return int(std::clamp(std::ceil(r), 1.0, double(max_radius)));  // (clamped as a double: no overflow)
}

}  // namespace wavecam
