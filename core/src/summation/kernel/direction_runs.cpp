#include "summation/kernel/direction_runs.h"

#include <algorithm>
#include <cmath>

#include "base/parallel.h"
#include "summation/nufft/lattice_nufft.h"

namespace wavecam::detail {
namespace {

using cdouble = std::complex<double>;

Result<bool> cancelled() { return Result<bool>::failure("cancelled", ErrorKind::Cancelled); }

// The direction cosine along u of the ray through tangents (u, v).
double cosine(double u, double v) { return u / std::sqrt(1 + u * u + v * v); }

// Domain pixels beyond the frame on every side: enough that, on the domain's outermost row and
// column (where the field compresses the pixels most), the margin spans `reach` in direction
// cosines along both axes; at most the frame's longer side (a pinhole whose PSF is wider than the
// frame, where the pixels beyond would run to grazing angles, each of a vanishing solid angle).
int margin_for(const PinholeCamera& c, double reach) {
    const double t = c.tan_pitch(), hw = 0.5 * c.width, hh = 0.5 * c.height;
    const int most = std::max(c.width, c.height);
    for (int m = 0; m < most; ++m) {
        const double u = (hw + m) * t, v = (hh + m) * t;
        if (cosine(u, v) - cosine(hw * t, v) >= reach && cosine(v, u) - cosine(hh * t, u) >= reach) return m;
    }
    return most;
}

}  // namespace

bool runs_in_directions(const KernelSummationSpec& spec, const ComputeDevice& device) {
    const double a = spec.aperture.bounding_radius();
    return !device.gpu() && !spec.incoherent && a > 0 &&
           DepthLayers::rim_phase(spec.max_inverse_depth, a, spec.wavelength, spec.camera.film_distance) <=
               kMaxFraunhoferPhase;
}

DirectionGeometry direction_geometry(const KernelSummationSpec& spec) {
    const PinholeCamera& c = spec.camera;
    const double a = spec.aperture.bounding_radius(), lambda = spec.wavelength, t = c.tan_pitch();
    DirectionGeometry g;
    g.margin = margin_for(c, 2 * lambda / (M_PI * M_PI * 2 * a * kDirectionMarginLight));
    g.width = c.width + 2 * g.margin;
    g.height = c.height + 2 * g.margin;
    // the domain's widest direction cosines (on its middle row and column), and a pixel's guard
    const double su = cosine((0.5 * g.width) * t, 0), sv = cosine((0.5 * g.height) * t, 0);
    g.period = std::min(2.0, 2 * std::max(su, sv) + t);
    // a pinhole of few samples across on a lattice of kMinDirectionModes (its rim's samples sit on
    // lattice points: the finer the lattice, the nearer their own places)
    g.period *= std::max(1.0, std::ceil(kMinDirectionModes * lambda / (2 * a * g.period)));
    const ApertureSamples samples = sample_aperture(spec.aperture, lambda / g.period);
    g.period = lambda / samples.pitch;  // (refined where the opening is finer than the pitch)
    int reach = 0;
    for (size_t i = 0; i < samples.size(); ++i)
        reach = std::max({reach, int(std::lround(std::abs(samples.x[i]) / samples.pitch)),
                          int(std::lround(std::abs(samples.y[i]) / samples.pitch))});
    g.modes = 2 * (reach + 1);
    g.layers = amplitude_layers(spec.max_inverse_depth, a, lambda);
    return g;
}

struct DirectionRuns::Impl {
    KernelSummationSpec spec;
    DirectionGeometry g;
    int threads = 1;
    int layers = 1;
    // per layer, the pinhole's transfer H on the lattice (modes x modes, centred), and the layers'
    // powers and neighbours' overlaps (for the balance)
    std::vector<std::vector<std::complex<float>>> transfer;
    std::vector<double> power, overlap;
    // the sources (domain pixels) and film points (camera rows within the overscan, columns
    // within it, n x n per pixel), in radians per lattice step; a film point's 1 / (f norm^2)
    std::vector<double> sx, sy, fx, fy;
    std::vector<std::complex<float>> film_weight;
    PlacedPoints placed_sources, placed_film;  // on the transforms' grid (every thread's alike)
    int columns = 0, points = 1;  // film columns a row, points a pixel
    // per thread: its transforms and work arrays (a transform holds its grid: one at a time)
    struct Work {
        std::unique_ptr<LatticeNufft> nufft;
        std::vector<std::complex<float>> strength, field, out;
        std::vector<std::vector<std::complex<float>>> lattice;
    };
    mutable std::vector<Work> work;

    double to_step(double cosine) const { return 2 * M_PI * cosine / g.period; }

