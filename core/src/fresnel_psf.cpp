#include "wavecam/fresnel_psf.h"

#include <kiss_fft.h>

#include <algorithm>
#include <cmath>
#include <complex>

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

// One axis of the matrix Fourier transform, split into real and imaginary parts:
// E[o][p] = exp(-2 pi i xi_p mu_o).
void transform_matrix(const std::vector<double>& xi, const std::vector<double>& mu, std::vector<float>& re,
                      std::vector<float>& im) {
    re.resize(mu.size() * xi.size());
    im.resize(mu.size() * xi.size());
    for (size_t o = 0; o < mu.size(); ++o)
        for (size_t p = 0; p < xi.size(); ++p) {
            const double phase = -2 * M_PI * std::remainder(xi[p] * mu[o], 1.0);
            re[o * xi.size() + p] = float(std::cos(phase));
            im[o * xi.size() + p] = float(std::sin(phase));
        }
}

struct MftPlan {
    int n = 0;        // pupil samples across (r, t)
    int half = 0;     // output grid half-width in steps
    double step = 0;  // output grid spacing on the film (m)
    int points = 0;   // points per kernel pixel side averaged from the grid
    double cost() const { return 4.0 * (double(n) * n * (2 * half + 1) + double(n) * (2 * half + 1) * (2 * half + 1)); }
};

MftPlan plan_mft(const FieldPsfRequest& q, const FieldGeometry& g) {
    MftPlan p;
    // The irradiance holds no frequency above span / (lambda f): its finest fringe is
    // lambda f / span. Output points a fraction of a pixel apart and at least two per finest
    // fringe, so that the sub-pixel points average fringes instead of aliasing them; where the
    // finest fringe spans pixels (small pinholes, large kernels), 16 points per fringe suffice
    // for the bilinear interpolation (its error on the Airy core, curvature x step^2 / 8, stays
    // near 0.3%), however many pixels that is.
    const double fringe = q.wavelength * q.film_distance / g.span;
    p.step = std::max(fringe / 16, std::min(q.pixel_pitch / q.subsamples, fringe / 2));
    p.points = std::max(q.subsamples, int(std::ceil(q.pixel_pitch / p.step - 1e-6)));
    // The grid covers the kernel square rotated by any angle, or only the PSF's own
    // kPsfKernelEnergy radius where that is smaller (pixels far wider than the PSF): the
    // fringe-fine step over a kernel of such pixels would cost (pixel / fringe)^2.
    const double psf_extent = psf_radius(q.aperture, q.film_distance, q.depth, q.wavelength, g.c) + 2 * fringe;
    const double cover = std::min((q.radius + 1) * q.pixel_pitch, psf_extent) * std::sqrt(2.0);
    p.half = int(std::ceil(cover / p.step));
    const double extent = p.half * p.step;
    // The quadratic phase spans N = (span/2)^2 alpha / lambda half-period zones; 8 N samples
    // across keep its phase step below pi/2, and never fewer than 64. The sampled pupil's
    // transform repeats every lambda f / (h cos) on the film: the output grid (half-width
    // `extent`) must fit in one period, n >= 2 span extent cos / (lambda f); twice that keeps
    // the cells' box filter (sinc(mu h) >= 0.9 at the grid's edge, where the far tail lands)
    // from dimming the tail: 0.1% of the power at 0.08 mm, f = 50 mm, 99% kernel.
    // Cells hold their open fraction at their centre, so an opening narrower than the pupil
    // (a zone plate's outer zone, a sieve's hole) needs kCellsAcrossFinest cells across it: with
    // 3.5 across sieve:8's smallest hole the focal core came out 6% dim, with 12 within 0.5%.
    constexpr double kCellsAcrossFinest = 12;
    const double zones = 0.25 * g.span * g.span * g.alpha / q.wavelength;
    p.n = q.pupil_samples > 0
              ? q.pupil_samples
              : std::clamp(2 * int(std::ceil(std::max({4 * zones, 2.2 * g.span * extent * g.c /
                                                                      (q.wavelength * q.film_distance),
                                                       0.5 * kCellsAcrossFinest * g.span / q.aperture.finest_width()}))),
                           64, 2048);
    return p;
}

