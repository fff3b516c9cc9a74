// The direct sums on a Vulkan device (wavecam/gpu_sums.h). The host lays the terms out exactly as
// the CPU kernel does (propagation.cpp: the same float casts of positions, |P|^2, |P|, |T|^2, |T|),
// the shaders (shaders/*.comp) sum them, and the host applies the same double scaling after.
#include "wavecam/gpu_sums.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>

#include "gpu/compute_device_impl.h"
#include "film_f32.h"
#include "film_f64.h"
#include "illuminate_f32.h"
#include "illuminate_f64.h"
#include "gpu/vulkan_context.h"

namespace wavecam {


namespace {

// The shaders' push constants (shaders/illuminate.comp, film.comp).
struct Push {
    uint32_t n_out, n_finite, n_terms, runs;
    float inv_lambda, f;
};
constexpr uint32_t kGroup = 64;      // local_size_x
constexpr uint32_t kRunsPerGroup = 4;  // kRuns: runs per workgroup; more runs, more groups in y
// Terms x runs per dispatch: a dispatch stays short (progress, cancellation, GPU watchdogs).
constexpr double kTermsPerDispatch = double(1 << 30);
// Terms one invocation sums in a dispatch: Mesa's llvmpipe (lavapipe) stops any loop after 65535
// iterations in all (its guard against endless loops, counted across a nested loop's entries),
// which silently dropped the terms past it (a 0.1 mm pinhole's 104517 samples to one film point
// came out 38% off); more terms go through further dispatches, their sums added on the host.
constexpr size_t kTermsPerInvocation = size_t(1) << 15;

// One sum: out[r * n_points + o] += sum_t phasor(o, t) w[r * n_terms + t].
struct SumJob {
    const gpu::Pipeline* pipe;
    const std::vector<float>* points;  // per output point: point_floats floats
    size_t point_floats;
    const std::vector<float>* terms;  // per term: term_floats floats
    size_t term_floats;
    size_t n_finite;  // sum 1: terms below it are finite sources, the rest plane waves
    const std::vector<float>* weights;  // runs x terms x (re, im)
    size_t runs;
    float inv_lambda, f;
    size_t n_points() const { return points->size() / point_floats; }
    size_t n_terms() const { return terms->size() / term_floats; }
};

Result<bool> cancelled() { return Result<bool>::failure("cancelled", ErrorKind::Cancelled); }

}  // namespace

struct GpuSums::Impl {
    std::shared_ptr<gpu::Context> ctx;  // the device's, shared with the kernel summation's runs
    gpu::Pipeline illuminate, film;
    std::string description;
    bool f64 = false;  // blocks added in double (else the compensated float pair)
    std::mutex busy;

