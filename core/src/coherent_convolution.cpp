#include "coherent_convolution.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "complex_fft2d.h"
#include "far_tail.h"
#include "gpu/gpu_convolution.h"
#include "kernel_basis.h"
#include "real_fft2d.h"
#include "summation/summation_cost.h"
#include "wavecam/fresnel_psf.h"
#include "wavecam/psf_convolution.h"

namespace wavecam::detail {

DepthLayers amplitude_layers(double max_inverse_depth, double aperture_radius, double wavelength) {
    DepthLayers d;
    if (!(max_inverse_depth > 0)) return d;
    d.step = kMaxLayerPhase * wavelength / (M_PI * aperture_radius * aperture_radius);
    const double steps = std::ceil(max_inverse_depth / d.step);  // (a double: no overflow)
    d.count = int(std::min(steps, double(kMaxPsfLayers))) + 1;
    return d;
}

Result<bool> too_many_layers() {
    char m[200];
    std::snprintf(m, sizeof m,
                  "summation: psf serves depths to %d layers at this pinhole and wavelength, this scene needs more "
                  "(its nearest source is too near for the pinhole's defocus); expected auto, direct or nufft",
                  kMaxPsfLayers);
    return Result<bool>::failure(m, ErrorKind::Invalid, "summation");
}

namespace {

// The convolution's geometry: kernel radius, domain, transform size, anchors and layers.
struct Geometry {
    int radius = 0, origin = 0, width = 0, height = 0, nx = 0, ny = 0;
    AnchorAxis ax, ay;
    DepthLayers layers;
    int anchors() const { return int(ax.knots.size() * ay.knots.size()); }
};

Geometry geometry_of(const CoherentSpec& s) {
    const PinholeCamera& c = s.camera;
    const int o = s.overscan, out_w = c.width - 2 * o, out_h = c.height - 2 * o;
    const double nearest = s.max_inverse_depth > 0 ? 1.0 / s.max_inverse_depth : INFINITY;
    Geometry g;
    // the radius depends on the widest field its sources reach: one refinement (it only grows)
    for (int pass = 0; pass < 2; ++pass) {
        const double cmax = c.cos_widest(o - g.radius, o - g.radius, o + out_w + g.radius, o + out_h + g.radius);
        g.radius = psf_kernel_radius(s.aperture, c.film_distance, nearest, s.wavelength, cmax, c.pixel_pitch(),
                                     ConvolutionSettings{}.max_radius);
    }
    g.origin = g.radius - o;
    g.width = out_w + 2 * g.radius;
    g.height = out_h + 2 * g.radius;
    // one transform over the whole domain: light wrapped round its period (at most R beyond the
    // domain) lands in the margin, which is never read
    g.nx = fft_friendly_size(g.width);
    g.ny = fft_friendly_size(g.height);
    const int longest = std::max(g.width, g.height), cells = std::max(1, s.anchor_cells);
    const int min_cell = kMinAmplitudeCellRadii * g.radius;
    g.ax = AnchorAxis::across(g.width, 1, std::max(1, int(std::lround(double(cells) * g.width / longest))), min_cell,
                              g.radius);
    g.ay = AnchorAxis::across(g.height, 1, std::max(1, int(std::lround(double(cells) * g.height / longest))),
                              min_cell, g.radius);
    g.layers = amplitude_layers(s.max_inverse_depth, s.aperture.bounding_radius(), s.wavelength);
    return g;
}

// The bilinear hat of knot `k` at pixel `i`: 1 on the knot itself, falling to 0 at its
// neighbours; the outermost knots keep 1 beyond them.
double hat(const AnchorAxis& axis, int k, int i) {
    const int cell = axis.cell_of(i);
    const double t = std::clamp(double(i - axis.knots[cell]) / (axis.knots[cell + 1] - axis.knots[cell]), 0.0, 1.0);
    return k == cell ? 1 - t : k == cell + 1 ? t : 0.0;
}

// A transform side the GPU's FFTs take (gpu_convolution.h): the next power of two.
int gpu_side(int n) {
    int p = 2;
    while (p < n) p *= 2;
    return p;
}

}  // namespace

struct CoherentConvolution::Impl {
    CoherentSpec spec;
    Geometry g;
    int threads = 1;
    std::unique_ptr<ComplexFft2D> fft;
    KernelBasis basis;  // the kernels (layer x anchors + anchor) as combinations of a few
    std::vector<std::complex<float>> spectra;  // [basis kernel][sub-point][ny x nx] (none on a GPU)
    // the runs on a Vulkan device (the spectra kept there), or none: on the CPU
    std::unique_ptr<GpuConvolution> gpu;
    // a run's images (one per basis kernel), sums (one per sub-point) and film values, kept from
    // run to run (hundreds of MiB at 1080p: allocated once, not every run); one run at a time
    mutable std::mutex busy;
    mutable std::vector<std::complex<float>> image, total;
    mutable std::vector<double> film;
    PsfTable tail;  // layers, anchors and, in deficit's first entry, the light beyond each kernel
    // Re <K_i, K_j> (the pixel-mean over sub-points) for kernels i = layer x anchors + anchor
    // and, where there are more than kMaxBasisKernels, only their neighbours j in layer and
    // both anchor axes (0 elsewhere)
    std::vector<double> gram;
    size_t kernel_index(int layer, int anchor) const { return size_t(layer) * g.anchors() + anchor; }

