#include "wavecam/fast_diffraction.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <sstream>

#include "progress_ticker.h"
#include "real_fft2d.h"
#include "wavecam/fresnel_psf.h"

namespace wavecam {
namespace {

constexpr double kMaxDefocusStep = 0.3;  // radians of defocus phase over the pinhole between layers
constexpr int kMaxLayers = 16;

using KernelSet = std::vector<float>;  // 9 kernels (primary p -> XYZ q at index 3p + q), each (2R+1)^2

Result<bool> validate(const SpectralScene& scene) {
    const PinholeCamera& c = scene.camera;
    if (c.width < 1 || c.height < 1) return Result<bool>::failure("image: expected at least 1x1 pixels");
    const size_t n = size_t(c.width) * c.height;
    for (size_t p = 0; p < n; ++p) {
        std::ostringstream where;
        where << "pixel (" << p % c.width << ", " << p / c.width << ")";
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(scene.rgb[3 * p + k]))
                return Result<bool>::failure("radiance: " + where.str() + " is not finite");
        if (std::isnan(scene.depth[p]) || !(scene.depth[p] > 0))
            return Result<bool>::failure("depth: " + where.str() + " expected a distance > 0 (inf or >= 1e9 for sky)");
    }
    return Result<bool>::success(true);
}

// Planar inverse depth of each pixel (0 for sky).
std::vector<double> inverse_depths(const SpectralScene& scene) {
    const PinholeCamera& c = scene.camera;
    std::vector<double> w(size_t(c.width) * c.height);
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            const size_t p = size_t(j) * c.width + i;
            const double d = scene.depth[p];
            w[p] = d >= kInfiniteDepth ? 0.0 : 1.0 / c.planar_depth(i, j, d, scene.depth_meaning);
        }
    return w;
}

}  // namespace

