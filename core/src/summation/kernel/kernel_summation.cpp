// The kernel summation's runs (kernel_summation.h, KernelSummation::run): the sources' weighted images per
// basis kernel, their convolutions with the kernels' spectra, and each pixel's film; the memo.
#include "summation/kernel/kernel_summation.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "base/parallel.h"
#include "summation/kernel/kernel_summation_impl.h"

namespace wavecam::detail {

namespace {

using Impl = KernelSummation::Impl;

Result<bool> cancelled() { return Result<bool>::failure("cancelled", ErrorKind::Cancelled); }

// Per run and basis kernel r, the sources' weights times the share of r in their blended
// kernel, sum over the blend of weight x coefficient[k][r], on the transform's grid (every
// point written, the padding's zeros too: hundreds of MiB at 1080p, not cleared first), in
// planes P apart (the spectra's whole chunks; the GPU's transforms take N), into m.image.
void weigh_sources(const Impl& m, const KernelSummationSources& sources, size_t P) {
    const KernelSummationGeometry& g = m.g;
    const KernelBasis& basis = m.basis;
    const int B = basis.rank, runs = sources.runs;
    const size_t n = size_t(g.width) * g.height;
    std::vector<std::complex<float>>& image = m.image;
    image.resize(size_t(runs) * B * P);
    const std::complex<float> zero(0);
    parallel_for(0, g.ny, m.threads, [&](int64_t j_) {
        const int j = int(j_);
        std::vector<std::complex<double>> share(B);
        for (int kr = 0; kr < runs * B; ++kr) {
            std::complex<float>* row = image.data() + size_t(kr) * P + size_t(j) * g.nx;
            std::fill(row + (j < g.height ? g.width : 0), row + g.nx, zero);
            if (j == g.ny - 1) std::fill(row + g.nx, image.data() + size_t(kr + 1) * P, zero);
        }
        if (j >= g.height) return;
        for (int i = 0; i < g.width; ++i) {
            size_t index[8];
            double weight[8];
            const int used = m.blend_of(sources, i, j, index, weight);
            std::fill(share.begin(), share.end(), 0.0);
            for (int u = 0; u < used; ++u)
                for (int r = 0; r < B; ++r) share[r] += weight[u] * basis.coefficient[index[u] * B + r];
            for (int k = 0; k < runs; ++k) {
                const std::complex<float> w = sources.weight[size_t(k) * n + size_t(j) * g.width + i];
                for (int r = 0; r < B; ++r)
                    image[(size_t(k) * B + r) * P + size_t(j) * g.nx + i] =
                        w == zero ? zero : std::complex<float>(share[r]) * w;
            }
        }
    });
}

// Per run and domain point of the transform's grid, the sum over sub-points of |u|^2 (or Re u),
// into m.film: the images through the device's transforms and spectra.
Result<bool> film_on_device(const Impl& m, int runs, const ProgressFn& progress) {
    const int B = m.basis.rank;
    const size_t N = m.fft->size();
    std::vector<std::complex<float>>& image = m.image;
    std::vector<double>& film = m.film;
    for (int k = 0; k < runs; ++k) {
        m.gpu->begin_run();
        for (int r = 0; r < B; ++r) {
            if (progress && !progress((k * (B + 1.0) + r + 1) / (runs * (B + 1.0)))) return cancelled();
            const auto first = image.begin() + (size_t(k) * B + r) * N;
            std::copy(first, first + N, m.gpu->sources());
            if (auto e = m.gpu->add_sources(r); !e.ok()) return e;
        }
        std::vector<float> sum;
        if (auto e = m.gpu->finish_run(m.spec.incoherent, sum); !e.ok()) return e;
        std::copy(sum.begin(), sum.end(), film.begin() + size_t(k) * N);
    }
    return Result<bool>::success(true);
}

// The same here: the images' transforms, their products with the spectra and the inverse
// transforms, in planes P apart.
Result<bool> film_on_cpu(const Impl& m, int runs, size_t P, const ProgressFn& progress) {
    const KernelSummationGeometry& g = m.g;
    const int M = m.modes.count, B = m.basis.rank;
    const size_t N = m.fft->size();
    std::vector<std::complex<float>>& image = m.image;
    std::vector<double>& film = m.film;
    // A large grid's transforms are spread over the threads one at a time; a small one's
    // (complex_fft2d.h: one thread each) go to the threads whole.
    const bool whole = N < ComplexFft2D::kParallelPoints;
    parallel_for_dynamic(0, runs * B, 1, whole ? m.threads : 1, [&](int64_t kr_) {
        const int kr = int(kr_);
        m.fft->forward(image.data() + size_t(kr) * P, g.height);
    });
    if (progress && !progress(0.4)) return cancelled();
    // the products, summed over the basis per run and mode (basis_spectra.h): a chunk of
    // points at a time, its spectra read once for all the runs at once
    std::vector<std::complex<float>>& total = m.total;
    total.resize(size_t(runs) * M * P);
    const long chunks = long(m.spectra.chunks());
    parallel_for(0, chunks, m.threads, [&](int64_t c) {
        for (int k = 0; k < runs; ++k)
            m.spectra.mix(size_t(c), image.data() + size_t(k) * B * P, total.data() + size_t(k) * M * P);
    });
    if (progress && !progress(0.7)) return cancelled();
    parallel_for_dynamic(0, runs * M, 1, whole ? m.threads : 1, [&](int64_t km_) {
        const int km = int(km_);
        m.fft->inverse(total.data() + size_t(km) * P);
    });
    const bool incoherent = m.spec.incoherent;
    const size_t block = 4096;
    const long blocks = long((N + block - 1) / block);
    parallel_for(0, blocks, m.threads, [&](int64_t b) {
        const size_t q0 = size_t(b) * block, q1 = std::min(N, q0 + block);
        for (int k = 0; k < runs; ++k)
            for (int mode = 0; mode < M; ++mode) {
                const std::complex<float>* u = total.data() + (size_t(k) * M + mode) * P;
                double* f = film.data() + size_t(k) * N;
                for (size_t q = q0; q < q1; ++q) f[q] += incoherent ? u[q].real() : std::norm(u[q]);
            }
    });
    return Result<bool>::success(true);
}

// Run by run, each pixel's mean over its points, then `each`, added to `irradiance` (camera
// rows `rows`, columns within the overscan).
void add_film(const Impl& m, int runs, double scale, const RowRange& rows, const float* each, float* irradiance) {
    const KernelSummationGeometry& g = m.g;
    const size_t N = m.fft->size();
    const std::vector<double>& film = m.film;
    const PinholeCamera& c = m.spec.camera;
    const int o = m.spec.overscan;
    const double coherent = 1.0 / (double(N) * N), incoherent = 1.0 / double(N);
    const double norm = scale / m.points() * (m.spec.incoherent ? incoherent : coherent);
    // (each run one addition per pixel, as the point sums' runs: a job is then the sum of its
    // shares' runs to the bit)
    for (int k = 0; k < runs; ++k) {
        const double* f = film.data() + size_t(k) * N;
        for (int cj = 0; cj < c.height; ++cj)
            for (int ci = 0; ci < c.width; ++ci) {
                const size_t p = size_t(cj) * c.width + ci;
                const bool lit = cj >= rows.begin && cj < rows.end && ci >= o && ci < c.width - o;
                const double v = (lit ? f[size_t(cj + g.origin) * g.nx + ci + g.origin] * norm : 0.0) +
                                 (each ? scale * each[p] : 0.0);
                if (v != 0) irradiance[p] += float(v);
            }
    }
}

}  // namespace

KernelSummation::KernelSummation() = default;
KernelSummation::~KernelSummation() = default;
KernelSummation::KernelSummation(KernelSummation&&) noexcept = default;
KernelSummation& KernelSummation::operator=(KernelSummation&&) noexcept = default;
int KernelSummation::radius() const { return impl_->g.radius; }
bool KernelSummation::on_gpu() const { return bool(impl_->gpu); }
int KernelSummation::domain_width() const { return impl_->g.width; }
int KernelSummation::domain_height() const { return impl_->g.height; }
int KernelSummation::origin() const { return impl_->g.origin; }
const DepthLayers& KernelSummation::layers() const { return impl_->g.layers; }

Result<bool> KernelSummation::run(const KernelSummationSources& sources, double scale, const RowRange& rows,
                               const float* each, float* irradiance, const ProgressFn& progress) const {
    const Impl& m = *impl_;
    if (m.directions) return m.directions->run(sources, scale, rows, irradiance, progress);  // (no tail: `each` is 0)
    const int runs = sources.runs;
    const size_t N = m.fft->size();
    if (progress && !progress(0.0)) return cancelled();
    std::lock_guard<std::mutex> lock(m.busy);
    const size_t P = m.gpu ? N : m.spectra.plane();
    weigh_sources(m, sources, P);
    m.film.assign(size_t(runs) * N, 0.0);
    if (auto r = m.gpu ? film_on_device(m, runs, progress) : film_on_cpu(m, runs, P, progress); !r.ok()) return r;
    add_film(m, runs, scale, rows, each, irradiance);
    if (progress && !progress(1.0)) return cancelled();
    return Result<bool>::success(true);
}

int KernelSummation::runs_at_once() const {
    const Impl& m = *impl_;
    if (m.directions) return m.directions->runs_at_once();
    const double N = double(m.fft->size()), B = m.basis.rank, M = m.modes.count;
    // a run's images, sums and film against the kernels' spectra (none kept here on a GPU)
    const double run = N * (8 * (B + M) + 8), spectra = m.gpu ? 0 : 8 * N * B * M;
    return int(std::clamp(std::floor(spectra / run), 1.0, double(kMaxRunsAtOnce)));
}

Result<std::shared_ptr<const KernelSummation>> KernelSummationMemo::get(const KernelSummationSpec& spec, double pitch,
                                                                  const Make& make) {
    using R = Result<std::shared_ptr<const KernelSummation>>;
    std::lock_guard<std::mutex> lock(busy_);
    const PinholeCamera &a = spec.camera, &b = spec_.camera;
    const bool same = kept_ && a.width == b.width && a.height == b.height && a.fov_h == b.fov_h &&
                      a.film_distance == b.film_distance && spec.overscan == spec_.overscan &&
                      spec.wavelength == spec_.wavelength && spec.max_inverse_depth == spec_.max_inverse_depth &&
                      spec.subsamples == spec_.subsamples && spec.incoherent == spec_.incoherent &&
                      kernel_energy(spec) == kernel_energy(spec_) && pitch == pitch_;
    if (!same) {
        kept_.reset();  // (its memory free before the next is made)
        auto made = make();
        if (!made.ok()) return R::failure(made);
        kept_ = std::make_shared<const KernelSummation>(std::move(made.value));
        spec_ = spec;
        pitch_ = pitch;
    }
    return R::success(kept_);
}

}  // namespace wavecam::detail
