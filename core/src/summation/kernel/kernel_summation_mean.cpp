// The kernel summation's power balance per source, and what its runs' mean adds: the blend's mean
// and the far tail (kernel_summation.h: energy, the blend's mean, the far tail).
#include <algorithm>
#include <cmath>

#include "base/parallel.h"
#include "convolution/far_tail.h"
#include "summation/kernel/kernel_summation_impl.h"
#include "wavecam/spectral_diffraction.h"

namespace wavecam::detail {

namespace {

// Per source and blended kernel u, its anchor's layer balance beta_a (the power the layers'
// blend L_a lacks, phi_a times it: the anchor's weights sum to phi_a); 8 per domain pixel.
std::vector<float> layer_balances(const KernelSummation::Impl& m, const KernelSummationSources& sources,
                                  const std::vector<float>& power) {
    const KernelSummationGeometry& g = m.g;
    const size_t n = size_t(g.width) * g.height;
    const size_t A = size_t(g.anchors()), K = size_t(g.layers.count) * A;
    std::vector<float> beta(n * 8, 1.0f);
    parallel_for(0, g.height, m.threads, [&](int64_t j_) {
        const int j = int(j_);
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
    });
    return beta;
}

}  // namespace

std::vector<float> KernelSummation::power_balance(const KernelSummationSources& sources) const {
    const Impl& m = *impl_;
    if (m.directions) return m.directions->power_balance(sources);
    const KernelSummationGeometry& g = m.g;
    const size_t n = size_t(g.width) * g.height, K = size_t(g.layers.count) * g.anchors();
    std::vector<float> factor(n, 1.0f);
    if (m.spec.incoherent) return factor;
    parallel_for(0, g.height, m.threads, [&](int64_t j_) {
        const int j = int(j_);
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
    });
    return factor;
}

void KernelSummation::add_blend_mean(const KernelSummationSources& sources, const std::vector<float>& power,
                                  const std::vector<float>& balance, const RowRange& rows, float* each) const {
    const Impl& m = *impl_;
    if (m.spec.incoherent || m.directions) return;  // (its powers are blended as they are; directions blend no anchors)
    const KernelSummationGeometry& g = m.g;
    const PinholeCamera& c = m.spec.camera;
    const int R = g.radius, side = 2 * R + 1, o = m.spec.overscan;
    const size_t P = size_t(side) * side, N9 = Impl::kNeighbours, A = size_t(g.anchors());
    const std::vector<float> beta = layer_balances(m, sources, power);
    // Each camera row of the share, within the overscan, from every source whose kernel reaches
    // it, in one order whatever the threads and the share (a job is the sum of its shares to the
    // bit): only that row of each source's image is formed.
    parallel_for_dynamic(std::max(rows.begin, o), std::min(rows.end, c.height - o), 1, m.threads, [&](int64_t cj_) {
        const int cj = int(cj_);
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
    });
}

void KernelSummation::add_far_tail(const float* radiance, const float* depth, DepthMeaning meaning, double scale,
                                const RowRange& rows, float* irradiance) const {
    const Impl& m = *impl_;
    if (m.directions) return;  // (a source's light is whole, beyond its margin but a kDirectionMarginLight share)
    const PinholeCamera& c = m.spec.camera;
    const int o = m.spec.overscan, out_w = c.width - 2 * o, out_h = c.height - 2 * o, R = m.g.radius;
    std::vector<float> rgb(3 * size_t(c.width) * c.height, 0.0f), xyz(3 * size_t(out_w) * out_h, 0.0f);
    for (size_t q = 0; q < size_t(c.width) * c.height; ++q) rgb[3 * q] = radiance[q];
    const SpectralScene scene{c, rgb.data(), depth, meaning, true};
    detail::add_far_tail(m.tail, detail::film_kernel_edge(m.tail.radius, c.tan_pitch()), false, scene, m.g.origin, {R, R, out_w, out_h}, xyz.data(), m.threads);
    for (int cj = std::max(rows.begin, o); cj < std::min(rows.end, c.height - o); ++cj)
        for (int ci = o; ci < c.width - o; ++ci)
            irradiance[size_t(cj) * c.width + ci] += float(scale * xyz[3 * (size_t(cj - o) * out_w + ci - o)]);
}

}  // namespace wavecam::detail
