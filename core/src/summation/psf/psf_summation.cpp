#include "summation/psf/psf_summation.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstdio>
#include <mutex>

#include "summation/psf/psf_summation_geometry.h"
#include "summation/psf/psf_kernel.h"
#include "summation/psf/basis_spectra.h"
#include "fft/complex_fft2d.h"
#include "convolution/far_tail.h"
#include "gpu/compute_device_impl.h"
#include "gpu/gpu_psf_summation.h"
#include "summation/psf/kernel_basis.h"
#include "fft/real_fft2d.h"
#include "summation/choose.h"
#include "wavecam/fresnel_psf.h"
#include "wavecam/convolution_method.h"
#include "wavecam/scene_diffraction.h"

namespace wavecam::detail {

namespace {

// The bilinear hat of knot `k` at pixel `i`: 1 on the knot itself, falling to 0 at its
// neighbours; the outermost knots keep 1 beyond them.
double hat(const AnchorAxis& axis, int k, int i) {
    const int cell = axis.cell_of(i);
    const double t = std::clamp(double(i - axis.knots[cell]) / (axis.knots[cell + 1] - axis.knots[cell]), 0.0, 1.0);
    return k == cell ? 1 - t : k == cell + 1 ? t : 0.0;
}

// A transform side the GPU's FFTs take (gpu_psf_summation.h): the next power of two.
int gpu_side(int n) {
    int p = 2;
    while (p < n) p *= 2;
    return p;
}

}  // namespace

struct PsfSummation::Impl {
    PsfSummationSpec spec;
    PsfSummationGeometry g;
    int threads = 1;
    std::unique_ptr<ComplexFft2D> fft;
    KernelBasis basis;  // the kernels (layer x anchors + anchor) as combinations of a few
    BasisSpectra spectra;  // the basis kernels' spectra per mode (none on a GPU)
    // the runs on a Vulkan device (the spectra kept there), or none: on the CPU
    std::unique_ptr<GpuPsfSummation> gpu;
    // a run's images (one per basis kernel), sums (one per sub-point) and film values, kept from
    // run to run (hundreds of MiB at 1080p: allocated once, not every run); one run at a time
    mutable std::mutex busy;
    mutable std::vector<std::complex<float>> image, total;
    mutable std::vector<double> film;
    KernelTable tail;  // layers, anchors and, in deficit's first entry, the light beyond each kernel
    // Re <K_i, K_j> (the pixel-mean over sub-points) for kernels i = layer x anchors + anchor
    // and, where there are more than kMaxBasisKernels, only their neighbours j in layer and
    // both anchor axes (0 elsewhere)
    std::vector<double> gram;
    size_t kernel_index(int layer, int anchor) const { return size_t(layer) * g.anchors() + anchor; }
    // Coherent runs: per kernel its pixel image I (each pixel's mean of |K|^2 over its film
    // points), and per kernel and neighbour (kNeighbours: layer and both anchor axes within one)
    // the pixel image J of |K - K'|^2, (2R + 1)^2 values each (add_blend_mean)
    static constexpr int kNeighbours = 27;
    std::vector<float> pixel_image, difference_image;
    int neighbour(size_t k, size_t other) const {
        const int A = g.anchors(), nax = int(g.ax.knots.size());
        const int l = int(k) / A, a = int(k) % A, l2 = int(other) / A, a2 = int(other) % A;
        return (l2 - l + 1) * 9 + (a2 / nax - a / nax + 1) * 3 + (a2 % nax - a % nax + 1);
    }

