// Throughput of the exact kernel (terms per second; one term = one pinhole sample contributing
// to one film point) against a straightforward scalar double-precision loop over the same case.
#include <benchmark/benchmark.h>

#include <cmath>
#include <complex>

#include "wavecam/propagation.h"

using namespace wavecam;

namespace {
// The case: the optimal pinhole of `wavecam psf`'s default (0.3 mm, f = 65 mm, 550 nm),
// a plane wave on axis, a 0.6 mm film window.
struct Case {
    double f = 65e-3, lambda = 550e-9;
    ApertureSamples samples = sample_aperture({ApertureShape::Circle, 0.3e-3}, sample_pitch(550e-9));
    PinholeField field;
    FilmPoints film;
    explicit Case(int n) {
        illuminate_pinhole(samples, {source_at_field_angle(INFINITY, 0)}, lambda, field);
        film.film_distance = f;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                film.x.push_back(static_cast<float>((i - n / 2) * 0.6e-3 / n));
                film.y.push_back(static_cast<float>((j - n / 2) * 0.6e-3 / n));
            }
    }
    double terms() const { return double(samples.size()) * film.size(); }
};

const Case& the_case() {
    static const Case c(16);
    return c;
}

void BM_ExactKernel(benchmark::State& state) {
    const Case& c = the_case();
    std::vector<float> out(c.film.size());
    for (auto _ : state) {
        accumulate_film_irradiance({c.samples, c.field, c.film, c.lambda}, 1.0, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["terms_per_s"] = benchmark::Counter(c.terms() * state.iterations(), benchmark::Counter::kIsRate);
}

// The same sum written the obvious way: double precision, absolute path lengths, std::exp.
void BM_ScalarDoubleLoop(benchmark::State& state) {
    const Case& c = the_case();
    const double k = 2 * M_PI / c.lambda;
    std::vector<double> out(c.film.size());
    for (auto _ : state) {
        for (size_t t = 0; t < c.film.size(); ++t) {
            std::complex<double> u = 0;
            for (size_t j = 0; j < c.samples.size(); ++j) {
                const double dx = c.film.x[t] - c.samples.x[j], dy = c.film.y[t] - c.samples.y[j];
                const double r = std::sqrt(dx * dx + dy * dy + c.f * c.f);
                u += std::complex<double>(c.field.re[j], c.field.im[j]) * std::polar(c.f / (r * r), k * r);
            }
            out[t] = std::norm(u);
        }
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["terms_per_s"] = benchmark::Counter(c.terms() * state.iterations(), benchmark::Counter::kIsRate);
}
}  // namespace

BENCHMARK(BM_ScalarDoubleLoop)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK(BM_ExactKernel)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK_MAIN();
