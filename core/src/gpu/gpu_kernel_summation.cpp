// The kernel summation's runs on a Vulkan device (gpu_kernel_summation.h).
#include "gpu/gpu_kernel_summation.h"

#include <cmath>
#include <cstring>
#include <string>

#include "gpu/compute_device_impl.h"
#include "fft_lines.h"
#include "film_power.h"
#include "spectrum_product.h"
#include "gpu/vulkan_context.h"

namespace wavecam::detail {

namespace {

struct FftPush {
    uint32_t n, log2n, element_step, line_step, twiddle_offset, inverse;
};
struct ProductPush {
    uint32_t n, spectrum_offset;
};
struct PowerPush {
    uint32_t n, powers;
};
constexpr uint32_t kGroup = 256;  // local_size_x of the shaders

int log2_of(int n) {
    int k = 0;
    while ((1 << k) < n) ++k;
    return k;
}

template <class P>
gpu::Context::Step step(const gpu::Pipeline& p, std::vector<const gpu::Buffer*> buffers, const P& push, uint32_t gx) {
    gpu::Context::Step s{&p, std::move(buffers), {}, gx, 1};
    std::memcpy(s.push.data(), &push, sizeof push);
    return s;
}

}  // namespace

struct GpuKernelSummation::Impl {
    std::shared_ptr<gpu::Context> ctx;  // the device's, shared with its direct sums
    gpu::Pipeline fft, product, power;
    int nx = 0, ny = 0, points = 0;
    size_t per_slab = 1;            // spectra per buffer
    std::vector<gpu::Buffer> slabs;  // the spectra, kernel by kernel, sub-point by sub-point
    gpu::Buffer twiddles;           // rows' table, then columns'
    gpu::Buffer image, pixel;
    std::vector<gpu::Buffer> totals;  // one per sub-point
    size_t size() const { return size_t(nx) * ny; }