    int points() const { return spec.subsamples * spec.subsamples; }
    // The film's sub-point fields U_sub, as the runs sum them: modes U_m = sum_sub mode[m][sub] U_sub
    // (sub_point_modes)
    SubPointModes modes;
    // The kernels that domain pixel (i, j)'s source blends, and their weights (at most 8): bilinear
    // over the anchors round it, linear between its two layers.
    int blend_of(const PsfSummationSources& s, int i, int j, size_t* index, double* weight) const {
        const size_t p = size_t(j) * g.width + i;
        const int cx = g.ax.cell_of(i), cy = g.ay.cell_of(j), lower = s.lower[p], nax = int(g.ax.knots.size());
        int used = 0;
        for (int dl = 0; dl < 2; ++dl) {
            const double share = dl == 0 ? 1.0 - s.upper_share[p] : s.upper_share[p];
            if (share == 0 || lower + dl >= g.layers.count) continue;
            for (int corner = 0; corner < 4; ++corner) {
                const int kx = cx + (corner & 1), ky = cy + (corner >> 1);
                if (kx >= nax || ky >= int(g.ay.knots.size())) continue;
                const double w = share * hat(g.ax, kx, i) * hat(g.ay, ky, j);
                if (w == 0) continue;
                index[used] = kernel_index(lower + dl, ky * nax + kx);
                weight[used++] = w;
            }
        }
        return used;
    }
};

PsfSummation::PsfSummation() = default;
PsfSummation::~PsfSummation() = default;
PsfSummation::PsfSummation(PsfSummation&&) noexcept = default;
PsfSummation& PsfSummation::operator=(PsfSummation&&) noexcept = default;
int PsfSummation::radius() const { return impl_->g.radius; }
int PsfSummation::domain_width() const { return impl_->g.width; }
int PsfSummation::domain_height() const { return impl_->g.height; }
int PsfSummation::origin() const { return impl_->g.origin; }
const DepthLayers& PsfSummation::layers() const { return impl_->g.layers; }

Result<PsfSummation> PsfSummation::create(const PsfSummationSpec& spec, double lattice_pitch,
                                          const UnitSource& unit_source, const ProgressFn& progress) {
    using R = Result<PsfSummation>;
    auto impl = std::make_unique<Impl>();
    impl->spec = spec;
    PsfSummationGeometry& g = impl->g;
    g = psf_summation_geometry(spec);
    if (g.layers.count > kMaxPsfLayers) return R::failure(too_many_layers());
    impl->threads = spec.settings.nthreads > 0 ? spec.settings.nthreads : omp_get_max_threads();
    const int n = spec.subsamples, S = impl->points(), side = 2 * g.radius + 1, A = g.anchors();
    const PinholeCamera& c = spec.camera;
    KernelTable& tail = impl->tail;
    tail.radius = g.radius;
    tail.layers = g.layers;
    tail.ax = g.ax;
    tail.ay = g.ay;
    tail.deficit.assign(size_t(g.layers.count) * A * 9, 0.0f);
    // every kernel (sub-point by sub-point, (2R + 1)^2 each): amplitudes, or powers in .real()
    std::vector<std::vector<std::complex<double>>> kernel(size_t(g.layers.count) * A);
    // how the kernels' sums are evaluated (choose.h: one source's directly)
    const KernelSums sums = kernel_sums(spec, g);
    const ApertureSamples samples = sample_aperture(spec.aperture, lattice_pitch);
    // The kernels of anchor a, every layer (psf_kernel.h), and the light beyond each.
    const KernelSetup setup{&spec, &g, &samples, sums.to_pinhole, unit_source};
    std::vector<double> depths(size_t(g.layers.count));
    for (int l = 0; l < g.layers.count; ++l) depths[size_t(l)] = g.layers.inverse_depth(l);
    auto anchor_kernels = [&](int a, const SummationSettings& settings, PlanScope& film_scope) -> Result<bool> {
        const int px = g.ax.knots[a % g.ax.knots.size()] - g.origin, py = g.ay.knots[a / g.ax.knots.size()] - g.origin;
        std::vector<std::vector<std::complex<double>>> fields;
        if (auto r = source_kernels(setup, px, py, depths, settings, film_scope, fields); !r.ok()) return r;
        for (int l = 0; l < g.layers.count; ++l) {
            std::vector<std::complex<double>>& film_field = fields[size_t(l)];
            // the light beyond the kernel: its share of the Fresnel PSF's power, times the light
            // within it, per unit of the far tail's source light (radiance x cos^4, far_tail.cpp;
            // a source here is radiance x its solid angle t^2 cos^3). Where the Fresnel PSF is
            // evaluated only out to a reach short of the kernel's edge (PSFs far narrower than a
            // pixel), the share beyond the edge follows the sharp edge's far tail, whose energy
            // beyond r falls as 1/r (far_tail.h): taking the share beyond the reach put the light
            // between reach and edge twice, once in the kernel's sums and once in the far tail
            // (a 0.15 px PSF on the axis of a 120 deg frame: 1.5% of its light, against 0.16%
            // beyond its 16 px kernel).
            FieldPsfRequest q;
            q.aperture = spec.aperture;
            q.film_distance = c.film_distance;
            q.depth = g.layers.inverse_depth(l) > 0 ? 1.0 / g.layers.inverse_depth(l) : INFINITY;
            q.wavelength = spec.wavelength;
            c.tangent(px + 0.5, py + 0.5, q.u, q.v);
            q.pixel_pitch = c.pixel_pitch();
            q.radius = g.radius;
            q.subsamples = n;
            const PsfKernel model = field_psf_kernel(q);
            double held = 0, within = 0;
            for (const float x : model.weight) held += x;
            const double edge = (g.radius + 0.5) * c.pixel_pitch();
            const double beyond = std::max(0.0, 1 - held) * std::min(1.0, model.reach / edge);
            for (const std::complex<double>& k : film_field) within += std::norm(k) / S;
            const double missing = held > 0 ? within * beyond / (1 - beyond) : 0.0;
            tail.deficit[(size_t(l) * A + a) * 9] =
                float(missing * c.tan_pitch() * c.tan_pitch() * std::sqrt(1 + q.u * q.u + q.v * q.v));
            if (spec.incoherent)
                for (auto& k : film_field) k = std::norm(k);
            kernel[impl->kernel_index(l, a)] = std::move(film_field);
        }
        return Result<bool>::success(true);
    };
    // Where the aperture is even along an axis, an anchor and its mirror image across the optical
    // axis have mirror-image kernels (psf_summation_geometry.cpp): one of each pair is computed.
    tail.source =
        mirror_sources(g.ax, g.ay, g.width - 1, g.height - 1, spec.aperture.even_in_x(), spec.aperture.even_in_y());
    const std::vector<int>& source = tail.source;
    std::vector<int> computed;
    for (int a = 0; a < A; ++a)
        if (source[a] == a) computed.push_back(a);
    const int C = int(computed.size());
    // The anchor nearest the frame's centre fixes the film sums' evaluator (a corner's film
    // points at a wide field took the cost model minutes); the others follow, one anchor per
    // thread on the CPU (a device's plans are not for concurrent use), reporting from the
    // first thread.
    PlanScope film_scope;
    const auto cancelled = [] { return R::failure("cancelled", ErrorKind::Cancelled); };
    const int first = source[g.ay.knots.size() / 2 * g.ax.knots.size() + g.ax.knots.size() / 2];
    const SummationSettings& kernel_settings = sums.to_film;
    if (auto r = anchor_kernels(first, kernel_settings, film_scope); !r.ok()) return R::failure(r);
    if (progress && !progress(1.0 / C)) return cancelled();
    const bool on_cpu = !spec.settings.device.gpu();
    SummationSettings one_thread = kernel_settings;
    one_thread.nthreads = on_cpu ? 1 : spec.settings.nthreads;
    std::atomic<int> done{1};
    std::atomic<bool> stop{false};
    Result<bool> failed = Result<bool>::success(true);
#pragma omp parallel for num_threads(on_cpu ? impl->threads : 1) schedule(dynamic)
    for (int i = 0; i < C; ++i) {
        const int a = computed[size_t(i)];
        if (stop || a == first) continue;
        PlanScope scope = film_scope;
        if (auto r = anchor_kernels(a, one_thread, scope); !r.ok()) {
#pragma omp critical(psf_summation_kernels)
            if (!stop.exchange(true)) failed = r;
            continue;
        }
        const int finished = ++done;
        if (progress && omp_get_thread_num() == 0 && !progress(double(finished) / C)) stop = true;
    }
    if (stop) return failed.ok() ? cancelled() : R::failure(failed);
    // the others, their sources' kernels mirrored: film point (dx, sub-point sa) of one is
    // (-dx, n - 1 - sa) of the other along x, likewise along y
    for (int a = 0; a < A; ++a) {
        if (source[a] == a) continue;
        const bool flip_x = tail.mirrored_x(a), flip_y = tail.mirrored_y(a);
        for (int l = 0; l < g.layers.count; ++l) {
            const std::vector<std::complex<double>>& from = kernel[impl->kernel_index(l, source[a])];
            std::vector<std::complex<double>>& to = kernel[impl->kernel_index(l, a)];
            to.resize(from.size());
            for (int sb = 0; sb < n; ++sb)
                for (int sa = 0; sa < n; ++sa)
                    for (int y = 0; y < side; ++y)
                        for (int x = 0; x < side; ++x) {
                            const int fsb = flip_y ? n - 1 - sb : sb, fsa = flip_x ? n - 1 - sa : sa;
                            const int fy = flip_y ? side - 1 - y : y, fx = flip_x ? side - 1 - x : x;
                            to[((size_t(sb) * n + sa) * side + y) * side + x] =
                                from[((size_t(fsb) * n + fsa) * side + fy) * side + fx];
                        }
            for (int m = 0; m < 9; ++m)
                tail.deficit[(size_t(l) * A + a) * 9 + m] = tail.deficit[(size_t(l) * A + source[a]) * 9 + m];
        }
    }
    // their Gram matrix, the pixel-mean over sub-points
    const int K = int(kernel.size()), nax = int(g.ax.knots.size());
    const bool whole = K <= kMaxBasisKernels;
    std::vector<std::complex<double>> gram(size_t(K) * K, 0.0);
#pragma omp parallel for num_threads(impl->threads) schedule(dynamic)
    for (int i = 0; i < K; ++i)
        for (int j = i; j < K; ++j) {
            const int ai = i % A, aj = j % A;
            if (!whole && (std::abs(i / A - j / A) > 1 || std::abs(ai % nax - aj % nax) > 1 ||
                           std::abs(ai / nax - aj / nax) > 1))
                continue;
            std::complex<double> dot = 0;
            for (size_t t = 0; t < kernel[i].size(); ++t) dot += kernel[i][t] * std::conj(kernel[j][t]);
            gram[size_t(i) * K + j] = dot / double(S);
            gram[size_t(j) * K + i] = std::conj(dot) / double(S);
        }
    if (!spec.incoherent) {
        impl->gram.resize(gram.size());
        for (size_t q = 0; q < gram.size(); ++q) impl->gram[q] = gram[q].real();
        // the pixel images the runs' mean is brought to the intensity blend with
        const size_t P = size_t(side) * side, N9 = Impl::kNeighbours;
        impl->pixel_image.assign(size_t(K) * P, 0.0f);
        impl->difference_image.assign(size_t(K) * N9 * P, 0.0f);
        const int nay = int(g.ay.knots.size());
#pragma omp parallel for num_threads(impl->threads) schedule(dynamic)
        for (int k = 0; k < K; ++k) {
            const int l = k / A, ax = (k % A) % nax, ay = (k % A) / nax;
            for (int sub = 0; sub < S; ++sub)
                for (size_t t = 0; t < P; ++t)
                    impl->pixel_image[size_t(k) * P + t] += float(std::norm(kernel[k][sub * P + t]) / S);
            for (int slot = 0; slot < int(N9); ++slot) {
                const int l2 = l + slot / 9 - 1, ay2 = ay + (slot / 3) % 3 - 1, ax2 = ax + slot % 3 - 1;
                if (l2 < 0 || l2 >= g.layers.count || ay2 < 0 || ay2 >= nay || ax2 < 0 || ax2 >= nax) continue;
                const std::vector<std::complex<double>>& other = kernel[impl->kernel_index(l2, ay2 * nax + ax2)];
                float* j = impl->difference_image.data() + (size_t(k) * N9 + slot) * P;
                for (int sub = 0; sub < S; ++sub)
                    for (size_t t = 0; t < P; ++t) j[t] += float(std::norm(kernel[k][sub * P + t] - other[sub * P + t]) / S);
            }
        }
    }
    // the few kernels the runs transform, and their spectra: on the device where one is asked
    // for (its transforms take powers of two), else here
    const KernelBasis& basis = impl->basis = whole ? kernel_basis(gram, K) : kernel_basis({}, K);
    const SubPointModes& modes = impl->modes = sub_point_modes(kernel, S, spec.incoherent);
    const int M = modes.count;
    const ComputeDevice& device = spec.settings.device;
    if (device.gpu()) {
        const int nx = gpu_side(g.width), ny = gpu_side(g.height);
        auto made = GpuPsfSummation::create(device, nx, ny, basis.rank, M);
        if (made.ok()) {
            impl->gpu = std::move(made.value);
            g.nx = nx;
            g.ny = ny;
        } else if (auto off = psf_runs_off_device(device, made.error, made.kind); !off.ok()) {
            return R::failure(off);
        }  // else the runs on the CPU, noted on the device (the output's header names both)
    }
    detail::note_run(device, impl->gpu ? kRanOnGpu : kRanOnCpu);
    impl->fft = std::make_unique<ComplexFft2D>(g.nx, g.ny, impl->threads);
    const size_t N = impl->fft->size();
    if (!impl->gpu) impl->spectra = BasisSpectra(basis.rank, M, N);
    // the basis kernels, sub-point by sub-point (as the kernels)
    const size_t length = size_t(S) * side * side;
    std::vector<std::complex<double>> based(size_t(basis.rank) * length, 0.0);
#pragma omp parallel for num_threads(impl->threads)
    for (int r = 0; r < basis.rank; ++r)
        for (int k = 0; k < K; ++k) {
            const std::complex<double> c = basis.mix[size_t(r) * K + k];
            if (c == 0.0) continue;
            std::complex<double>* u = based.data() + size_t(r) * length;
            for (size_t t = 0; t < length; ++t) u[t] += c * kernel[k][t];
        }
    // basis kernel r in mode m, wrapped round the transform's period, and its transform
    auto spectrum_of = [&](int r, int m, std::complex<float>* spectrum) {
        const std::complex<double>* u = based.data() + size_t(r) * length;
        for (int dy = -g.radius; dy <= g.radius; ++dy)
            for (int dx = -g.radius; dx <= g.radius; ++dx) {
                std::complex<double> v = 0;
                const size_t t = size_t(dy + g.radius) * side + dx + g.radius;
                for (int sub = 0; sub < S; ++sub) v += modes.weight[size_t(m) * S + sub] * u[sub * side * side + t];
                spectrum[size_t((dy + g.ny) % g.ny) * g.nx + (dx + g.nx) % g.nx] = std::complex<float>(v);
            }
        impl->fft->forward(spectrum);
    };
    if (impl->gpu) {
        std::vector<std::complex<float>> scratch(N);
        for (int r = 0; r < basis.rank; ++r)
            for (int m = 0; m < M; ++m) {
                std::fill(scratch.begin(), scratch.end(), std::complex<float>(0));
                spectrum_of(r, m, scratch.data());
                if (auto e = impl->gpu->set_spectrum(r, m, scratch.data()); !e.ok()) return R::failure(e);
            }
    } else {
        // small transforms one per thread (complex_fft2d.h), large ones spread over the threads
#pragma omp parallel num_threads(impl->threads) if (N < ComplexFft2D::kParallelPoints)
        {
            std::vector<std::complex<float>> spectrum(N);
#pragma omp for schedule(dynamic)
            for (int rm = 0; rm < basis.rank * M; ++rm) {
                std::fill(spectrum.begin(), spectrum.end(), std::complex<float>(0));
                spectrum_of(rm / M, rm % M, spectrum.data());
                impl->spectra.set(rm / M, rm % M, spectrum.data());
            }
        }
    }
    PsfSummation conv;
    conv.impl_ = std::move(impl);
    return R::success(std::move(conv));
}

Result<bool> PsfSummation::run(const PsfSummationSources& sources, double scale, const RowRange& rows,
                               const float* each, float* irradiance, const ProgressFn& progress) const {
    const Impl& m = *impl_;
    const PsfSummationGeometry& g = m.g;
    const KernelBasis& basis = m.basis;
    const int S = m.points(), M = m.modes.count, B = basis.rank, runs = sources.runs;
    const size_t N = m.fft->size(), n = size_t(g.width) * g.height;
    const auto cancelled = [] { return Result<bool>::failure("cancelled", ErrorKind::Cancelled); };
    if (progress && !progress(0.0)) return cancelled();
    std::lock_guard<std::mutex> lock(m.busy);
    // per run and basis kernel r, the sources' weights times the share of r in their blended
    // kernel, sum over the blend of weight x coefficient[k][r], on the transform's grid (every
    // point written, the padding's zeros too: hundreds of MiB at 1080p, not cleared first), in
    // planes P apart (the spectra's whole chunks; the GPU's transforms take N)
    const size_t P = m.gpu ? N : m.spectra.plane();
    std::vector<std::complex<float>>& image = m.image;
    image.resize(size_t(runs) * B * P);
    const std::complex<float> zero(0);
#pragma omp parallel for num_threads(m.threads)
    for (int j = 0; j < g.ny; ++j) {
        std::vector<std::complex<double>> share(B);
        for (int kr = 0; kr < runs * B; ++kr) {
            std::complex<float>* row = image.data() + size_t(kr) * P + size_t(j) * g.nx;
            std::fill(row + (j < g.height ? g.width : 0), row + g.nx, zero);
            if (j == g.ny - 1) std::fill(row + g.nx, image.data() + size_t(kr + 1) * P, zero);
        }
        if (j >= g.height) continue;
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
    }
    // per run and domain point of the transform's grid, the sum over sub-points of |u|^2 (or Re u)
    std::vector<double>& film = m.film;
    film.assign(size_t(runs) * N, 0.0);
    if (m.gpu) {
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
    } else {
        // A large grid's transforms are spread over the threads one at a time; a small one's
        // (complex_fft2d.h: one thread each) go to the threads whole.
        const bool whole = N < ComplexFft2D::kParallelPoints;
#pragma omp parallel for num_threads(m.threads) schedule(dynamic) if (whole)
        for (int kr = 0; kr < runs * B; ++kr) m.fft->forward(image.data() + size_t(kr) * P, g.height);
        if (progress && !progress(0.4)) return cancelled();
        // the products, summed over the basis per run and mode (basis_spectra.h): a chunk of
        // points at a time, its spectra read once for all the runs at once
        std::vector<std::complex<float>>& total = m.total;
        total.resize(size_t(runs) * M * P);
        const long chunks = long(m.spectra.chunks());
#pragma omp parallel for num_threads(m.threads) schedule(static)
        for (long c = 0; c < chunks; ++c)
            for (int k = 0; k < runs; ++k)
                m.spectra.mix(size_t(c), image.data() + size_t(k) * B * P, total.data() + size_t(k) * M * P);
        if (progress && !progress(0.7)) return cancelled();
#pragma omp parallel for num_threads(m.threads) schedule(dynamic) if (whole)
        for (int km = 0; km < runs * M; ++km) m.fft->inverse(total.data() + size_t(km) * P);
        const bool incoherent = m.spec.incoherent;
        const size_t block = 4096;
        const long blocks = long((N + block - 1) / block);
#pragma omp parallel for num_threads(m.threads) schedule(static)
        for (long b = 0; b < blocks; ++b) {
            const size_t q0 = size_t(b) * block, q1 = std::min(N, q0 + block);
            for (int k = 0; k < runs; ++k)
                for (int mode = 0; mode < M; ++mode) {
                    const std::complex<float>* u = total.data() + (size_t(k) * M + mode) * P;
                    double* f = film.data() + size_t(k) * N;
                    for (size_t q = q0; q < q1; ++q) f[q] += incoherent ? u[q].real() : std::norm(u[q]);
                }
        }
    }
    // run by run, each pixel's mean over its points, then `each`
    const PinholeCamera& c = m.spec.camera;
    const int o = m.spec.overscan;
    const double coherent = 1.0 / (double(N) * N), incoherent = 1.0 / double(N);
    const double norm = scale / S * (m.spec.incoherent ? incoherent : coherent);
    // (each run one addition per pixel, as the exact sums' runs: a job is then the sum of its
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
    if (progress && !progress(1.0)) return cancelled();
    return Result<bool>::success(true);
}

int PsfSummation::runs_at_once() const {
    const Impl& m = *impl_;
    const double N = double(m.fft->size()), B = m.basis.rank, M = m.modes.count;
    // a run's images, sums and film against the kernels' spectra (none kept here on a GPU)
    const double run = N * (8 * (B + M) + 8), spectra = m.gpu ? 0 : 8 * N * B * M;
    return int(std::clamp(std::floor(spectra / run), 1.0, double(kMaxRunsAtOnce)));
}

std::vector<float> PsfSummation::power_balance(const PsfSummationSources& sources) const {
    const Impl& m = *impl_;
    const PsfSummationGeometry& g = m.g;
    const size_t n = size_t(g.width) * g.height, K = size_t(g.layers.count) * g.anchors();
    std::vector<float> factor(n, 1.0f);
    if (m.spec.incoherent) return factor;
#pragma omp parallel for num_threads(m.threads)
    for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
            size_t index[8];
            double weight[8];
            const int used = m.blend_of(sources, i, j, index, weight);
            double blended = 0, target = 0;
            for (int a = 0; a < used; ++a) {
                target += weight[a] * m.gram[index[a] * K + index[a]];
                for (int b = 0; b < used; ++b) blended += weight[a] * weight[b] * m.gram[index[a] * K + index[b]];
            }
            if (blended > 0 && target > 0) factor[size_t(j) * g.width + i] = float(std::sqrt(target / blended));
        }
    return factor;
}

