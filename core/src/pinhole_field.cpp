#include <omp.h>

#include <cmath>

#include "progress_ticker.h"
#include "sincos_turns.h"
#include "wavecam/propagation.h"

namespace wavecam {
namespace {

// Sources as structure of arrays; complex amplitude c = a exp(i phase).
struct SourceArrays {
    // finite sources: position, |P|^2, |P|
    std::vector<float> px, py, pz, p2, pn, cr, ci;
    // plane waves: direction
    std::vector<float> ux, uy, wr, wi;
};

SourceArrays split_sources(const std::vector<PointSource>& sources) {
    SourceArrays a;
    for (const PointSource& s : sources) {
        const float cr = static_cast<float>(s.amplitude * std::cos(s.phase));
        const float ci = static_cast<float>(s.amplitude * std::sin(s.phase));
        if (s.at_infinity) {
            a.ux.push_back(static_cast<float>(s.x));
            a.uy.push_back(static_cast<float>(s.y));
            a.wr.push_back(cr);
            a.wi.push_back(ci);
        } else {
            const double p2 = s.x * s.x + s.y * s.y + s.z * s.z;
            a.px.push_back(static_cast<float>(s.x));
            a.py.push_back(static_cast<float>(s.y));
            a.pz.push_back(static_cast<float>(s.z));
            a.p2.push_back(static_cast<float>(p2));
            a.pn.push_back(static_cast<float>(std::sqrt(p2)));
            a.cr.push_back(cr);
            a.ci.push_back(ci);
        }
    }
    return a;
}

// Field at one pinhole sample (x, y, 0), summed over all sources.
// Finite source: r - |P| = (|xi|^2 - 2 xi.P) / (r + |P|), no cancellation.
__attribute__((target_clones("arch=x86-64-v3", "default")))
void sum_sources(const SourceArrays& a, float x, float y, float inv_lambda, double& out_re, double& out_im) {
    const float q = x * x + y * y;
    double acc_re = 0, acc_im = 0;
    constexpr size_t kBlock = 1024;  // float partial sums, double across blocks
    const float* __restrict px = a.px.data();
    const float* __restrict py = a.py.data();
    const float* __restrict p2 = a.p2.data();
    const float* __restrict pn = a.pn.data();
    const float* __restrict cr = a.cr.data();
    const float* __restrict ci = a.ci.data();
    const size_t nf = a.px.size();
    for (size_t b = 0; b < nf; b += kBlock) {
        const size_t e = std::min(nf, b + kBlock);
        float sr = 0, si = 0;
#pragma omp simd reduction(+ : sr, si)
        for (size_t s = b; s < e; ++s) {
            const float num = q - 2.0f * (x * px[s] + y * py[s]);
            const float r = std::sqrt(p2[s] + num);
            float sn, cs;
            detail::sincos_turns(num * inv_lambda / (r + pn[s]), sn, cs);
            const float amp = 1.0f / r;
            sr += amp * (cr[s] * cs - ci[s] * sn);
            si += amp * (cr[s] * sn + ci[s] * cs);
        }
        acc_re += sr;
        acc_im += si;
    }
    const float* __restrict ux = a.ux.data();
    const float* __restrict uy = a.uy.data();
    const float* __restrict wr = a.wr.data();
    const float* __restrict wi = a.wi.data();
    const size_t np = a.ux.size();
    for (size_t b = 0; b < np; b += kBlock) {
        const size_t e = std::min(np, b + kBlock);
        float sr = 0, si = 0;
#pragma omp simd reduction(+ : sr, si)
        for (size_t s = b; s < e; ++s) {
            float sn, cs;
            detail::sincos_turns(-(x * ux[s] + y * uy[s]) * inv_lambda, sn, cs);
            sr += wr[s] * cs - wi[s] * sn;
            si += wr[s] * sn + wi[s] * cs;
        }
        acc_re += sr;
        acc_im += si;
    }
    out_re = acc_re;
    out_im = acc_im;
}

}  // namespace

bool illuminate_pinhole(const ApertureSamples& samples, const std::vector<PointSource>& sources,
                        double wavelength, PinholeField& field, int nthreads, const ProgressFn& progress) {
    const SourceArrays a = split_sources(sources);
    const long n = static_cast<long>(samples.size());
    field.re.assign(n, 0.0f);
    field.im.assign(n, 0.0f);
    const float inv_lambda = static_cast<float>(1.0 / wavelength);
    detail::ProgressTicker ticker(progress, double(n));
    constexpr long kChunk = 256;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads > 0 ? nthreads : omp_get_max_threads())
    for (long c = 0; c < n; c += kChunk) {
        if (ticker.cancelled()) continue;
        const long e = std::min(n, c + kChunk);
        for (long j = c; j < e; ++j) {
            double re, im;
            sum_sources(a, samples.x[j], samples.y[j], inv_lambda, re, im);
            const double w = samples.weight[j] / wavelength;
            field.re[j] = static_cast<float>(re * w);
            field.im[j] = static_cast<float>(im * w);
        }
        ticker.advance(e - c, omp_get_thread_num() == 0);
    }
    return !ticker.cancelled();
}

}  // namespace wavecam