std::vector<float> kernel_by_mft(const FieldPsfRequest& q, const FieldGeometry& g, const MftPlan& plan) {
    const double f = q.film_distance, lambda = q.wavelength, c = g.c;
    const int n = plan.n, half = plan.half, m = 2 * half + 1;
    const double step = plan.step;
    // Pupil on an n x n grid in (r, t) axes; cell weights from the aperture's coverage (the
    // aperture's own x, y axes rotated by the field azimuth).
    const double h = g.span / n;
    std::vector<double> xi(n);
    for (int k = 0; k < n; ++k) xi[k] = (k - 0.5 * (n - 1)) * h;
    std::vector<float> pupil_re(size_t(n) * n), pupil_im(size_t(n) * n);
    for (int ir = 0; ir < n; ++ir)
        for (int it = 0; it < n; ++it) {
            constexpr int kSub = 4;  // sub-sampled coverage of the rotated cell
            double open = 0;
            for (int s = 0; s < kSub * kSub; ++s) {
                const double r = xi[ir] + ((s % kSub) + 0.5 - 0.5 * kSub) * h / kSub;
                const double t = xi[it] + ((s / kSub) + 0.5 - 0.5 * kSub) * h / kSub;
                const double x = r * g.er_x - t * g.er_y, y = r * g.er_y + t * g.er_x;
                open += q.aperture.transmission(-x, y);  // (x, y): image (column, row); pupil +x lands at column -x
            }
            open /= kSub * kSub;
            const double phase = M_PI / lambda * (g.ar * xi[ir] * xi[ir] + g.at * xi[it] * xi[it]);
            pupil_re[size_t(ir) * n + it] = float(open * std::cos(phase));
            pupil_im[size_t(ir) * n + it] = float(open * std::sin(phase));
        }

    // Output grid in (r, t) film offsets, spacing `step`, covering the kernel square rotated by
    // any angle.
    std::vector<double> mu_r(m), mu_t(m);
    for (int o = 0; o < m; ++o) {
        const double d = (o - half) * step;
        mu_r[o] = d * c * c * c / (lambda * f);
        mu_t[o] = d * c / (lambda * f);
    }
    std::vector<float> er_re, er_im, et_re, et_im;
    transform_matrix(xi, mu_r, er_re, er_im);
    transform_matrix(xi, mu_t, et_re, et_im);
    // tmp[ir][o] = sum_it pupil[ir][it] et[o][it]
    std::vector<float> tmp_re(size_t(n) * m), tmp_im(size_t(n) * m);
    for (int ir = 0; ir < n; ++ir)
        for (int o = 0; o < m; ++o) {
            const float* pr = &pupil_re[size_t(ir) * n];
            const float* pi = &pupil_im[size_t(ir) * n];
            const float* qr = &et_re[size_t(o) * n];
            const float* qi = &et_im[size_t(o) * n];
            float sr = 0, si = 0;
#pragma omp simd reduction(+ : sr, si)
            for (int it = 0; it < n; ++it) {
                sr += pr[it] * qr[it] - pi[it] * qi[it];
                si += pr[it] * qi[it] + pi[it] * qr[it];
            }
            tmp_re[size_t(ir) * m + o] = sr;
            tmp_im[size_t(ir) * m + o] = si;
        }
    // field[or][ot] = sum_ir er[or][ir] tmp[ir][ot]; intensity = |field|^2
    std::vector<float> intensity(size_t(m) * m), row_re(m), row_im(m);
    for (int orr = 0; orr < m; ++orr) {
        std::fill(row_re.begin(), row_re.end(), 0.0f);
        std::fill(row_im.begin(), row_im.end(), 0.0f);
        for (int ir = 0; ir < n; ++ir) {
            const float ar = er_re[size_t(orr) * n + ir], ai = er_im[size_t(orr) * n + ir];
            const float* br = &tmp_re[size_t(ir) * m];
            const float* bi = &tmp_im[size_t(ir) * m];
#pragma omp simd
            for (int ot = 0; ot < m; ++ot) {
                row_re[ot] += ar * br[ot] - ai * bi[ot];
                row_im[ot] += ar * bi[ot] + ai * br[ot];
            }
        }
        for (int ot = 0; ot < m; ++ot) intensity[size_t(orr) * m + ot] = row_re[ot] * row_re[ot] + row_im[ot] * row_im[ot];
    }

    // Power per film area. The transform above is Q(mu) = sum_p Q_p exp(-2 pi i xi_p mu) without
    // its cell area h^2; Parseval gives int |Q|^2 d^2mu = aperture area, and d^2mu =
    // c^4 / (lambda f)^2 d^2(film), so the fraction of the transmitted power per film area is
    // |Q|^2 h^4 c^4 / ((lambda f)^2 area).
    const double density = std::pow(h * h * c * c / (lambda * f), 2) / g.area;
    // Area-average each kernel pixel from the (r, t) grid by bilinear interpolation.
    const int w = 2 * q.radius + 1, sub = plan.points;
    std::vector<float> weight(size_t(w) * w, 0.0f);
    auto sample = [&](double r, double t) {
        const double fr = r / step + half, ft = t / step + half;
        const int i0 = int(std::floor(fr)), j0 = int(std::floor(ft));
        if (i0 < 0 || j0 < 0 || i0 + 1 >= m || j0 + 1 >= m) return 0.0;
        const double a = fr - i0, b = ft - j0;
        auto I = [&](int i, int j) { return double(intensity[size_t(i) * m + j]); };
        return (1 - a) * ((1 - b) * I(i0, j0) + b * I(i0, j0 + 1)) + a * ((1 - b) * I(i0 + 1, j0) + b * I(i0 + 1, j0 + 1));
    };
    const double pixel_area = q.pixel_pitch * q.pixel_pitch;
    for (int b = -q.radius; b <= q.radius; ++b)
        for (int a = -q.radius; a <= q.radius; ++a) {
            double s = 0;
            for (int sb = 0; sb < sub; ++sb)
                for (int sa = 0; sa < sub; ++sa) {
                    // image offset (column, row) in metres on the film
                    const double x = (a + (sa + 0.5) / sub - 0.5) * q.pixel_pitch;
                    const double y = (b + (sb + 0.5) / sub - 0.5) * q.pixel_pitch;
                    s += sample(x * g.er_x + y * g.er_y, -x * g.er_y + y * g.er_x);
                }
            weight[size_t(b + q.radius) * w + (a + q.radius)] = float(s / (sub * sub) * pixel_area * density);
        }
    return weight;
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
    int sub = 0;   // grid points per kernel pixel side
    int n = 0;     // grid size (FFT length)
    double h = 0;  // pitch on the pupil plane (m)
    double cost() const { return 2.0 * 5.0 * double(n) * n * std::log2(double(n)) + 8.0 * double(n) * n; }
};