void PsfSummation::add_blend_mean(const PsfSummationSources& sources, const std::vector<float>& power,
                                  const std::vector<float>& balance, const RowRange& rows, float* each) const {
    const Impl& m = *impl_;
    if (m.spec.incoherent) return;  // (its powers are blended as they are)
    const PsfSummationGeometry& g = m.g;
    const PinholeCamera& c = m.spec.camera;
    const int R = g.radius, side = 2 * R + 1, o = m.spec.overscan;
    const size_t P = size_t(side) * side, N9 = Impl::kNeighbours, n = size_t(g.width) * g.height;
    const size_t A = size_t(g.anchors()), K = size_t(g.layers.count) * A;
    // Per source and blended kernel u, its anchor's layer balance beta_a (the power the layers'
    // blend L_a lacks, phi_a times it: the anchor's weights sum to phi_a).
    std::vector<float> beta(n * 8, 1.0f);
#pragma omp parallel for num_threads(m.threads) schedule(static)
    for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
            const size_t p = size_t(j) * g.width + i;
            if (power[p] == 0) continue;
            size_t index[8];
            double weight[8];
            const int used = m.blend_of(sources, i, j, index, weight);
            for (int u = 0; u < used; ++u) {
                double target = 0, blended = 0;
                for (int v = 0; v < used; ++v) {
                    if (index[v] % A != index[u] % A) continue;
                    target += weight[v] * m.gram[index[v] * K + index[v]];
                    for (int x = 0; x < used; ++x)
                        if (index[x] % A == index[u] % A) blended += weight[v] * weight[x] * m.gram[index[v] * K + index[x]];
                }
                if (blended > 0) beta[p * 8 + u] = float(target / blended);
            }
        }
    // Each camera row of the share, within the overscan, from every source whose kernel reaches
    // it, in one order whatever the threads and the share (a job is the sum of its shares to the
    // bit): only that row of each source's image is formed.