    Result<bool> run(const SumJob& job, std::vector<std::complex<double>>& out, const ProgressFn& progress);
};

Result<bool> GpuSums::Impl::run(const SumJob& job, std::vector<std::complex<double>>& out,
                                const ProgressFn& progress) {
    const size_t np = job.n_points(), nt = job.n_terms(), R = job.runs, max = ctx->max_buffer_bytes();
    out.assign(R * np, 0.0);
    if (np == 0 || nt == 0) return Result<bool>::success(true);
    // chunks of terms and of output points whose buffers fit the device's binding range
    size_t tc = std::min({nt, max / (8 * R), max / (4 * job.term_floats), kTermsPerInvocation});
    size_t oc = std::min({np, max / (16 * R), max / (4 * job.point_floats)});
    const size_t by_time = size_t(kTermsPerDispatch / (double(tc) * R));
    oc = std::min(oc, std::max<size_t>(kGroup, by_time / kGroup * kGroup));
    if (tc == 0 || oc == 0) return Result<bool>::failure("GPU sums: " + std::to_string(R) + " runs at once do not fit a "
                                                         "buffer of " + ctx->name());
    auto points = ctx->buffer(oc * job.point_floats * 4);
    auto terms = ctx->buffer(tc * job.term_floats * 4);
    auto weights = ctx->buffer(R * tc * 8);
    auto sums = ctx->buffer(R * oc * 16);
    for (auto* b : {&points, &terms, &weights, &sums})
        if (!b->ok()) return Result<bool>::failure(*b);
    const double total = double(np) * nt;
    double done = 0;
    for (size_t t0 = 0; t0 < nt; t0 += tc) {
        const size_t tn = std::min(tc, nt - t0);
        std::memcpy(terms.value.data(), job.terms->data() + t0 * job.term_floats, tn * job.term_floats * 4);
        for (size_t r = 0; r < R; ++r)
            std::memcpy(static_cast<float*>(weights.value.data()) + 2 * r * tn,
                        job.weights->data() + 2 * (r * nt + t0), tn * 8);
        const size_t finite = std::clamp(job.n_finite, t0, t0 + tn) - t0;
        for (size_t o0 = 0; o0 < np; o0 += oc) {
            const size_t on = std::min(oc, np - o0);
            std::memcpy(points.value.data(), job.points->data() + o0 * job.point_floats, on * job.point_floats * 4);
            const Push push{uint32_t(on), uint32_t(finite), uint32_t(tn), uint32_t(R), job.inv_lambda, job.f};
            auto d = ctx->dispatch(*job.pipe, {&points.value, &terms.value, &weights.value, &sums.value}, &push,
                                   uint32_t((on + kGroup - 1) / kGroup),
                                   uint32_t((R + kRunsPerGroup - 1) / kRunsPerGroup));
            if (!d.ok()) return d;
            for (size_t r = 0; r < R; ++r)
                for (size_t o = 0; o < on; ++o) {
                    std::complex<double> v;
                    if (f64) {
                        const double* s = static_cast<const double*>(sums.value.data()) + 2 * (r * on + o);
                        v = {s[0], s[1]};
                    } else {  // sum + compensation
                        const float* s = static_cast<const float*>(sums.value.data()) + 4 * (r * on + o);
                        v = {double(s[0]) + s[2], double(s[1]) + s[3]};
                    }
                    out[r * np + o0 + o] += v;
                }
            done += double(on) * tn;
            if (progress && !progress(done / total)) return cancelled();
        }
    }
    return Result<bool>::success(true);
}

GpuSums::GpuSums(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuSums::~GpuSums() = default;

Result<std::shared_ptr<GpuSums>> GpuSums::create(const ComputeDevice& device, bool double_blocks) {
    using R = Result<std::shared_ptr<GpuSums>>;
    if (!device.impl() || !device.impl()->context)
        return R::failure("GPU sums: " + (device.error().empty() ? "the device `cpu` is no GPU" : device.error()),
                          ErrorKind::Invalid, "device");
    auto impl = std::make_unique<Impl>();
    impl->ctx = device.impl()->context;
    const bool f64 = impl->f64 = double_blocks && impl->ctx->float64();
    auto ill = f64 ? impl->ctx->pipeline(gpu::spirv::illuminate_f64, sizeof gpu::spirv::illuminate_f64, 4, sizeof(Push))
                   : impl->ctx->pipeline(gpu::spirv::illuminate_f32, sizeof gpu::spirv::illuminate_f32, 4, sizeof(Push));
    auto film = f64 ? impl->ctx->pipeline(gpu::spirv::film_f64, sizeof gpu::spirv::film_f64, 4, sizeof(Push))
                    : impl->ctx->pipeline(gpu::spirv::film_f32, sizeof gpu::spirv::film_f32, 4, sizeof(Push));
    if (!ill.ok()) return R::failure(ill.error, ErrorKind::Failed, "device");
    if (!film.ok()) return R::failure(film.error, ErrorKind::Failed, "device");
    impl->illuminate = std::move(ill.value);
    impl->film = std::move(film.value);
    impl->description = impl->ctx->name() + ", " + impl->ctx->kind() + " (" + impl->ctx->driver() + ")";
    return R::success(std::shared_ptr<GpuSums>(new GpuSums(std::move(impl))));
}

const std::string& GpuSums::device_name() const { return impl_->ctx->name(); }
const std::string& GpuSums::driver() const { return impl_->ctx->driver(); }
bool GpuSums::double_blocks() const { return impl_->f64; }
std::string GpuSums::description() const { return impl_->description; }

Result<bool> GpuSums::illuminate_pinhole(const ApertureSamples& samples, const std::vector<PointSource>& sources,
                                         double wavelength, PinholeField& field, const ProgressFn& progress) {
    std::vector<std::complex<double>> w;
    w.reserve(sources.size());
    for (const PointSource& s : sources) w.push_back(std::polar(s.amplitude, s.phase));
    std::vector<PinholeField> fields;
    auto r = illuminate_pinhole_runs(samples, sources, {w, 1}, wavelength, fields, progress);
    if (r.ok()) field = std::move(fields[0]);
    return r;
}

Result<bool> GpuSums::illuminate_pinhole_runs(const ApertureSamples& samples, const std::vector<PointSource>& sources,
                                              const RunWeights& run_weights, double wavelength,
                                              std::vector<PinholeField>& fields, const ProgressFn& progress) {
    const std::vector<std::complex<double>>& weights = run_weights.weights;
    const int runs = run_weights.runs;
    if (runs < 1 || weights.size() != size_t(runs) * sources.size())
        return Result<bool>::failure("GPU sums: expected runs x sources weights, got " +
                                     std::to_string(weights.size()) + " for " + std::to_string(runs) + " x " +
                                     std::to_string(sources.size()), ErrorKind::Invalid);
    // finite sources (Px, Py, |P|^2, |P|) first, then plane waves (ux, uy), as propagation.cpp
    std::vector<size_t> order;
    std::vector<float> terms;
    for (int pass = 0; pass < 2; ++pass)
        for (size_t s = 0; s < sources.size(); ++s) {
            const PointSource& p = sources[s];
            if (p.at_infinity != (pass == 1)) continue;
            order.push_back(s);
            const double p2 = p.x * p.x + p.y * p.y + p.z * p.z;
            terms.insert(terms.end(), {float(p.x), float(p.y), pass ? 0.0f : float(p2),
                                       pass ? 0.0f : float(std::sqrt(p2))});
        }
    const size_t finite = std::count_if(sources.begin(), sources.end(), [](auto& p) { return !p.at_infinity; });
    std::vector<float> w(2 * weights.size());
    for (int r = 0; r < runs; ++r)
        for (size_t k = 0; k < order.size(); ++k) {
            const std::complex<double> c = weights[r * sources.size() + order[k]];
            w[2 * (r * order.size() + k)] = float(c.real());
            w[2 * (r * order.size() + k) + 1] = float(c.imag());
        }
    std::vector<float> points(2 * samples.size());
    for (size_t j = 0; j < samples.size(); ++j) {
        points[2 * j] = samples.x[j];
        points[2 * j + 1] = samples.y[j];
    }
    std::lock_guard<std::mutex> lock(impl_->busy);
    const SumJob job{&impl_->illuminate, &points, 2, &terms, 4, finite, &w, size_t(runs),
                     float(1.0 / wavelength), 0.0f};
    std::vector<std::complex<double>> out;
    if (auto r = impl_->run(job, out, progress); !r.ok()) return r;
    fields.assign(runs, {});
    const size_t n = samples.size();
    for (int r = 0; r < runs; ++r) {
        fields[r].re.resize(n);
        fields[r].im.resize(n);
        for (size_t j = 0; j < n; ++j) {
            const double scale = samples.weight[j] / wavelength;
            fields[r].re[j] = float(out[r * n + j].real() * scale);
            fields[r].im[j] = float(out[r * n + j].imag() * scale);
        }
    }
    return Result<bool>::success(true);
}

Result<bool> GpuSums::add_film_field(const ApertureSamples& samples, const PinholeField& field, const FilmPoints& film,
                                     double wavelength, std::complex<double>* film_field, const ProgressFn& progress) {
    return add_film_field_runs(samples, {field}, film, wavelength, {film_field}, progress);
}

Result<bool> GpuSums::add_film_field_runs(const ApertureSamples& samples, const std::vector<PinholeField>& fields,
                                          const FilmPoints& film, double wavelength,
                                          const std::vector<std::complex<double>*>& film_fields,
                                          const ProgressFn& progress) {
    const size_t ns = samples.size(), runs = fields.size();
    bool sizes = runs >= 1 && film_fields.size() == runs;
    for (const PinholeField& f : fields) sizes = sizes && f.re.size() == ns && f.im.size() == ns;
    if (!sizes)
        return Result<bool>::failure("GPU sums: expected one film field per pinhole field and a value per sample",
                                     ErrorKind::Invalid);
    const double f = film.film_distance;
    std::vector<float> points(4 * film.size());  // (tx, ty, |T|^2, |T|) as propagation.cpp rounds them
    for (size_t t = 0; t < film.size(); ++t) {
        const double tx = film.x[t], ty = film.y[t];
        const float r0sq = float(tx * tx + ty * ty + f * f);
        points[4 * t] = film.x[t];
        points[4 * t + 1] = film.y[t];
        points[4 * t + 2] = r0sq;
        points[4 * t + 3] = std::sqrt(r0sq);
    }
    std::vector<float> terms(2 * ns), w(2 * ns * runs);
    for (size_t j = 0; j < ns; ++j) {
        terms[2 * j] = samples.x[j];
        terms[2 * j + 1] = samples.y[j];
    }
    for (size_t r = 0; r < runs; ++r)
        for (size_t j = 0; j < ns; ++j) {
            w[2 * (r * ns + j)] = fields[r].re[j];
            w[2 * (r * ns + j) + 1] = fields[r].im[j];
        }
    std::lock_guard<std::mutex> lock(impl_->busy);
    const SumJob job{&impl_->film, &points, 4, &terms, 2, 0, &w, runs, float(1.0 / wavelength), float(f)};
    std::vector<std::complex<double>> out;
    if (auto r = impl_->run(job, out, progress); !r.ok()) return r;
    for (size_t r = 0; r < runs; ++r)
        for (size_t t = 0; t < film.size(); ++t) film_fields[r][t] += out[r * film.size() + t];
    return Result<bool>::success(true);
}

}  // namespace wavecam
