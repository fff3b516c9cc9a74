// The kernel summation's kernels (kernel_summation.h, KernelSummation::create): the point sums at the
// anchors and layers, their Gram matrix and pixel images, their basis and its spectra.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <utility>

#include "base/parallel.h"
#include "summation/choose.h"
#include "summation/kernel/source_kernels.h"
#include "summation/kernel/gpu_run_cost.h"
#include "summation/kernel/kernel_summation_impl.h"
#include "wavecam/fresnel_psf.h"

namespace wavecam::detail {
namespace {

using Impl = KernelSummation::Impl;
// A kernel, sub-point by sub-point ((2R + 1)^2 film points each): amplitudes, or powers in .real().
using Field = std::vector<std::complex<double>>;

Result<bool> cancelled() { return Result<bool>::failure("cancelled", ErrorKind::Cancelled); }

// The light beyond the kernel of layer l at camera pixel (px, py), whose film field is
// `film_field`: its share of the Fresnel PSF's power, times the light within it, per unit of the
// far tail's source light (radiance x cos^4, far_tail.cpp; a source here is radiance x its solid
// angle t^2 cos^3). Where the Fresnel PSF is evaluated only out to a reach short of the kernel's
// edge (PSFs far narrower than a pixel), the share beyond the edge follows the sharp edge's far
// tail, whose energy beyond r falls as 1/r (far_tail.h): taking the share beyond the reach put
// the light between reach and edge twice, once in the kernel's sums and once in the far tail (a
// 0.15 px PSF on the axis of a 120 deg frame: 1.5% of its light, against 0.16% beyond its 16 px
// kernel).
float light_beyond(const Impl& m, int l, int px, int py, const Field& film_field) {
    const KernelSummationSpec& spec = m.spec;
    const KernelSummationGeometry& g = m.g;
    const PinholeCamera& c = spec.camera;
    FieldPsfRequest q;
    q.aperture = spec.aperture;
    q.film_distance = c.film_distance;
    q.depth = g.layers.inverse_depth(l) > 0 ? 1.0 / g.layers.inverse_depth(l) : INFINITY;
    q.wavelength = spec.wavelength;
    c.tangent(px + 0.5, py + 0.5, q.u, q.v);
    q.pixel_pitch = c.pixel_pitch();
    q.radius = g.radius;
    q.subsamples = spec.subsamples;
    const PsfKernel model = field_psf_kernel(q);
    double held = 0, within = 0;
    for (const float x : model.weight) held += x;
    const double edge = (g.radius + 0.5) * c.pixel_pitch();
    const double beyond = std::max(0.0, 1 - held) * std::min(1.0, model.reach / edge);
    for (const std::complex<double>& k : film_field) within += std::norm(k) / m.points();
    const double missing = held > 0 ? within * beyond / (1 - beyond) : 0.0;
    return float(missing * c.tan_pitch() * c.tan_pitch() * std::sqrt(1 + q.u * q.u + q.v * q.v));
}

// The kernels of anchor a, every layer (source_kernels.h), and the light beyond each.
Result<bool> anchor_kernels(Impl& m, const KernelSetup& setup, const std::vector<double>& depths, int a,
                            const SummationSettings& settings, PlanScope& film_scope, std::vector<Field>& kernel) {
    const KernelSummationGeometry& g = m.g;
    const int A = g.anchors();
    const int px = g.ax.knots[a % g.ax.knots.size()] - g.origin, py = g.ay.knots[a / g.ax.knots.size()] - g.origin;
    std::vector<Field> fields;
    if (auto r = source_kernels(setup, px, py, depths, settings, film_scope, fields); !r.ok()) return r;
    for (int l = 0; l < g.layers.count; ++l) {
        Field& film_field = fields[size_t(l)];
        m.tail.deficit[(size_t(l) * A + a) * 9] = light_beyond(m, l, px, py, film_field);
        if (m.spec.incoherent)
            for (auto& k : film_field) k = std::norm(k);
        kernel[m.kernel_index(l, a)] = std::move(film_field);
    }
    return Result<bool>::success(true);
}

// Every anchor's kernels that are computed (one of each mirror or transposed pair, `sources`), into `kernel`.
Result<bool> sum_kernels(Impl& m, const KernelSources& sources, double lattice_pitch, const UnitSource& unit_source,
                         const ProgressFn& progress, std::vector<Field>& kernel) {
    const KernelSummationSpec& spec = m.spec;
    const KernelSummationGeometry& g = m.g;
    // how the kernels' sums are evaluated (choose.h: one source's directly)
    const KernelSums sums = kernel_sums(spec, g);
    const ApertureSamples samples = sample_aperture(spec.aperture, lattice_pitch);
    const KernelSetup setup{&spec, &g, &samples, sums.to_pinhole, unit_source, &m.device};
    std::vector<double> depths(size_t(g.layers.count));
    for (int l = 0; l < g.layers.count; ++l) depths[size_t(l)] = g.layers.inverse_depth(l);
    // Where the aperture is even along an axis, an anchor and its mirror image across the optical
    // axis have mirror-image kernels, and on a square frame of an opening even across y = -x an
    // anchor and its transpose have transposed kernels (kernel_sources): one of each is computed.
    std::vector<int> computed;
    for (int a = 0; a < g.anchors(); ++a)
        if (sources.summed(a)) computed.push_back(a);
    const int C = int(computed.size());
    // The anchor nearest the frame's centre fixes the film sums' evaluator (a corner's film
    // points at a wide field took the cost model minutes); the others follow, one anchor per
    // thread on the CPU (a device's plans are not for concurrent use), reporting from the
    // first thread.
    PlanScope film_scope;
    // (the centre's mirror source lies on the knots' diagonal: never a transpose's)
    const int first = sources.mirror[g.ay.knots.size() / 2 * g.ax.knots.size() + g.ax.knots.size() / 2];
    const SummationSettings& kernel_settings = sums.to_film;
    if (auto r = anchor_kernels(m, setup, depths, first, kernel_settings, film_scope, kernel); !r.ok()) return r;
    if (progress && !progress(1.0 / C)) return cancelled();
    const bool on_cpu = !m.device.gpu();
    SummationSettings one_thread = kernel_settings;
    one_thread.nthreads = on_cpu ? 1 : spec.settings.nthreads;
    std::atomic<int> done{1};
    std::atomic<bool> stop{false};
    Result<bool> failed = Result<bool>::success(true);
    std::mutex failure;
    parallel_for_dynamic(0, C, 1, on_cpu ? m.threads : 1, [&](int64_t i_) {
        const int i = int(i_);
        const int a = computed[size_t(i)];
        if (stop || a == first) return;
        PlanScope scope = film_scope;
        if (auto r = anchor_kernels(m, setup, depths, a, one_thread, scope, kernel); !r.ok()) {
            std::lock_guard<std::mutex> lock(failure);
            if (!stop.exchange(true)) failed = r;
            return;
        }
        const int finished = ++done;
        if (progress && on_calling_thread() && !progress(double(finished) / C)) stop = true;
    });
    if (stop) return failed.ok() ? cancelled() : failed;
    return Result<bool>::success(true);
}

// Anchor a's kernels, every layer, read from anchor `from`'s: transposed, film point (x, y) and
// sub-point (sa, sb) from (y, x) and (sb, sa); mirrored along x, from side - 1 - x and n - 1 - sa,
// likewise along y; and the light beyond them (entries m = 3p + q, transposed likewise).
void read_kernels(Impl& m, int a, int from, bool transpose, bool flip_x, bool flip_y, std::vector<Field>& kernel) {
    const KernelSummationGeometry& g = m.g;
    const int n = m.spec.subsamples, side = 2 * g.radius + 1, A = g.anchors();
    for (int l = 0; l < g.layers.count; ++l) {
        const Field& source = kernel[m.kernel_index(l, from)];
        Field& to = kernel[m.kernel_index(l, a)];
        to.resize(source.size());
        for (int sb = 0; sb < n; ++sb)
            for (int sa = 0; sa < n; ++sa)
                for (int y = 0; y < side; ++y)
                    for (int x = 0; x < side; ++x) {
                        int fsa = flip_x ? n - 1 - sa : sa, fsb = flip_y ? n - 1 - sb : sb;
                        int fx = flip_x ? side - 1 - x : x, fy = flip_y ? side - 1 - y : y;
                        if (transpose) {
                            std::swap(fsa, fsb);
                            std::swap(fx, fy);
                        }
                        to[((size_t(sb) * n + sa) * side + y) * side + x] =
                            source[((size_t(fsb) * n + fsa) * side + fy) * side + fx];
                    }
        for (int mm = 0; mm < 9; ++mm)
            m.tail.deficit[(size_t(l) * A + a) * 9 + mm] =
                m.tail.deficit[(size_t(l) * A + from) * 9 + (transpose ? 3 * (mm % 3) + mm / 3 : mm)];
    }
}

// The anchors not summed, read from those that are (kernel_sources): first the transposed ones,
// which mirror images may read next, then the mirror images.
void read_other_kernels(Impl& m, const KernelSources& sources, std::vector<Field>& kernel) {
    const int A = m.g.anchors();
    for (int a = 0; a < A; ++a)
        if (sources.transpose[size_t(a)] >= 0) read_kernels(m, a, sources.transpose[size_t(a)], true, false, false, kernel);
    for (int a = 0; a < A; ++a)
        if (sources.mirror[size_t(a)] != a)
            read_kernels(m, a, sources.mirror[size_t(a)], false, m.tail.mirrored_x(a), m.tail.mirrored_y(a), kernel);
}

// The kernels' Gram matrix, the pixel-mean over sub-points: whole up to kMaxBasisKernels, else
// only each kernel's neighbours in layer and both anchor axes (0 elsewhere).
std::vector<std::complex<double>> kernel_gram(const Impl& m, const std::vector<Field>& kernel) {
    const KernelSummationGeometry& g = m.g;
    const int S = m.points(), A = g.anchors();
    const int K = int(kernel.size()), nax = int(g.ax.knots.size());
    const bool whole = K <= kMaxBasisKernels;
    std::vector<std::complex<double>> gram(size_t(K) * K, 0.0);
    parallel_for_dynamic(0, K, 1, m.threads, [&](int64_t i_) {
        const int i = int(i_);
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
    });
    return gram;
}

// Coherent runs: the Gram matrix's real part, and the pixel images the runs' mean is brought to
// the intensity blend with (add_blend_mean).
void blend_mean_images(Impl& m, const std::vector<Field>& kernel, const std::vector<std::complex<double>>& gram) {
    const KernelSummationGeometry& g = m.g;
    const int S = m.points(), side = 2 * g.radius + 1, A = g.anchors();
    const int K = int(kernel.size()), nax = int(g.ax.knots.size());
    m.gram.resize(gram.size());
    for (size_t q = 0; q < gram.size(); ++q) m.gram[q] = gram[q].real();
    const size_t P = size_t(side) * side, N9 = Impl::kNeighbours;
    m.pixel_image.assign(size_t(K) * P, 0.0f);
    m.difference_image.assign(size_t(K) * N9 * P, 0.0f);
    const int nay = int(g.ay.knots.size());
    parallel_for_dynamic(0, K, 1, m.threads, [&](int64_t k_) {
        const int k = int(k_);
        const int l = k / A, ax = (k % A) % nax, ay = (k % A) / nax;
        for (int sub = 0; sub < S; ++sub)
            for (size_t t = 0; t < P; ++t)
                m.pixel_image[size_t(k) * P + t] += float(std::norm(kernel[k][sub * P + t]) / S);
        for (int slot = 0; slot < int(N9); ++slot) {
            const int l2 = l + slot / 9 - 1, ay2 = ay + (slot / 3) % 3 - 1, ax2 = ax + slot % 3 - 1;
            if (l2 < 0 || l2 >= g.layers.count || ay2 < 0 || ay2 >= nay || ax2 < 0 || ax2 >= nax) continue;
            const Field& other = kernel[m.kernel_index(l2, ay2 * nax + ax2)];
            float* j = m.difference_image.data() + (size_t(k) * N9 + slot) * P;
            for (int sub = 0; sub < S; ++sub)
                for (size_t t = 0; t < P; ++t) j[t] += float(std::norm(kernel[k][sub * P + t] - other[sub * P + t]) / S);
        }
    });
}

// The runs' transforms: on the device where one is asked for (its transforms take powers of
// two), else here; the CPU's spectra made room for.
Result<bool> open_transforms(Impl& m) {
    KernelSummationGeometry& g = m.g;
    const ComputeDevice& device = m.device;
    if (device.gpu()) {
        const int nx = gpu_transform_side(g.width), ny = gpu_transform_side(g.height);
        auto made = GpuKernelSummation::create(device, nx, ny, m.basis.rank, m.modes.count);
        if (made.ok()) {
            m.gpu = std::move(made.value);
            g.nx = nx;
            g.ny = ny;
        } else if (auto off = kernel_runs_off_device(device, made.error, made.kind); !off.ok()) {
            return off;
        }  // else the runs on the CPU (on_gpu false: the job's report names both)
    }
    m.fft = std::make_unique<ComplexFft2D>(g.nx, g.ny, m.threads);
    if (!m.gpu) m.spectra = BasisSpectra(m.basis.rank, m.modes.count, m.fft->size());
    return Result<bool>::success(true);
}

// The basis kernels, sub-point by sub-point (as the kernels).
std::vector<std::complex<double>> basis_kernels(const Impl& m, const std::vector<Field>& kernel) {
    const int side = 2 * m.g.radius + 1, K = int(kernel.size());
    const KernelBasis& basis = m.basis;
    const size_t length = size_t(m.points()) * side * side;
    std::vector<std::complex<double>> based(size_t(basis.rank) * length, 0.0);
    parallel_for(0, basis.rank, m.threads, [&](int64_t r_) {
        const int r = int(r_);
        for (int k = 0; k < K; ++k) {
            const std::complex<double> c = basis.mix[size_t(r) * K + k];
            if (c == 0.0) continue;
            std::complex<double>* u = based.data() + size_t(r) * length;
            for (size_t t = 0; t < length; ++t) u[t] += c * kernel[k][t];
        }
    });
    return based;
}

// Basis kernel r (`based`, as basis_kernels gives them) in mode `mode`, wrapped round the
// transform's period, and its transform.
void spectrum_of(const Impl& m, const std::vector<std::complex<double>>& based, int r, int mode,
                 std::complex<float>* spectrum) {
    const KernelSummationGeometry& g = m.g;
    const int S = m.points(), side = 2 * g.radius + 1;
    const size_t length = size_t(S) * side * side;
    const std::complex<double>* u = based.data() + size_t(r) * length;
    for (int dy = -g.radius; dy <= g.radius; ++dy)
        for (int dx = -g.radius; dx <= g.radius; ++dx) {
            std::complex<double> v = 0;
            const size_t t = size_t(dy + g.radius) * side + dx + g.radius;
            for (int sub = 0; sub < S; ++sub) v += m.modes.weight[size_t(mode) * S + sub] * u[sub * side * side + t];
            spectrum[size_t((dy + g.ny) % g.ny) * g.nx + (dx + g.nx) % g.nx] = std::complex<float>(v);
        }
    m.fft->forward(spectrum);
}

// Every basis kernel's spectrum in every mode: to the device, or kept here.
Result<bool> set_spectra(Impl& m, const std::vector<std::complex<double>>& based) {
    const int B = m.basis.rank, M = m.modes.count;
    const size_t N = m.fft->size();
    if (m.gpu) {
        std::vector<std::complex<float>> scratch(N);
        for (int r = 0; r < B; ++r)
            for (int mode = 0; mode < M; ++mode) {
                std::fill(scratch.begin(), scratch.end(), std::complex<float>(0));
                spectrum_of(m, based, r, mode, scratch.data());
                if (auto e = m.gpu->set_spectrum(r, mode, scratch.data()); !e.ok()) return e;
            }
    } else {
        // small transforms one per thread (complex_fft2d.h), large ones spread over the threads
        parallel_team(N < ComplexFft2D::kParallelPoints ? m.threads : 1, [&](Team& team) {
            std::vector<std::complex<float>> spectrum(N);
            team.for_dynamic(0, B * M, 1, [&](int64_t rm_) {
                const int rm = int(rm_);
                std::fill(spectrum.begin(), spectrum.end(), std::complex<float>(0));
                spectrum_of(m, based, rm / M, rm % M, spectrum.data());
                m.spectra.set(rm / M, rm % M, spectrum.data());
            });
        });
    }
    return Result<bool>::success(true);
}

}  // namespace

Result<KernelSummation> KernelSummation::create(const ComputeDevice& device, const KernelSummationSpec& spec,
                                                double lattice_pitch, const UnitSource& unit_source,
                                                const ProgressFn& progress) {
    using R = Result<KernelSummation>;
    auto impl = std::make_unique<Impl>();
    Impl& m = *impl;
    m.device = device;
    m.spec = spec;
    m.threads = thread_count(spec.settings.nthreads);
    if (runs_in_directions(spec, device)) {
        m.directions = std::make_unique<DirectionRuns>(spec, m.threads);
        const DirectionGeometry& d = m.directions->geometry();
        m.g.radius = m.g.origin = d.margin;
        m.g.width = d.width;
        m.g.height = d.height;
        m.g.layers = d.layers;
        KernelSummation conv;
        conv.impl_ = std::move(impl);
        return R::success(std::move(conv));
    }
    const KernelSummationGeometry& g = m.g = kernel_summation_geometry(spec);
    if (g.layers.count > kMaxKernelLayers) return R::failure(too_many_layers());
    m.tail.radius = g.radius;
    m.tail.layers = g.layers;
    m.tail.ax = g.ax;
    m.tail.ay = g.ay;
    m.tail.deficit.assign(size_t(g.layers.count) * g.anchors() * 9, 0.0f);
    // every kernel (layer x anchors + anchor)
    std::vector<Field> kernel(size_t(g.layers.count) * g.anchors());
    const KernelSources sources = kernel_sources(spec, g);
    m.tail.source = sources.mirror;
    if (auto r = sum_kernels(m, sources, lattice_pitch, unit_source, progress, kernel); !r.ok()) return R::failure(r);
    read_other_kernels(m, sources, kernel);
    const std::vector<std::complex<double>> gram = kernel_gram(m, kernel);
    if (!spec.incoherent) blend_mean_images(m, kernel, gram);
    // the few kernels the runs transform, and their spectra
    const int K = int(kernel.size());
    m.basis = K <= kMaxBasisKernels ? kernel_basis(gram, K) : kernel_basis({}, K);
    m.modes = sub_point_modes(kernel, m.points(), spec.incoherent);
    if (auto r = open_transforms(m); !r.ok()) return R::failure(r);
    if (auto r = set_spectra(m, basis_kernels(m, kernel)); !r.ok()) return R::failure(r);
    KernelSummation conv;
    conv.impl_ = std::move(impl);
    return R::success(std::move(conv));
}

}  // namespace wavecam::detail