#pragma omp parallel for num_threads(m.threads) schedule(dynamic)
    for (int cj = std::max(rows.begin, o); cj < std::min(rows.end, c.height - o); ++cj) {
        std::vector<float> line(size_t(c.width), 0.0f), add(static_cast<size_t>(side));
        for (int j = std::max(0, cj + g.origin - R); j <= std::min(g.height - 1, cj + g.origin + R); ++j) {
            const size_t row = size_t(cj + g.origin - j + R) * side;  // the row of the kernels: dy + R
            for (int i = 0; i < g.width; ++i) {
                const size_t p = size_t(j) * g.width + i;
                if (power[p] == 0) continue;
                size_t index[8];
                double weight[8];
                const int used = m.blend_of(sources, i, j, index, weight);
                const double b2 = double(balance[p]) * balance[p];
                double phi[8];
                for (int u = 0; u < used; ++u) {
                    phi[u] = 0;
                    for (int v = 0; v < used; ++v)
                        if (index[v] % A == index[u] % A) phi[u] += weight[v];
                }
                std::fill(add.begin(), add.end(), 0.0f);
                for (int u = 0; u < used; ++u) {
                    const double bu = phi[u] * beta[p * 8 + u];  // the anchor's balance
                    const float* image = m.pixel_image.data() + index[u] * P + row;
                    const float w = float((bu - b2) * weight[u]);
                    for (int t = 0; t < side; ++t) add[t] += w * image[t];
                    for (int v = u + 1; v < used; ++v) {
                        const bool one_anchor = index[u] % A == index[v] % A;
                        const double k = b2 * weight[u] * weight[v] - (one_anchor ? bu * weight[u] * weight[v] / phi[u] : 0);
                        const float* d =
                            m.difference_image.data() + (index[u] * N9 + m.neighbour(index[u], index[v])) * P + row;
                        for (int t = 0; t < side; ++t) add[t] += float(k) * d[t];
                    }
                }
                const int ci0 = i - g.origin;
                for (int dx = -R; dx <= R; ++dx) {
                    const int ci = ci0 + dx;
                    if (ci >= o && ci < c.width - o) line[size_t(ci)] += power[p] * add[size_t(dx + R)];
                }
            }
        }
        for (int ci = 0; ci < c.width; ++ci) each[size_t(cj) * c.width + ci] += line[size_t(ci)];
    }
}

