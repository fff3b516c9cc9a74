#include <omp.h>

#include <cmath>

#include "progress_ticker.h"
#include "sincos_turns.h"
#include "wavecam/propagation.h"

namespace wavecam {
namespace {

// |U|^2 at one film point T = (tx, ty, -f), up to the constant 1/lambda already in the field.
// r - |T| = (|xi|^2 - 2 xi.T) / (r + |T|) (reference path |T|, a common phase per film point).
__attribute__((target_clones("arch=x86-64-v3", "default")))
double film_point_irradiance(const ApertureSamples& smp, const PinholeField& field, float tx, float ty,
                             float f, float r0sq, float inv_lambda) {
    const float r0 = std::sqrt(r0sq);
    const float* __restrict xs = smp.x.data();
    const float* __restrict ys = smp.y.data();
    const float* __restrict wr = field.re.data();
    const float* __restrict wi = field.im.data();
    const size_t n = smp.size();
    double acc_re = 0, acc_im = 0;
    constexpr size_t kBlock = 1024;  // float partial sums, double across blocks
    for (size_t b = 0; b < n; b += kBlock) {
        const size_t e = std::min(n, b + kBlock);
        float sr = 0, si = 0;
#pragma omp simd reduction(+ : sr, si)
        for (size_t j = b; j < e; ++j) {
            const float x = xs[j], y = ys[j];
            const float num = x * (x - 2.0f * tx) + y * (y - 2.0f * ty);
            const float rsq = r0sq + num;
            const float r = std::sqrt(rsq);
            float sn, cs;
            detail::sincos_turns(num * inv_lambda / (r + r0), sn, cs);
            const float amp = f / rsq;  // obliquity f/r times 1/r
            sr += amp * (wr[j] * cs - wi[j] * sn);
            si += amp * (wr[j] * sn + wi[j] * cs);
        }
        acc_re += sr;
        acc_im += si;
    }
    return acc_re * acc_re + acc_im * acc_im;
}

}  // namespace

bool accumulate_film_irradiance(const ApertureSamples& samples, const PinholeField& field,
                                const FilmPoints& film, double wavelength, double scale, float* irradiance,
                                int nthreads, const ProgressFn& progress) {
    const long n = static_cast<long>(film.size());
    const double f = film.film_distance;
    const float inv_lambda = static_cast<float>(1.0 / wavelength);
    detail::ProgressTicker ticker(progress, double(n));
#pragma omp parallel for schedule(dynamic, 4) num_threads(nthreads > 0 ? nthreads : omp_get_max_threads())
    for (long t = 0; t < n; ++t) {
        if (ticker.cancelled()) continue;
        const double tx = film.x[t], ty = film.y[t];
        const double i = film_point_irradiance(samples, field, film.x[t], film.y[t], static_cast<float>(f),
                                               static_cast<float>(tx * tx + ty * ty + f * f), inv_lambda);
        irradiance[t] += static_cast<float>(scale * i);
        ticker.advance(1, omp_get_thread_num() == 0);
    }
    return !ticker.cancelled();
}

}  // namespace wavecam
