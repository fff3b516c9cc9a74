// The exact propagator (propagation.h): scene -> pinhole samples -> film points, both legs the
// same phasor sum (phasor_sum.h) over path lengths taken as differences from a reference path,
// r - r0 = (r^2 - r0^2) / (r + r0), which float arithmetic keeps exact to a fraction of a
// wavelength over 10^6 wavelengths (docs/physics.md).

#include <cmath>

#include "optics/phasor_sum.h"
#include "base/parallel.h"
#include "base/progress_ticker.h"
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
// Finite source: exp(i k (r - |P|)) / r, r - |P| = (|xi|^2 - 2 xi.P) / (r + |P|).
// Plane wave along u: exp(-i k u.xi).
__attribute__((target_clones("arch=x86-64-v3", "default")))
void field_at_sample(const SourceArrays& a, float x, float y, float inv_lambda, double& re, double& im) {
    const float q = x * x + y * y;
    const float* __restrict px = a.px.data();
    const float* __restrict py = a.py.data();
    const float* __restrict p2 = a.p2.data();
    const float* __restrict pn = a.pn.data();
    re = im = 0;
    detail::phasor_sum(a.px.size(), a.cr.data(), a.ci.data(), [&](size_t s, float& turns, float& amp) {
        const float num = q - 2.0f * (x * px[s] + y * py[s]);
        const float r = std::sqrt(p2[s] + num);
        turns = num * inv_lambda / (r + pn[s]);
        amp = 1.0f / r;
    }, re, im);
    const float* __restrict ux = a.ux.data();
    const float* __restrict uy = a.uy.data();
    detail::phasor_sum(a.ux.size(), a.wr.data(), a.wi.data(), [&](size_t s, float& turns, float& amp) {
        turns = -(x * ux[s] + y * uy[s]) * inv_lambda;
        amp = 1.0f;
    }, re, im);
}

// A film point T = (tx, ty, -f) and r0sq = |T|^2.
struct FilmPoint {
    float tx, ty, f, r0sq;
};

// U at one film point T, up to the constant 1/lambda already in the field.
// Reference path |T| (a common phase per film point): r - |T| = (|xi|^2 - 2 xi.T) / (r + |T|);
// amplitude obliquity f/r times 1/r (Goodman eq. 3-41).
__attribute__((target_clones("arch=x86-64-v3", "default")))
void field_at_film_point(const ApertureSamples& smp, const PinholeField& field, const FilmPoint& T, float inv_lambda,
                         double& re, double& im) {
    const float tx = T.tx, ty = T.ty, f = T.f, r0sq = T.r0sq;
    const float r0 = std::sqrt(r0sq);
    const float* __restrict xs = smp.x.data();
    const float* __restrict ys = smp.y.data();
    re = im = 0;
    detail::phasor_sum(smp.size(), field.re.data(), field.im.data(), [&](size_t j, float& turns, float& amp) {
        const float x = xs[j], y = ys[j];
        const float num = x * (x - 2.0f * tx) + y * (y - 2.0f * ty);
        const float rsq = r0sq + num;
        turns = num * inv_lambda / (std::sqrt(rsq) + r0);
        amp = f / rsq;
    }, re, im);
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
    detail::parallel_for_dynamic(0, (n + kChunk - 1) / kChunk, 1, detail::thread_count(nthreads), [&](int64_t chunk) {
        if (ticker.cancelled()) return;
        const long c = chunk * kChunk, e = std::min(n, c + kChunk);
        for (long j = c; j < e; ++j) {
            double re, im;
            field_at_sample(a, samples.x[j], samples.y[j], inv_lambda, re, im);
            const double w = samples.weight[j] / wavelength;
            field.re[j] = static_cast<float>(re * w);
            field.im[j] = static_cast<float>(im * w);
        }
        ticker.advance(e - c, detail::on_calling_thread());
    });
    return !ticker.cancelled();
}

bool add_film_field(const FilmPropagation& propagation, std::complex<double>* film_field, int nthreads,
                    const ProgressFn& progress) {
    const ApertureSamples& samples = propagation.samples;
    const PinholeField& field = propagation.field;
    const FilmPoints& film = propagation.film;
    const double wavelength = propagation.wavelength;
    const long n = static_cast<long>(film.size());
    const double f = film.film_distance;
    const float inv_lambda = static_cast<float>(1.0 / wavelength);
    detail::ProgressTicker ticker(progress, double(n));
    detail::parallel_for_dynamic(0, n, 4, detail::thread_count(nthreads), [&](int64_t t) {
        if (ticker.cancelled()) return;
        const double tx = film.x[t], ty = film.y[t];
        double re, im;
        field_at_film_point(samples, field,
                            {film.x[t], film.y[t], static_cast<float>(f), static_cast<float>(tx * tx + ty * ty + f * f)},
                            inv_lambda, re, im);
        film_field[t] += std::complex<double>(re, im);
        ticker.advance(1, detail::on_calling_thread());
    });
    return !ticker.cancelled();
}

bool accumulate_film_irradiance(const FilmPropagation& propagation, double scale, float* irradiance, int nthreads,
                                const ProgressFn& progress) {
    const FilmPropagation& p = propagation;
    std::vector<std::complex<double>> u(p.film.size(), 0.0);
    if (!add_film_field(p, u.data(), nthreads, progress)) return false;
    for (size_t t = 0; t < u.size(); ++t) irradiance[t] += static_cast<float>(scale * std::norm(u[t]));
    return true;
}

}  // namespace wavecam
