// The rate of core's transform (fft/column_fft.h) as the transfer-function PSFs run it: a block
// of columns that fits one thread's cache, every column an n-point complex transform, at the
// grid sizes of large pinholes' kernel tables (1350-1944 points). Where FFTW is found at build
// time (a benchmark only: its GPL keeps it out of core and the plugin), FFTW's plan for the
// same columns (fftwf_plan_many_dft, FFTW_MEASURE) beside it, as the machine's reference rate.
// Counters: GFlop/s at the customary 5 n log2 n flops a complex transform, one thread.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "fft/column_fft.h"
#ifdef WAVECAM_BENCH_FFTW
#include <fftw3.h>
#endif

using wavecam::detail::ColumnFft;

namespace {
void set_rate(benchmark::State& state, int n, int columns) {
    const double flops = 5.0 * n * std::log2(double(n)) * columns;
    state.counters["GFlop/s"] = benchmark::Counter(flops * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}

std::vector<std::complex<float>> columns_of(int n, int columns) {
    std::vector<std::complex<float>> v(size_t(n) * columns);
    for (size_t i = 0; i < v.size(); ++i) v[i] = {float(std::sin(0.37 * double(i))), float(std::cos(0.11 * double(i)))};
    return v;
}

void BM_CoreColumnBlock(benchmark::State& state) {
    const int n = int(state.range(0)), columns = ColumnFft::block_columns(n);
    const ColumnFft fft(n, true);
    std::vector<std::complex<float>> data = columns_of(n, columns), work(data.size());
    for (auto _ : state) benchmark::DoNotOptimize(fft.transform_where(data.data(), work.data(), columns, 0, columns));
    set_rate(state, n, columns);
}

#ifdef WAVECAM_BENCH_FFTW
// as_columns: the core's layout (point k of column c at k * columns + c); else each transform's
// points contiguous, FFTW's own preference
void fftw_block(benchmark::State& state, bool as_columns) {
    const int n = int(state.range(0)), columns = ColumnFft::block_columns(n);
    std::vector<std::complex<float>> data(size_t(n) * columns), out(data.size());
    auto* in = reinterpret_cast<fftwf_complex*>(data.data());
    auto* to = reinterpret_cast<fftwf_complex*>(out.data());
    const int stride = as_columns ? columns : 1, dist = as_columns ? 1 : n;
    const fftwf_plan plan =
        fftwf_plan_many_dft(1, &n, columns, in, nullptr, stride, dist, to, nullptr, stride, dist, FFTW_BACKWARD, FFTW_MEASURE);
    const std::vector<std::complex<float>> values = columns_of(n, columns);
    std::copy(values.begin(), values.end(), data.begin());  // (planning with FFTW_MEASURE overwrites them)
    for (auto _ : state) {
        fftwf_execute(plan);
        benchmark::DoNotOptimize(out.data());
    }
    fftwf_destroy_plan(plan);
    set_rate(state, n, columns);
}
void BM_FftwColumnBlock(benchmark::State& state) { fftw_block(state, true); }
void BM_FftwContiguous(benchmark::State& state) { fftw_block(state, false); }
BENCHMARK(BM_FftwColumnBlock)->Arg(1350)->Arg(1440)->Arg(1600)->Arg(1944);
BENCHMARK(BM_FftwContiguous)->Arg(1350)->Arg(1440)->Arg(1600)->Arg(1944);
#endif
}  // namespace

BENCHMARK(BM_CoreColumnBlock)->Arg(1350)->Arg(1440)->Arg(1600)->Arg(1944);
BENCHMARK_MAIN();