    // The field of run strengths `a` (per source, layers at once) at film points [first, last)
    // into w.out, on w's transforms.
    void field(Work& w, size_t first, size_t last) const {
        const size_t M2 = size_t(g.modes) * g.modes;
        std::vector<std::complex<float>*> out(w.lattice.size());
        for (int l = 0; l < layers; ++l) out[size_t(l)] = w.lattice[size_t(l)].data();
        w.nufft->to_lattice(placed_sources, w.strength.data(), layers, out.data());
        w.field.assign(M2, 0.0f);
        for (int l = 0; l < layers; ++l)
            for (size_t m = 0; m < M2; ++m) w.field[m] += transfer[size_t(l)][m] * w.lattice[size_t(l)][m];
        const std::complex<float>* lattice = w.field.data();
        w.out.resize(last - first);
        w.nufft->from_lattice(&lattice, 1, placed_film, first, last, film_weight.data() + first, w.out.data());
    }
};

DirectionRuns::DirectionRuns(const KernelSummationSpec& spec, int threads) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.spec = spec;
    const DirectionGeometry& g = m.g = direction_geometry(spec);
    m.threads = std::max(1, threads);
    m.layers = g.layers.count;
    const PinholeCamera& c = spec.camera;
    const double lambda = spec.wavelength, k = 2 * M_PI / lambda, f = c.film_distance;
    // H per layer: each sample on its lattice point, its curvature's phase at its own place
    const ApertureSamples samples = sample_aperture(spec.aperture, lambda / g.period);
    const int M = g.modes, centre = M / 2;
    m.transfer.assign(size_t(m.layers), std::vector<std::complex<float>>(size_t(M) * M, 0.0f));
    for (int l = 0; l < m.layers; ++l) {
        const double curvature = g.layers.inverse_depth(l) + 1 / f;
        for (size_t i = 0; i < samples.size(); ++i) {
            const double x = samples.x[i], y = samples.y[i];
            const long ix = std::lround(x / samples.pitch) + centre, iy = std::lround(y / samples.pitch) + centre;
            m.transfer[size_t(l)][size_t(iy) * M + ix] +=
                std::complex<float>(std::polar(samples.weight[i] / lambda, 0.5 * k * (x * x + y * y) * curvature));
        }
    }
    m.power.assign(size_t(m.layers), 0.0);
    m.overlap.assign(size_t(m.layers), 0.0);  // Re <H_l, H_l+1>
    for (int l = 0; l < m.layers; ++l)
        for (size_t i = 0; i < m.transfer[size_t(l)].size(); ++i) {
            const cdouble h(m.transfer[size_t(l)][i]);
            m.power[size_t(l)] += std::norm(h);
            if (l + 1 < m.layers) m.overlap[size_t(l)] += std::real(h * std::conj(cdouble(m.transfer[size_t(l + 1)][i])));
        }
    // the sources at the domain pixels' centres
    double u, v;
    for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
            c.tangent(i - g.margin + 0.5, j - g.margin + 0.5, u, v);
            m.sx.push_back(m.to_step(cosine(u, v)));
            m.sy.push_back(m.to_step(cosine(v, u)));
        }
    // the film points, row by row, as the direct sums place them (source_kernels.h); the
    // lattice's sum to the film turns by +k m . ξ: a type 2 at -m
    const int o = spec.overscan, n = spec.subsamples;
    m.columns = c.width - 2 * o;
    m.points = n * n;
    for (int cj = o; cj < c.height - o; ++cj)
        for (int ci = o; ci < c.width - o; ++ci)
            for (int sb = 0; sb < n; ++sb)
                for (int sa = 0; sa < n; ++sa) {
                    c.tangent(ci + (sa + 0.5) / n, cj + (sb + 0.5) / n, u, v);
                    const double norm2 = 1 + u * u + v * v;
                    m.fx.push_back(-m.to_step(cosine(u, v)));
                    m.fy.push_back(-m.to_step(cosine(v, u)));
                    m.film_weight.emplace_back(float(1 / (f * norm2)), 0.0f);
                }
    m.work.resize(size_t(m.threads));
    for (Impl::Work& w : m.work) {
        w.nufft = std::make_unique<LatticeNufft>(M, M, spec.settings.tolerance, 1);
        w.lattice.assign(size_t(m.layers), std::vector<std::complex<float>>(size_t(M) * M));
    }
    m.placed_sources = m.work[0].nufft->place({m.sx.data(), m.sy.data(), m.sx.size()});
    m.placed_film = m.work[0].nufft->place({m.fx.data(), m.fy.data(), m.fx.size()});
}

DirectionRuns::~DirectionRuns() = default;

const DirectionGeometry& DirectionRuns::geometry() const { return impl_->g; }

int DirectionRuns::runs_at_once() const { return impl_->threads; }

std::vector<float> DirectionRuns::power_balance(const KernelSummationSources& sources) const {
    const Impl& m = *impl_;
    std::vector<float> factor(sources.lower.size(), 1.0f);
    for (size_t p = 0; p < factor.size(); ++p) {
        const int l = sources.lower[p];
        const double s = sources.upper_share[p];
        if (s == 0 || l + 1 >= m.layers) continue;
        const double a = m.power[size_t(l)], b = m.power[size_t(l + 1)];
        const double target = (1 - s) * a + s * b;
        const double blended = (1 - s) * (1 - s) * a + s * s * b + 2 * s * (1 - s) * m.overlap[size_t(l)];
        if (blended > 0 && target > 0) factor[p] = float(std::sqrt(target / blended));
    }
    return factor;
}