TransferPlan plan_transfer(const FieldPsfRequest& q, const FieldGeometry& g) {
    TransferPlan p;
    const double fa = q.film_distance * g.alpha;
    p.sub = std::max(q.subsamples, int(std::ceil(kMinCellsAcross * q.pixel_pitch / (g.span * fa))));
    p.h = q.pixel_pitch / (p.sub * fa);
    const double shift = q.wavelength / g.ar / (std::sqrt(2.0) * p.h);
    const double kernel_half = (q.radius + 0.5) * q.pixel_pitch / fa, pupil_half = 0.5 * g.span;
    const double period = std::max(kernel_half + pupil_half + shift, 2 * shift);
    p.n = detail::fft_friendly_size(int(std::ceil(period / p.h)) + 2);
    return p;
}

// In-place 2D complex FFT (kissfft rows, then columns), unnormalised; rows outside
// [row0, row1) are known to be zero on input and are skipped in the first pass.
void fft2d(std::vector<std::complex<float>>& a, int n, bool inverse, int row0, int row1) {
    kiss_fft_cfg cfg = kiss_fft_alloc(n, inverse ? 1 : 0, nullptr, nullptr);
    std::vector<std::complex<float>> line(n);
    auto cpx = [](std::complex<float>* p) { return reinterpret_cast<kiss_fft_cpx*>(p); };
    for (int r = row0; r < row1; ++r) {
        kiss_fft(cfg, cpx(&a[size_t(r) * n]), cpx(line.data()));
        std::copy(line.begin(), line.end(), &a[size_t(r) * n]);
    }
    for (int k = 0; k < n; ++k) {
        kiss_fft_stride(cfg, cpx(&a[k]), cpx(line.data()), n);
        for (int r = 0; r < n; ++r) a[size_t(r) * n + k] = line[r];
    }
    kiss_fft_free(cfg);
}