    // Both passes of a 2D transform of `data`, in place.
    void transform(const gpu::Buffer& data, bool inverse, std::vector<gpu::Context::Step>& steps) const {
        steps.push_back(step(fft, {&data, &twiddles},
                             FftPush{uint32_t(nx), uint32_t(log2_of(nx)), 1, uint32_t(nx), 0, inverse}, ny));
        steps.push_back(step(fft, {&data, &twiddles},
                             FftPush{uint32_t(ny), uint32_t(log2_of(ny)), uint32_t(nx), 1, uint32_t(nx / 2), inverse},
                             nx));
    }
    uint32_t groups() const { return uint32_t((size() + kGroup - 1) / kGroup); }
};

GpuKernelSummation::GpuKernelSummation(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuKernelSummation::~GpuKernelSummation() = default;

Result<std::unique_ptr<GpuKernelSummation>> GpuKernelSummation::create(const ComputeDevice& device, int nx, int ny,
                                                                 int kernels, int points) {
    using R = Result<std::unique_ptr<GpuKernelSummation>>;
    const auto power_of_two = [](int n) { return n >= 2 && n <= kMaxSide && (n & (n - 1)) == 0; };
    if (!power_of_two(nx) || !power_of_two(ny))
        return R::failure("GPU kernel summation: transforms of " + std::to_string(nx) + " x " + std::to_string(ny) +
                              " points; the device's take powers of two up to " + std::to_string(kMaxSide) + " a side",
                          ErrorKind::Invalid, "device");
    if (!device.gpu()) {
        const std::string why = device.error().empty() ? "the device `cpu` is no GPU" : device.error();
        return R::failure("GPU kernel summation: " + why, ErrorKind::Invalid, "device");
    }
    auto m = std::make_unique<Impl>();
    m->ctx = device.impl()->context;
    m->nx = nx;
    m->ny = ny;
    m->points = points;
    const size_t bytes = m->size() * 8, max = m->ctx->max_buffer_bytes();
    if (m->ctx->shared_memory_bytes() < size_t(kMaxSide) * 8 || bytes > max)
        return R::failure("GPU kernel summation: " + m->ctx->name() + " holds too little for transforms of " +
                              std::to_string(nx) + " x " + std::to_string(ny) + " points",
                          ErrorKind::Failed, "device");
    auto fft = m->ctx->pipeline(gpu::spirv::fft_lines, sizeof gpu::spirv::fft_lines, 2, sizeof(FftPush));
    auto product = m->ctx->pipeline(gpu::spirv::spectrum_product, sizeof gpu::spirv::spectrum_product, 3,
                                    sizeof(ProductPush));
    auto power = m->ctx->pipeline(gpu::spirv::film_power, sizeof gpu::spirv::film_power, 2, sizeof(PowerPush));
    for (auto* p : {&fft, &product, &power})
        if (!p->ok()) return R::failure(p->error, ErrorKind::Failed, "device");
    m->fft = std::move(fft.value);
    m->product = std::move(product.value);
    m->power = std::move(power.value);
    // buffers: twiddles exp(-2 pi i j / n) for both sides (double, rounded once), image, pixel,
    // one total per sub-point, and the spectra in slabs of at most the binding range
    auto buffer = [&](size_t b, gpu::Buffer& into) -> Result<bool> {
        auto r = m->ctx->buffer(b);
        if (!r.ok()) return Result<bool>::failure(r.error, ErrorKind::Failed, "device");
        into = std::move(r.value);
        return Result<bool>::success(true);
    };
    if (auto r = buffer(size_t(nx / 2 + ny / 2) * 8, m->twiddles); !r.ok()) return R::failure(r);
    auto* tw = static_cast<float*>(m->twiddles.data());
    size_t at = 0;
    for (int n : {nx, ny})
        for (int j = 0; j < n / 2; ++j, ++at) {
            tw[2 * at] = float(std::cos(2 * M_PI * j / n));
            tw[2 * at + 1] = float(-std::sin(2 * M_PI * j / n));
        }
    if (auto r = buffer(bytes, m->image); !r.ok()) return R::failure(r);
    if (auto r = buffer(m->size() * 4, m->pixel); !r.ok()) return R::failure(r);
    m->totals.resize(points);
    for (auto& t : m->totals)
        if (auto r = buffer(bytes, t); !r.ok()) return R::failure(r);
    const size_t spectra = size_t(kernels) * points;
    m->per_slab = std::max<size_t>(1, max / bytes);
    m->slabs.resize((spectra + m->per_slab - 1) / m->per_slab);
    for (size_t k = 0; k < m->slabs.size(); ++k)
        if (auto r = buffer(std::min(m->per_slab, spectra - k * m->per_slab) * bytes, m->slabs[k]); !r.ok())
            return R::failure(r);
    return R::success(std::unique_ptr<GpuKernelSummation>(new GpuKernelSummation(std::move(m))));
}

Result<bool> GpuKernelSummation::set_spectrum(int kernel, int point, const std::complex<float>* spectrum) {
    const Impl& m = *impl_;
    const size_t index = size_t(kernel) * m.points + point;
    std::memcpy(static_cast<std::complex<float>*>(m.slabs[index / m.per_slab].data()) + (index % m.per_slab) * m.size(),
                spectrum, m.size() * 8);
    return Result<bool>::success(true);
}

void GpuKernelSummation::begin_run() {
    for (auto& t : impl_->totals) std::memset(t.data(), 0, t.bytes());
}

std::complex<float>* GpuKernelSummation::sources() { return static_cast<std::complex<float>*>(impl_->image.data()); }

Result<bool> GpuKernelSummation::add_sources(int kernel) {
    const Impl& m = *impl_;
    std::vector<gpu::Context::Step> steps;
    m.transform(m.image, false, steps);
    // (one product per sub-point: a pixel of many sub-points takes several submissions, each
    // after the last, so the image's transform comes first)
    for (int p = 0; p < m.points; ++p) {
        const size_t index = size_t(kernel) * m.points + p;
        steps.push_back(step(m.product, {&m.image, &m.slabs[index / m.per_slab], &m.totals[p]},
                             ProductPush{uint32_t(m.size()), uint32_t((index % m.per_slab) * m.size())}, m.groups()));
        if (steps.size() == gpu::Context::kMaxSteps) {
            if (auto r = m.ctx->submit(steps); !r.ok()) return r;
            steps.clear();
        }
    }
    return steps.empty() ? Result<bool>::success(true) : m.ctx->submit(steps);
}

Result<bool> GpuKernelSummation::finish_run(bool powers, std::vector<float>& sum) {
    const Impl& m = *impl_;
    std::memset(m.pixel.data(), 0, m.pixel.bytes());
    std::vector<gpu::Context::Step> steps;
    for (int p = 0; p < m.points; ++p) {
        m.transform(m.totals[p], true, steps);
        steps.push_back(step(m.power, {&m.totals[p], &m.pixel}, PowerPush{uint32_t(m.size()), powers}, m.groups()));
        if (steps.size() + 3 > gpu::Context::kMaxSteps || p + 1 == m.points) {
            if (auto r = m.ctx->submit(steps); !r.ok()) return r;
            steps.clear();
        }
    }
    const float* v = static_cast<const float*>(m.pixel.data());
    sum.assign(v, v + m.size());
    return Result<bool>::success(true);
}

}  // namespace wavecam::detail