Result<bool> diffract_fast(const SpectralScene& scene, const SpectralBasis& basis, const Aperture& aperture,
                           bool vignetting, float* xyz, const FastSettings& settings, const ProgressFn& progress) {
    if (auto v = validate(scene); !v.ok()) return v;
    const PinholeCamera& c = scene.camera;
    const int W = c.width, H = c.height, S = basis.size();
    const int threads = settings.nthreads > 0 ? settings.nthreads : omp_get_max_threads();

    // Depth layers, even in 1/z.
    const std::vector<double> inv = inverse_depths(scene);
    const double w_max = *std::max_element(inv.begin(), inv.end());
    double lambda_min = basis.wavelength(0), lambda_max = basis.wavelength(0);
    for (int s = 0; s < S; ++s) {
        lambda_min = std::min(lambda_min, basis.wavelength(s));
        lambda_max = std::max(lambda_max, basis.wavelength(s));
    }
    const double radius = aperture.bounding_radius();
    // defocus phase pi a^2 dw / lambda <= kMaxDefocusStep
    const double dw = kMaxDefocusStep * lambda_min / (M_PI * radius * radius);
    const int layers = w_max > 0 ? std::min(kMaxLayers, int(std::ceil(w_max / dw)) + 1) : 1;
    const double layer_step = layers > 1 ? w_max / (layers - 1) : 1.0;
    // Each pixel's light is shared between the two layers around its 1/z, linearly: the PSF is
    // interpolated in depth as it is over the field.
    std::vector<int> layer_of(inv.size());
    std::vector<float> upper_share(inv.size(), 0.0f);
    for (size_t p = 0; p < inv.size(); ++p) {
        const double x = layers > 1 ? inv[p] / layer_step : 0.0;
        layer_of[p] = std::min(layers - 1, int(std::floor(x)));
        upper_share[p] = float(x - layer_of[p]);
    }
    auto layer_weight = [&](size_t p, int l) {
        return l == layer_of[p] ? 1.0f - upper_share[p] : l == layer_of[p] + 1 ? upper_share[p] : 0.0f;
    };

    // Field anchors at the image's corners, edges and inside, about 5 across the long side.
    const int longest = std::max(W, H);
    const int ax = settings.anchors_x > 0 ? settings.anchors_x : std::max(2, int(std::lround(5.0 * W / longest)));
    const int ay = settings.anchors_y > 0 ? settings.anchors_y : std::max(2, int(std::lround(5.0 * H / longest)));
    const double pitch = c.film_distance * c.tan_pitch();
    const double cos_max = std::sqrt(1.0 - std::pow(c.sin_max_field_angle(), 2));
    const double nearest = w_max > 0 ? 1.0 / w_max : INFINITY;
    const int R = psf_kernel_radius(aperture, c.film_distance, nearest, lambda_max, cos_max, pitch, settings.max_radius);
    const int kw = 2 * R + 1;
    const size_t ksize = size_t(kw) * kw;

    // Kernels per (layer, anchor): the wavelength sum folded into nine RGB -> XYZ kernels.
    std::vector<KernelSet> kernels(size_t(layers) * ax * ay, KernelSet(9 * ksize, 0.0f));
    const long grid = long(kernels.size());
    detail::ProgressTicker ticker(progress, double(grid) * S * 2);  // kernels: first half of the work
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (long g = 0; g < grid; ++g) {
        if (ticker.cancelled()) continue;
        const int l = int(g / (ax * ay)), a = int(g % (ax * ay));
        FieldPsfRequest q;
        q.aperture = aperture;
        q.film_distance = c.film_distance;
        q.depth = l * layer_step > 0 ? 1.0 / (l * layer_step) : INFINITY;
        c.tangent(double(a % ax) / (ax - 1) * W, double(a / ax) / (ay - 1) * H, q.u, q.v);
        q.pixel_pitch = pitch;
        q.radius = R;
        KernelSet& k = kernels[g];
        for (int s = 0; s < S; ++s) {
            q.wavelength = basis.wavelength(s);
            const PsfKernel psf = field_psf_kernel(q);
            const Vector3& xyz_s = basis.xyz_per_power(s);
            for (int p = 0; p < 3; ++p) {
                const double bp = basis.power(s, p == 0, p == 1, p == 2);
                for (int qq = 0; qq < 3; ++qq) {
                    const float wgt = float(bp * xyz_s[qq]);
                    float* dst = &k[(3 * p + qq) * ksize];
                    for (size_t e = 0; e < ksize; ++e) dst[e] += wgt * psf.weight[e];
                }
            }
            ticker.advance(1, omp_get_thread_num() == 0);
        }
    }
    if (ticker.cancelled()) return Result<bool>::failure("cancelled");

    // Tiles: overlap-add FFT convolution, four passes so that concurrent tiles never overlap.
    const int T = settings.tile, N = detail::fft_friendly_size(T + 2 * R);
    const int ntx = (W + T - 1) / T, nty = (H + T - 1) / T;
    std::fill(xyz, xyz + 3 * size_t(W) * H, 0.0f);
    std::vector<std::unique_ptr<detail::RealFft2D>> ffts(threads);
    std::atomic<bool> fft_failed{false};
    const double tile_share = double(grid) * S / (double(ntx) * nty);
    for (int phase = 0; phase < 4; ++phase) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
        for (long t = 0; t < long(ntx) * nty; ++t) {
            const int tx = int(t % ntx), ty = int(t / ntx);
            if ((tx % 2) + 2 * (ty % 2) != phase || ticker.cancelled()) continue;
            auto& fft = ffts[omp_get_thread_num()];
            if (!fft) fft = std::make_unique<detail::RealFft2D>(N);
            if (!fft->ok()) {
                fft_failed = true;
                continue;
            }
            const size_t spec = fft->spectrum_size();
            std::vector<float> image(size_t(N) * N);
            std::vector<std::complex<float>> in(3 * spec), kern(9 * spec), acc(spec);
            const int x0 = tx * T, y0 = ty * T, x1 = std::min(W, x0 + T), y1 = std::min(H, y0 + T);
            // bilinear anchor weights at the tile centre
            const double fx = (0.5 * (x0 + x1)) / W * (ax - 1), fy = (0.5 * (y0 + y1)) / H * (ay - 1);
            const int ia = std::min(ax - 2, int(fx)), ja = std::min(ay - 2, int(fy));
            const double bx = fx - ia, by = fy - ja;
            for (int l = 0; l < layers; ++l) {
                bool present = false;
                for (int j = y0; j < y1 && !present; ++j)
                    for (int i = x0; i < x1 && !present; ++i) present = layer_weight(size_t(j) * W + i, l) > 0;
                if (!present) continue;
                // the tile's kernels, interpolated over the anchors
                const size_t base = size_t(l) * ax * ay;
                const KernelSet* k4[4] = {&kernels[base + ja * ax + ia], &kernels[base + ja * ax + ia + 1],
                                          &kernels[base + (ja + 1) * ax + ia], &kernels[base + (ja + 1) * ax + ia + 1]};
                const float w4[4] = {float((1 - bx) * (1 - by)), float(bx * (1 - by)), float((1 - bx) * by),
                                     float(bx * by)};
                for (int m = 0; m < 9; ++m) {
                    std::fill(image.begin(), image.end(), 0.0f);
                    for (int b = -R; b <= R; ++b)
                        for (int a = -R; a <= R; ++a) {
                            const size_t e = size_t(m) * ksize + size_t(b + R) * kw + (a + R);
                            image[size_t((b + N) % N) * N + (a + N) % N] =
                                w4[0] * (*k4[0])[e] + w4[1] * (*k4[1])[e] + w4[2] * (*k4[2])[e] + w4[3] * (*k4[3])[e];
                        }
                    fft->forward(image.data(), &kern[m * spec]);
                }
                // the tile's sources in this layer, with the natural cos^4 fall-off of their light
                for (int p = 0; p < 3; ++p) {
                    std::fill(image.begin(), image.end(), 0.0f);
                    for (int j = y0; j < y1; ++j)
                        for (int i = x0; i < x1; ++i) {
                            const size_t px = size_t(j) * W + i;
                            if (const float share = layer_weight(px, l); share > 0)
                                image[size_t(j - y0) * N + (i - x0)] =
                                    float(share * scene.rgb[3 * px + p] * c.cos4(i, j));
                        }
                    fft->forward(image.data(), &in[p * spec]);
                }
                const float norm = 1.0f / (float(N) * N);
                for (int qq = 0; qq < 3; ++qq) {
                    for (size_t e = 0; e < spec; ++e)
                        acc[e] = in[e] * kern[qq * spec + e] + in[spec + e] * kern[(3 + qq) * spec + e] +
                                 in[2 * spec + e] * kern[(6 + qq) * spec + e];
                    fft->inverse(acc.data(), image.data());
                    for (int r = -R; r < (y1 - y0) + R; ++r) {
                        const int j = y0 + r;
                        if (j < 0 || j >= H) continue;
                        for (int s2 = -R; s2 < (x1 - x0) + R; ++s2) {
                            const int i = x0 + s2;
                            if (i < 0 || i >= W) continue;
                            xyz[3 * (size_t(j) * W + i) + qq] += norm * image[size_t((r + N) % N) * N + (s2 + N) % N];
                        }
                    }
                }
            }
            ticker.advance(long(std::lround(tile_share)), omp_get_thread_num() == 0);
        }
    }
    if (ticker.cancelled()) return Result<bool>::failure("cancelled");
    if (fft_failed) return Result<bool>::failure("fft: cannot set up a " + std::to_string(N) + "-point transform");
    if (!vignetting)
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i)
                for (int qq = 0; qq < 3; ++qq) xyz[3 * (size_t(j) * W + i) + qq] /= float(c.cos4(i, j));
    return Result<bool>::success(true);
}

}  // namespace wavecam