std::vector<float> kernel_by_transfer(const FieldPsfRequest& q, const FieldGeometry& g, const TransferPlan& plan) {
    const int n = plan.n, sub = plan.sub;
    const double h = plan.h;
    // Grid index i sits at (i - n/2 + o) h, o = 1/2 for even sub, so that kernel pixel a's
    // sub points are indices n/2 + a sub - sub/2 + [0, sub).
    const double o = sub % 2 == 0 ? 0.5 : 0.0;
    auto position = [&](int i) { return (i - n / 2 + o) * h; };
    std::vector<std::complex<float>> field(size_t(n) * n, 0.0f);
    int row0 = n, row1 = 0;
    for (int iy = 0; iy < n; ++iy) {
        const double y = position(iy);
        if (std::fabs(y) > 0.5 * g.span + h) continue;
        for (int ix = 0; ix < n; ++ix) {
            const double x = position(ix);
            if (std::fabs(x) > 0.5 * g.span + h) continue;
            double cx, cy;
            // (x, y): image (column, row); pupil +x lands at column -x (as in the matrix transform)
            const double open = q.aperture.coverage(-x - 0.5 * h, -x + 0.5 * h, y - 0.5 * h, y + 0.5 * h, cx, cy);
            if (open <= 0) continue;
            field[size_t(iy) * n + ix] = float(open);
            row0 = std::min(row0, iy);
            row1 = std::max(row1, iy + 1);
        }
    }
    fft2d(field, n, false, row0, row1);
    const double L = n * h, zr = 1.0 / g.ar, zt = 1.0 / g.at;
    for (int ky = 0; ky < n; ++ky) {
        const double ny = (ky < n / 2 ? ky : ky - n) / L;
        for (int kx = 0; kx < n; ++kx) {
            const double nx = (kx < n / 2 ? kx : kx - n) / L;
            const double nr = nx * g.er_x + ny * g.er_y, nt = -nx * g.er_y + ny * g.er_x;
            const double phase = -M_PI * q.wavelength * (zr * nr * nr + zt * nt * nt);
            const double gain = 1.0 / (box_response(nx * h) * box_response(ny * h));
            field[size_t(ky) * n + kx] *= std::complex<float>(float(gain * std::cos(phase)), float(gain * std::sin(phase)));
        }
    }
    fft2d(field, n, true, 0, n);
    // Each pixel: sum of |U|^2 h^2 over its points / transmitted power (the aperture's area);
    // kissfft's forward-inverse pair scales by n^2.
    const double scale = h * h / (double(n) * n * double(n) * n) / g.area;
    const int w = 2 * q.radius + 1;
    std::vector<float> weight(size_t(w) * w, 0.0f);
    for (int b = -q.radius; b <= q.radius; ++b)
        for (int a = -q.radius; a <= q.radius; ++a) {
            double s = 0;
            const int i0 = n / 2 + a * sub - sub / 2, j0 = n / 2 + b * sub - sub / 2;
            for (int j = j0; j < j0 + sub; ++j)
                for (int i = i0; i < i0 + sub; ++i) s += std::norm(field[size_t((j + n) % n) * n + (i + n) % n]);
            weight[size_t(b + q.radius) * w + (a + q.radius)] = float(s * scale);
        }
    return weight;
}

}  // namespace

PsfKernel field_psf_kernel(const FieldPsfRequest& q) {
    const FieldGeometry g = geometry_of(q);
    const MftPlan mft = plan_mft(q, g);
    const TransferPlan transfer = plan_transfer(q, g);
    const bool use_transfer = q.method == FieldPsfMethod::TransferFunction ||
                              (q.method == FieldPsfMethod::Auto && q.pupil_samples <= 0 && transfer.cost() < mft.cost());
    PsfKernel k;
    k.radius = q.radius;
    k.weight = use_transfer ? kernel_by_transfer(q, g, transfer) : kernel_by_mft(q, g, mft);
    return k;
}

int psf_kernel_radius(const Aperture& aperture, double film_distance, double nearest_depth, double wavelength,
                      double cos_theta_max, double pixel_pitch, int max_radius) {
    const double r = psf_radius(aperture, film_distance, nearest_depth, wavelength, cos_theta_max) / pixel_pitch;
    return std::clamp(int(std::ceil(r)), 1, max_radius);
}

}  // namespace wavecam
