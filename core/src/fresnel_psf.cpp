#include "wavecam/fresnel_psf.h"

#include <algorithm>
#include <cmath>

namespace wavecam {
namespace {

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

}  // namespace

PsfKernel field_psf_kernel(const FieldPsfRequest& q) {
    const double f = q.film_distance, lambda = q.wavelength;
    const double tan2 = q.u * q.u + q.v * q.v;
    const double c = 1.0 / std::sqrt(1.0 + tan2);  // cos theta
    const double alpha = (std::isinf(q.depth) ? 0.0 : 1.0 / q.depth) + 1.0 / f;
    const double ar = c * c * c * alpha, at = c * alpha;
    // Radial unit vector in image (column, row) coordinates; any axis on axis.
    const double rn = std::sqrt(tan2);
    const double er_x = rn > 0 ? q.u / rn : 1.0, er_y = rn > 0 ? -q.v / rn : 0.0;

    // Pupil on an n x n grid in (r, t) axes; cell weights from the aperture's coverage (the
    // aperture's own x, y axes rotated by the field azimuth).
    const double span = 2 * q.aperture.bounding_radius();
    // The quadratic phase spans N = (span/2)^2 alpha / lambda half-period zones; its slope at the
    // rim is 2 pi N / (span/2) per metre, so 8 N samples across keep the phase step below pi/2
    // (no aliased copies of the PSF), and never fewer than 64.
    const double zones = 0.25 * span * span * alpha / lambda;
    // The sampled pupil's transform repeats every 1 / h in frequency, that is every
    // lambda f / (h cos) on the film: the output grid (half-width `extent`) must fit in one
    // period or shifted copies of the PSF appear, so n >= 2 span extent cos / (lambda f).
    const double step = q.pixel_pitch / q.subsamples;
    const int half = int(std::ceil((q.radius + 1) * std::sqrt(2.0) * q.pixel_pitch / step));
    const double extent = half * step;
    const int n = q.pupil_samples > 0
                      ? q.pupil_samples
                      : std::clamp(2 * int(std::ceil(std::max(4 * zones, 1.1 * span * extent * c / (lambda * f)))),
                                   64, 2048);
    const double h = span / n;
    std::vector<double> xi(n);
    for (int k = 0; k < n; ++k) xi[k] = (k - 0.5 * (n - 1)) * h;
    std::vector<float> pupil_re(size_t(n) * n), pupil_im(size_t(n) * n);
    for (int ir = 0; ir < n; ++ir)
        for (int it = 0; it < n; ++it) {
            // sub-sampled coverage of the rotated cell
            constexpr int kSub = 4;
            double open = 0;
            for (int s = 0; s < kSub * kSub; ++s) {
                const double r = xi[ir] + ((s % kSub) + 0.5 - 0.5 * kSub) * h / kSub;
                const double t = xi[it] + ((s / kSub) + 0.5 - 0.5 * kSub) * h / kSub;
                const double x = r * er_x - t * er_y, y = r * er_y + t * er_x;
                open += q.aperture.transmission(-x, y);  // (x, y): image (column, row); pupil +x lands at column -x
            }
            open /= kSub * kSub;
            const double phase = M_PI / lambda * (ar * xi[ir] * xi[ir] + at * xi[it] * xi[it]);
            pupil_re[size_t(ir) * n + it] = float(open * std::cos(phase));
            pupil_im[size_t(ir) * n + it] = float(open * std::sin(phase));
        }

    // Output grid in (r, t) film offsets: spacing pitch / subsamples (`step`), covering the
    // kernel square rotated by any angle (`half` steps each side).
    const int m = 2 * half + 1;
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

    // Area-average each kernel pixel from the (r, t) grid by bilinear interpolation.
    PsfKernel k;
    k.radius = q.radius;
    const int w = 2 * q.radius + 1, sub = q.subsamples;
    k.weight.assign(size_t(w) * w, 0.0f);
    auto sample = [&](double r, double t) {
        const double fr = r / step + half, ft = t / step + half;
        const int i0 = int(std::floor(fr)), j0 = int(std::floor(ft));
        if (i0 < 0 || j0 < 0 || i0 + 1 >= m || j0 + 1 >= m) return 0.0;
        const double a = fr - i0, b = ft - j0;
        auto I = [&](int i, int j) { return double(intensity[size_t(i) * m + j]); };
        return (1 - a) * ((1 - b) * I(i0, j0) + b * I(i0, j0 + 1)) + a * ((1 - b) * I(i0 + 1, j0) + b * I(i0 + 1, j0 + 1));
    };
    double total = 0;
    for (int b = -q.radius; b <= q.radius; ++b)
        for (int a = -q.radius; a <= q.radius; ++a) {
            double s = 0;
            for (int sb = 0; sb < sub; ++sb)
                for (int sa = 0; sa < sub; ++sa) {
                    // image offset (column, row) in metres on the film
                    const double x = (a + (sa + 0.5) / sub - 0.5) * q.pixel_pitch;
                    const double y = (b + (sb + 0.5) / sub - 0.5) * q.pixel_pitch;
                    s += sample(x * er_x + y * er_y, -x * er_y + y * er_x);
                }
            k.weight[size_t(b + q.radius) * w + (a + q.radius)] = float(s);
            total += s;
        }
    if (total > 0)
        for (float& x : k.weight) x = float(x / total);
    return k;
}

int psf_kernel_radius(const Aperture& aperture, double film_distance, double nearest_depth, double wavelength,
                      double cos_theta_max, double pixel_pitch, int max_radius) {
    const double shadow = 0.5 * aperture.diameter * (1.0 + film_distance / nearest_depth);
    const double airy = 1.22 * wavelength * film_distance / aperture.diameter;
    const double c3 = std::pow(cos_theta_max, 3);
    const double r = (shadow + 5.0 * airy) / c3 / pixel_pitch;
    return std::clamp(int(std::ceil(r)), 1, max_radius);
}

}  // namespace wavecam