void PsfSummation::add_far_tail(const float* radiance, const float* depth, DepthMeaning meaning, double scale,
                                const RowRange& rows, float* irradiance) const {
    const Impl& m = *impl_;
    const PinholeCamera& c = m.spec.camera;
    const int o = m.spec.overscan, out_w = c.width - 2 * o, out_h = c.height - 2 * o, R = m.g.radius;
    std::vector<float> rgb(3 * size_t(c.width) * c.height, 0.0f), xyz(3 * size_t(out_w) * out_h, 0.0f);
    for (size_t q = 0; q < size_t(c.width) * c.height; ++q) rgb[3 * q] = radiance[q];
    const SpectralScene scene{c, rgb.data(), depth, meaning, true};
    detail::add_far_tail(m.tail, scene, m.g.origin, {R, R, out_w, out_h}, xyz.data(), m.threads);
    for (int cj = std::max(rows.begin, o); cj < std::min(rows.end, c.height - o); ++cj)
        for (int ci = o; ci < c.width - o; ++ci)
            irradiance[size_t(cj) * c.width + ci] += float(scale * xyz[3 * (size_t(cj - o) * out_w + ci - o)]);
}

Result<std::shared_ptr<const PsfSummation>> PsfSummationMemo::get(const PsfSummationSpec& spec, double pitch,
                                                                  const Make& make) {
    using R = Result<std::shared_ptr<const PsfSummation>>;
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
        kept_ = std::make_shared<const PsfSummation>(std::move(made.value));
        spec_ = spec;
        pitch_ = pitch;
    }
    return R::success(kept_);
}

}  // namespace wavecam::detail