    int points() const { return spec.subsamples * spec.subsamples; }
    std::complex<float>* spectrum(int r, int sub) { return &spectra[(size_t(r) * points() + sub) * fft->size()]; }
    const std::complex<float>* spectrum(int r, int sub) const {
        return &spectra[(size_t(r) * points() + sub) * fft->size()];
    }
    // The kernels that domain pixel (i, j)'s source blends, and their weights (at most 8): bilinear
    // over the anchors round it, linear between its two layers.
    int blend_of(const CoherentSources& s, int i, int j, size_t* index, double* weight) const {
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

CoherentConvolution::CoherentConvolution() = default;
CoherentConvolution::~CoherentConvolution() = default;
CoherentConvolution::CoherentConvolution(CoherentConvolution&&) noexcept = default;
CoherentConvolution& CoherentConvolution::operator=(CoherentConvolution&&) noexcept = default;
int CoherentConvolution::radius() const { return impl_->g.radius; }
int CoherentConvolution::domain_width() const { return impl_->g.width; }
int CoherentConvolution::domain_height() const { return impl_->g.height; }
int CoherentConvolution::origin() const { return impl_->g.origin; }
const DepthLayers& CoherentConvolution::layers() const { return impl_->g.layers; }

Result<CoherentConvolution> CoherentConvolution::create(const CoherentSpec& spec, const ApertureSamples& samples,
                                                        const UnitSource& unit_source, const ProgressFn& progress) {
    using R = Result<CoherentConvolution>;
    auto impl = std::make_unique<Impl>();
    impl->spec = spec;
    Geometry& g = impl->g;
    g = geometry_of(spec);
    if (g.layers.count > kMaxPsfLayers) return R::failure(too_many_layers());
    impl->threads = spec.settings.nthreads > 0 ? spec.settings.nthreads : omp_get_max_threads();
    const int n = spec.subsamples, S = impl->points(), side = 2 * g.radius + 1, A = g.anchors();
    const PinholeCamera& c = spec.camera;
    PsfTable& tail = impl->tail;
    tail.radius = g.radius;
    tail.layers = g.layers;
    tail.ax = g.ax;
    tail.ay = g.ay;
    tail.deficit.assign(size_t(g.layers.count) * A * 9, 0.0f);
    PinholeField field;
    std::vector<std::complex<double>> film_field;
    // every kernel (sub-point by sub-point, (2R + 1)^2 each): amplitudes, or powers in .real()
    std::vector<std::vector<std::complex<double>>> kernel(size_t(g.layers.count) * A);
    // one source's sum is direct (a lattice of transforms for one source never pays)
    SummationSettings one_source = spec.settings;
    one_source.summation = Summation::Direct;
    PlanScope film_scope;
    for (int a = 0; a < A; ++a) {
        // the anchor's pixel (camera coordinates) and its kernel's film points, as the direct sums
        // place them (n x n per pixel), sub-point by sub-point
        const int px = g.ax.knots[a % g.ax.knots.size()] - g.origin, py = g.ay.knots[a / g.ax.knots.size()] - g.origin;
        FilmPoints film;
        film.film_distance = c.film_distance;
        for (int sb = 0; sb < n; ++sb)
            for (int sa = 0; sa < n; ++sa)
                for (int dy = -g.radius; dy <= g.radius; ++dy)
                    for (int dx = -g.radius; dx <= g.radius; ++dx) {
                        double u, v;
                        c.tangent(px + dx + (sa + 0.5) / n, py + dy + (sb + 0.5) / n, u, v);
                        film.x.push_back(float(-c.film_distance * u));
                        film.y.push_back(float(-c.film_distance * v));
                    }
        SummationPlan to_film =
            SummationPlan::create(SumKind::PinholeToFilm, samples, spec.wavelength, spec.settings, film_scope);
        if (auto r = to_film.set_points(film); !r.ok()) return R::failure(r);
        film_scope.fixed_choice = true;  // every anchor's film points count alike: one decision
        film_scope.choice = to_film.choice();
        for (int l = 0; l < g.layers.count; ++l) {
            const std::vector<PointSource> one{unit_source(px + 0.5, py + 0.5, g.layers.inverse_depth(l))};
            SummationPlan to_pinhole = SummationPlan::create(SumKind::SourcesToPinhole, samples, spec.wavelength, one_source);
            if (auto r = to_pinhole.set_points(one); !r.ok()) return R::failure(r);
            if (auto r = to_pinhole.execute(source_weights(one), field); !r.ok()) return R::failure(r);
            film_field.assign(film.size(), 0.0);
            const double kernels = double(A) * g.layers.count, done = (a * g.layers.count + l) / kernels;
            if (auto r = to_film.execute(field, film_field.data(), progress_part(progress, done, done + 1 / kernels));
                !r.ok())
                return R::failure(r);
            // the light beyond the kernel: its share of the Fresnel PSF's power, times the light
            // within it, per unit of the far tail's source light (radiance x cos^4, far_tail.cpp;
            // a source here is radiance x its solid angle t^2 cos^3)
            FieldPsfRequest q;
            q.aperture = spec.aperture;
            q.film_distance = c.film_distance;
            q.depth = g.layers.inverse_depth(l) > 0 ? 1.0 / g.layers.inverse_depth(l) : INFINITY;
            q.wavelength = spec.wavelength;
            c.tangent(px + 0.5, py + 0.5, q.u, q.v);
            q.pixel_pitch = c.pixel_pitch();
            q.radius = g.radius;
            q.subsamples = n;
            double held = 0, within = 0;
            for (const float x : field_psf_kernel(q).weight) held += x;
            for (const std::complex<double>& k : film_field) within += std::norm(k) / S;
            const double missing = held > 0 && held < 1 ? within * (1 - held) / held : 0.0;
            tail.deficit[(size_t(l) * A + a) * 9] =
                float(missing * c.tan_pitch() * c.tan_pitch() * std::sqrt(1 + q.u * q.u + q.v * q.v));
            if (spec.incoherent)
                for (auto& k : film_field) k = std::norm(k);
            kernel[impl->kernel_index(l, a)] = std::move(film_field);
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
    }
    // the few kernels the runs transform, and their spectra: on the device where one is asked
    // for (its transforms take powers of two), else here
    const KernelBasis& basis = impl->basis = whole ? kernel_basis(gram, K) : kernel_basis({}, K);
    if (spec.settings.device != Device::Cpu) {
        const int nx = gpu_side(g.width), ny = gpu_side(g.height);
        auto made = GpuConvolution::create(spec.settings.device, nx, ny, basis.rank, S);
        if (made.ok()) {
            impl->gpu = std::move(made.value);
            g.nx = nx;
            g.ny = ny;
        } else if (spec.settings.device == Device::Gpu) {
            return R::failure("device gpu: " + made.error, made.kind, "device");
        }  // auto: quietly the CPU
    }
    impl->fft = std::make_unique<ComplexFft2D>(g.nx, g.ny, impl->threads);
    const size_t N = impl->fft->size();
    if (!impl->gpu) impl->spectra.assign(size_t(basis.rank) * S * N, {});
    std::vector<std::complex<float>> scratch(impl->gpu ? N : 0);
    for (int r = 0; r < basis.rank; ++r)
        for (int sub = 0; sub < S; ++sub) {
            // basis kernel r at this sub-point, wrapped round the transform's period
            std::complex<float>* spectrum = impl->gpu ? scratch.data() : impl->spectrum(r, sub);
            if (impl->gpu) std::fill(scratch.begin(), scratch.end(), std::complex<float>(0));
            for (int dy = -g.radius; dy <= g.radius; ++dy)
                for (int dx = -g.radius; dx <= g.radius; ++dx) {
                    const size_t t = (size_t(sub) * side + dy + g.radius) * side + dx + g.radius;
                    std::complex<double> v = 0;
                    for (int k = 0; k < K; ++k) {
                        const std::complex<double> m = basis.mix[size_t(r) * K + k];
                        if (m != 0.0) v += m * kernel[k][t];
                    }
                    spectrum[size_t((dy + g.ny) % g.ny) * g.nx + (dx + g.nx) % g.nx] = std::complex<float>(v);
                }
            impl->fft->forward(spectrum);
            if (impl->gpu)
                if (auto e = impl->gpu->set_spectrum(r, sub, spectrum); !e.ok()) return R::failure(e);
        }
    CoherentConvolution conv;
    conv.impl_ = std::move(impl);
    return R::success(std::move(conv));
}

Result<bool> CoherentConvolution::run(const CoherentSources& sources, double scale, int row_begin, int row_end,
                                      float* irradiance, const ProgressFn& progress) const {
    const Impl& m = *impl_;
    const Geometry& g = m.g;
    const KernelBasis& basis = m.basis;
    const int S = m.points(), B = basis.rank;
    const size_t N = m.fft->size();
    const bool parallel = N >= (1u << 16);  // small frames on one thread (complex_fft2d.h says why)
    const auto cancelled = [] { return Result<bool>::failure("cancelled", ErrorKind::Cancelled); };
    const double steps = double(B) + S + 1;
    if (progress && !progress(0.0)) return cancelled();
    std::lock_guard<std::mutex> lock(m.busy);
    // per basis kernel r, the sources' weights times the share of r in their blended kernel,
    // sum over the blend of weight x coefficient[k][r], on the transform's grid
    std::vector<std::complex<float>>& image = m.image;
    image.assign(size_t(B) * N, std::complex<float>(0));
#pragma omp parallel for num_threads(m.threads) if (parallel)
    for (int j = 0; j < g.height; ++j) {
        std::vector<std::complex<double>> share(B);
        for (int i = 0; i < g.width; ++i) {
            const std::complex<float> w = sources.weight[size_t(j) * g.width + i];
            if (w == std::complex<float>(0)) continue;
            size_t index[8];
            double weight[8];
            const int used = m.blend_of(sources, i, j, index, weight);
            std::fill(share.begin(), share.end(), 0.0);
            for (int u = 0; u < used; ++u)
                for (int r = 0; r < B; ++r) share[r] += weight[u] * basis.coefficient[index[u] * B + r];
            for (int r = 0; r < B; ++r)
                image[size_t(r) * N + size_t(j) * g.nx + i] = std::complex<float>(share[r]) * w;
        }
    }
    // per domain point of the transform's grid, the sum over sub-points of |u|^2 (or Re u)
    std::vector<double>& film = m.film;
    film.assign(N, 0.0);
    if (m.gpu) {
        m.gpu->begin_run();
        for (int r = 0; r < B; ++r) {
            if (progress && !progress((r + 1.0) / steps)) return cancelled();
            std::copy(image.begin() + size_t(r) * N, image.begin() + size_t(r + 1) * N, m.gpu->sources());
            if (auto e = m.gpu->add_sources(r); !e.ok()) return e;
        }
        std::vector<float> sum;
        if (auto e = m.gpu->finish_run(m.spec.incoherent, sum); !e.ok()) return e;
        std::copy(sum.begin(), sum.end(), film.begin());
    } else {
        for (int r = 0; r < B; ++r) {
            if (progress && !progress((r + 1.0) / steps)) return cancelled();
            m.fft->forward(image.data() + size_t(r) * N, g.height);
        }
        // the products, summed over the basis per sub-point: a block of points at a time, so
        // that each sum stays in cache while the basis streams past
        std::vector<std::complex<float>>& total = m.total;
        total.assign(size_t(S) * N, std::complex<float>(0));
        constexpr size_t kBlock = 2048;
        const long blocks = long((N + kBlock - 1) / kBlock);
#pragma omp parallel for num_threads(m.threads) schedule(static) if (parallel)
        for (long b = 0; b < blocks; ++b) {
            const size_t q0 = size_t(b) * kBlock, q1 = std::min(N, q0 + kBlock);
            for (int sub = 0; sub < S; ++sub) {
                std::complex<float>* t = total.data() + size_t(sub) * N;
                for (int r = 0; r < B; ++r) {
                    const std::complex<float>* k = m.spectrum(r, sub);
                    const std::complex<float>* im = image.data() + size_t(r) * N;
                    for (size_t q = q0; q < q1; ++q) t[q] += im[q] * k[q];
                }
            }
        }
        for (int sub = 0; sub < S; ++sub) {
            if (progress && !progress((B + 1.0 + sub) / steps)) return cancelled();
            std::complex<float>* u = total.data() + size_t(sub) * N;
            m.fft->inverse(u);
#pragma omp parallel for num_threads(m.threads) if (parallel)
            for (size_t q = 0; q < N; ++q) film[q] += m.spec.incoherent ? u[q].real() : std::norm(u[q]);
        }
    }
    // each pixel's mean over its points
    const PinholeCamera& c = m.spec.camera;
    const int o = m.spec.overscan;
    const double coherent = 1.0 / (double(N) * N), incoherent = 1.0 / double(N);
    const double norm = scale / S * (m.spec.incoherent ? incoherent : coherent);
    for (int cj = row_begin; cj < row_end; ++cj)
        for (int ci = o; ci < c.width - o; ++ci)
            irradiance[size_t(cj) * c.width + ci] += float(film[size_t(cj + g.origin) * g.nx + ci + g.origin] * norm);
    if (progress && !progress(1.0)) return cancelled();
    return Result<bool>::success(true);
}

std::vector<float> CoherentConvolution::power_balance(const CoherentSources& sources) const {
    const Impl& m = *impl_;
    const Geometry& g = m.g;
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

void CoherentConvolution::add_far_tail(const float* radiance, const float* depth, DepthMeaning meaning, double scale,
                                       int row_begin, int row_end, float* irradiance) const {
    const Impl& m = *impl_;
    const PinholeCamera& c = m.spec.camera;
    const int o = m.spec.overscan, out_w = c.width - 2 * o, out_h = c.height - 2 * o, R = m.g.radius;
    std::vector<float> rgb(3 * size_t(c.width) * c.height, 0.0f), xyz(3 * size_t(out_w) * out_h, 0.0f);
    for (size_t q = 0; q < size_t(c.width) * c.height; ++q) rgb[3 * q] = radiance[q];
    const SpectralScene scene{c, rgb.data(), depth, meaning, true};
    detail::add_far_tail(m.tail, scene, m.g.origin, R, R, out_w, out_h, xyz.data(), m.threads);
    for (int cj = std::max(row_begin, o); cj < std::min(row_end, c.height - o); ++cj)
        for (int ci = o; ci < c.width - o; ++ci)
            irradiance[size_t(cj) * c.width + ci] += float(scale * xyz[3 * (size_t(cj - o) * out_w + ci - o)]);
}

CoherentWork coherent_work(const CoherentSpec& spec, SumCounts in, SumCounts out) {
    const Geometry g = geometry_of(spec);
    const double side = 2.0 * g.radius + 1, S = double(spec.subsamples) * spec.subsamples;
    const double kernels = double(g.anchors()) * std::min(g.layers.count, kMaxPsfLayers + 1);
    in.points = 1;
    out.points = side * side * S;
    const double N = double(g.nx) * g.ny, transform = kFftCost * N * std::log2(N);
    CoherentWork w;
    w.kernels = kernels * (choose_sum(in, Summation::Auto).work + choose_sum(out, Summation::Auto).work + S * transform);
    w.per_run = kernels * transform + (kernels + 1) * S * N * kMacCost + S * transform;
    return w;
}

double coherent_bytes(const CoherentSpec& spec) {
    const Geometry g = geometry_of(spec);
    const double N = double(g.nx) * g.ny, S = double(spec.subsamples) * spec.subsamples;
    const double kernels = double(g.anchors()) * std::min(g.layers.count, kMaxPsfLayers + 1);
    const double complex_float = 8;
    // (upper bounds: the basis holds at most every kernel) spectra, a run's images and sums
    return complex_float * N * (kernels * S + kernels + S) + sizeof(double) * N;
}

}  // namespace wavecam::detail