Result<bool> DirectionRuns::run(const KernelSummationSources& sources, double scale, const RowRange& rows,
                                float* irradiance, const ProgressFn& progress) const {
    const Impl& m = *impl_;
    const PinholeCamera& c = m.spec.camera;
    const int o = m.spec.overscan, runs = sources.runs, L = m.layers;
    if (progress && !progress(0.0)) return cancelled();
    const int row0 = std::max(rows.begin, o), row1 = std::min(rows.end, c.height - o);
    if (row0 >= row1) return Result<bool>::success(true);
    const size_t per_row = size_t(m.columns) * m.points, first = size_t(row0 - o) * per_row,
                 last = size_t(row1 - o) * per_row, S = m.sx.size();
    std::vector<std::vector<float>> image(sources.weight.size() / S);
    parallel_for(0, m.threads, m.threads, [&](int64_t t) {
        Impl::Work& w = m.work[size_t(t)];
        for (int k = int(t); k < runs; k += m.threads) {
            // each source's weight shared between its two layers
            w.strength.assign(S * L, 0.0f);
            const std::complex<float>* weight = sources.weight.data() + size_t(k) * S;
            for (size_t s = 0; s < S; ++s) {
                const int l = sources.lower[s];
                const float up = sources.upper_share[s];
                w.strength[s * L + l] += weight[s] * (1 - up);
                if (l + 1 < L) w.strength[s * L + l + 1] += weight[s] * up;
            }
            m.field(w, first, last);
            std::vector<float>& pixels = image[size_t(k)];
            pixels.assign((last - first) / m.points, 0.0f);
            for (size_t q = 0; q < pixels.size(); ++q) {
                double sum = 0;
                for (int s = 0; s < m.points; ++s) sum += std::norm(w.out[q * m.points + s]);
                pixels[q] = float(sum / m.points);
            }
        }
    });
    // run by run, one addition per pixel (a job is the sum of its shares to the bit)
    for (int k = 0; k < runs; ++k)
        for (int cj = row0; cj < row1; ++cj)
            for (int ci = o; ci < c.width - o; ++ci) {
                const double v = scale * image[size_t(k)][size_t(cj - row0) * m.columns + ci - o];
                if (v != 0) irradiance[size_t(cj) * c.width + ci] += float(v);
            }
    if (progress && !progress(1.0)) return cancelled();
    return Result<bool>::success(true);
}

std::vector<std::complex<double>> DirectionRuns::star_field(double x, double y, double w,
                                                           const std::vector<double>& film_x,
                                                           const std::vector<double>& film_y) const {
    const Impl& m = *impl_;
    const PinholeCamera& c = m.spec.camera;
    KernelSummationSources one;
    one.weight.assign(1, 1.0f);
    int lower = 0;
    float share = 0;
    m.g.layers.locate(w, lower, share);
    one.lower.assign(1, uint8_t(lower));
    one.upper_share.assign(1, share);
    const double balance = power_balance(one)[0];
    double u, v;
    c.tangent(x, y, u, v);
    const double ax = m.to_step(cosine(u, v)), ay = m.to_step(cosine(v, u));
    const int M = m.g.modes, centre = M / 2;
    std::vector<std::complex<float>> lattice(size_t(M) * M, 0.0f);
    for (int l = lower; l <= std::min(lower + 1, m.layers - 1); ++l) {
        const double part = balance * (l == lower ? 1 - share : share);
        if (part == 0) continue;
        for (int j = 0; j < M; ++j)
            for (int i = 0; i < M; ++i)
                lattice[size_t(j) * M + i] += std::complex<float>(
                    part * cdouble(m.transfer[size_t(l)][size_t(j) * M + i]) *
                    std::polar(1.0, -((i - centre) * ax + (j - centre) * ay)));
    }
    std::vector<double> px, py;
    std::vector<std::complex<float>> weight;
    for (size_t t = 0; t < film_x.size(); ++t) {
        c.tangent(film_x[t], film_y[t], u, v);
        px.push_back(-m.to_step(cosine(u, v)));
        py.push_back(-m.to_step(cosine(v, u)));
        weight.emplace_back(float(1 / (c.film_distance * (1 + u * u + v * v))), 0.0f);
    }
    const LatticeNufft nufft(M, M, m.spec.settings.tolerance, 1);
    std::vector<std::complex<float>> out(px.size());
    const std::complex<float>* lattices = lattice.data();
    nufft.from_lattice(&lattices, 1, {px.data(), py.data(), px.size()}, weight.data(), out.data());
    return {out.begin(), out.end()};
}

}  // namespace wavecam::detail
