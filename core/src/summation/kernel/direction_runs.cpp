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

// The geometry, and the pinhole's samples on its lattice (pitch λ / period).
DirectionGeometry geometry_and_samples(const KernelSummationSpec& spec, ApertureSamples& samples) {
    const PinholeCamera& c = spec.camera;
    const double a = spec.aperture.bounding_radius(), lambda = spec.wavelength, t = c.tan_pitch();
    DirectionGeometry g;
    g.margin = margin_for(c, airy_reach(spec.aperture, lambda, kDirectionMarginLight));
    g.width = c.width + 2 * g.margin;
    g.height = c.height + 2 * g.margin;
    // the domain's widest direction cosines (on its middle row and column), and a pixel's guard
    const double su = cosine((0.5 * g.width) * t, 0), sv = cosine((0.5 * g.height) * t, 0);
    g.period = std::min(2.0, 2 * std::max(su, sv) + t);
    // a pinhole of few samples across on a lattice of kMinDirectionModes (its rim's samples sit on
    // lattice points: the finer the lattice, the nearer their own places)
    g.period *= std::max(1.0, std::ceil(kMinDirectionModes * lambda / (2 * a * g.period)));
    samples = sample_aperture(spec.aperture, lambda / g.period);
    g.period = lambda / samples.pitch;  // (refined where the opening is finer than the pitch)
    int reach = 0;
    for (size_t i = 0; i < samples.size(); ++i)
        reach = std::max({reach, int(std::lround(std::abs(samples.x[i]) / samples.pitch)),
                          int(std::lround(std::abs(samples.y[i]) / samples.pitch))});
    g.modes = 2 * (reach + 1);
    g.layers = amplitude_layers(spec.max_inverse_depth, a, lambda);
    return g;
}

}  // namespace

double airy_reach(const Aperture& aperture, double wavelength, double light) {
    return 2 * wavelength / (M_PI * M_PI * 2 * aperture.bounding_radius() * light);
}

bool runs_in_directions(const KernelSummationSpec& spec, const ComputeDevice& device) {
    const double a = spec.aperture.bounding_radius();
    return !device.gpu() && !spec.incoherent && a > 0 &&
           DepthLayers::rim_phase(spec.max_inverse_depth, a, spec.wavelength, spec.camera.film_distance) <=
               kMaxFraunhoferPhase;
}

DirectionGeometry direction_geometry(const KernelSummationSpec& spec) {
    ApertureSamples samples;
    return geometry_and_samples(spec, samples);
}

DirectionTransfer direction_transfer(const KernelSummationSpec& spec) {
    DirectionTransfer t;
    ApertureSamples samples;
    const DirectionGeometry& g = t.g = geometry_and_samples(spec, samples);
    const double lambda = spec.wavelength, k = 2 * M_PI / lambda;
    const int M = g.modes, centre = M / 2, L = g.layers.count;
    // H per layer: each sample on its lattice point, its curvature's phase at its own place
    t.h.assign(size_t(L), std::vector<std::complex<float>>(size_t(M) * M, 0.0f));
    for (int l = 0; l < L; ++l) {
        const double curvature = g.layers.inverse_depth(l) + 1 / spec.camera.film_distance;
        for (size_t i = 0; i < samples.size(); ++i) {
            const double x = samples.x[i], y = samples.y[i];
            const long ix = std::lround(x / samples.pitch) + centre, iy = std::lround(y / samples.pitch) + centre;
            t.h[size_t(l)][size_t(iy) * M + ix] +=
                std::complex<float>(std::polar(samples.weight[i] / lambda, 0.5 * k * (x * x + y * y) * curvature));
        }
    }
    t.power.assign(size_t(L), 0.0);
    t.overlap.assign(size_t(L), 0.0);
    for (int l = 0; l < L; ++l)
        for (size_t i = 0; i < t.h[size_t(l)].size(); ++i) {
            const cdouble h(t.h[size_t(l)][i]);
            t.power[size_t(l)] += std::norm(h);
            if (l + 1 < L) t.overlap[size_t(l)] += std::real(h * std::conj(cdouble(t.h[size_t(l + 1)][i])));
        }
    return t;
}

double DirectionTransfer::balance(int lower, double upper) const {
    if (upper == 0 || lower + 1 >= g.layers.count) return 1;
    const double a = power[size_t(lower)], b = power[size_t(lower + 1)];
    const double target = (1 - upper) * a + upper * b;
    const double blended = (1 - upper) * (1 - upper) * a + upper * upper * b + 2 * upper * (1 - upper) * overlap[size_t(lower)];
    return blended > 0 && target > 0 ? std::sqrt(target / blended) : 1;
}

void place_film_point(const DirectionTransfer& t, const PinholeCamera& c, double x, double y, double& px, double& py,
                      std::complex<float>& weight) {
    double u, v;
    c.tangent(x, y, u, v);
    px = -t.to_step(cosine(u, v));
    py = -t.to_step(cosine(v, u));
    weight = {float(1 / (c.film_distance * (1 + u * u + v * v))), 0.0f};
}

std::vector<std::complex<double>> star_field(const DirectionTransfer& t, const KernelSummationSpec& spec, double x,
                                             double y, double w, const std::vector<double>& film_x,
                                             const std::vector<double>& film_y) {
    const PinholeCamera& c = spec.camera;
    int lower = 0;
    float share = 0;
    t.g.layers.locate(w, lower, share);
    const double balance = t.balance(lower, share);
    double u, v;
    c.tangent(x, y, u, v);
    const double ax = t.to_step(cosine(u, v)), ay = t.to_step(cosine(v, u));
    const int M = t.g.modes, centre = M / 2;
    std::vector<std::complex<float>> lattice(size_t(M) * M, 0.0f);
    for (int l = lower; l <= std::min(lower + 1, t.g.layers.count - 1); ++l) {
        const double part = balance * (l == lower ? 1 - share : share);
        if (part == 0) continue;
        for (int j = 0; j < M; ++j)
            for (int i = 0; i < M; ++i)
                lattice[size_t(j) * M + i] += std::complex<float>(part * cdouble(t.h[size_t(l)][size_t(j) * M + i]) *
                                                                  std::polar(1.0, -((i - centre) * ax + (j - centre) * ay)));
    }
    std::vector<double> px(film_x.size()), py(film_x.size());
    std::vector<std::complex<float>> weight(film_x.size()), out(film_x.size());
    for (size_t p = 0; p < film_x.size(); ++p) place_film_point(t, c, film_x[p], film_y[p], px[p], py[p], weight[p]);
    const LatticeNufft nufft(M, M, spec.settings.tolerance, 1);
    const std::complex<float>* lattices = lattice.data();
    nufft.from_lattice(&lattices, 1, {px.data(), py.data(), px.size()}, weight.data(), out.data());
    return {out.begin(), out.end()};
}

struct DirectionRuns::Impl {
    KernelSummationSpec spec;
    DirectionTransfer transfer;
    int threads = 1;
    int layers = 1;
    // the sources (domain pixels) and film points (camera rows within the overscan, columns
    // within it, n x n per pixel), placed on the transforms' grid (every thread's alike); a film
    // point's amplitude
    PlacedPoints placed_sources, placed_film;
    std::vector<std::complex<float>> film_weight;
    int columns = 0, points = 1;  // film columns a row, points a pixel
    // per thread: its transforms and work arrays (a transform holds its grid: one at a time)
    struct Work {
        std::unique_ptr<LatticeNufft> nufft;
        std::vector<std::complex<float>> strength, field, out;
        std::vector<std::vector<std::complex<float>>> lattice;
    };
    mutable std::vector<Work> work;

    // The field of run strengths `w.strength` (per source, layers at once) at film points
    // [first, last) into w.out, on w's transforms.
    void field(Work& w, size_t first, size_t last) const {
        const size_t M2 = size_t(transfer.g.modes) * transfer.g.modes;
        std::vector<std::complex<float>*> out(w.lattice.size());
        for (int l = 0; l < layers; ++l) out[size_t(l)] = w.lattice[size_t(l)].data();
        w.nufft->to_lattice(placed_sources, w.strength.data(), layers, out.data());
        w.field.assign(M2, 0.0f);
        for (int l = 0; l < layers; ++l)
            for (size_t m = 0; m < M2; ++m) w.field[m] += transfer.h[size_t(l)][m] * w.lattice[size_t(l)][m];
        const std::complex<float>* lattice = w.field.data();
        w.out.resize(last - first);
        w.nufft->from_lattice(&lattice, 1, placed_film, first, last, film_weight.data() + first, w.out.data());
    }
};

DirectionRuns::DirectionRuns(const KernelSummationSpec& spec, int threads) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.spec = spec;
    m.transfer = direction_transfer(spec);
    const DirectionTransfer& t = m.transfer;
    const DirectionGeometry& g = t.g;
    m.threads = std::max(1, threads);
    m.layers = g.layers.count;
    const PinholeCamera& c = spec.camera;
    const int M = g.modes;
    m.work.resize(size_t(m.threads));
    for (Impl::Work& w : m.work) {
        w.nufft = std::make_unique<LatticeNufft>(M, M, spec.settings.tolerance, 1);
        w.lattice.assign(size_t(m.layers), std::vector<std::complex<float>>(size_t(M) * M));
    }
    // the sources at the domain pixels' centres
    std::vector<double> x, y;
    double u, v;
    for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
            c.tangent(i - g.margin + 0.5, j - g.margin + 0.5, u, v);
            x.push_back(t.to_step(cosine(u, v)));
            y.push_back(t.to_step(cosine(v, u)));
        }
    m.placed_sources = m.work[0].nufft->place({x.data(), y.data(), x.size()});
    // the film points, row by row, as the direct sums place them (source_kernels.h)
    const int o = spec.overscan, n = spec.subsamples;
    m.columns = c.width - 2 * o;
    m.points = n * n;
    const size_t count = size_t(m.columns) * (c.height - 2 * o) * m.points;
    x.resize(count);
    y.resize(count);
    m.film_weight.resize(count);
    size_t p = 0;
    for (int cj = o; cj < c.height - o; ++cj)
        for (int ci = o; ci < c.width - o; ++ci)
            for (int sb = 0; sb < n; ++sb)
                for (int sa = 0; sa < n; ++sa, ++p)
                    place_film_point(t, c, ci + (sa + 0.5) / n, cj + (sb + 0.5) / n, x[p], y[p], m.film_weight[p]);
    m.placed_film = m.work[0].nufft->place({x.data(), y.data(), count});
}

DirectionRuns::~DirectionRuns() = default;

const DirectionGeometry& DirectionRuns::geometry() const { return impl_->transfer.g; }

int DirectionRuns::runs_at_once() const { return impl_->threads; }

std::vector<float> DirectionRuns::power_balance(const KernelSummationSources& sources) const {
    std::vector<float> factor(sources.lower.size());
    for (size_t p = 0; p < factor.size(); ++p)
        factor[p] = float(impl_->transfer.balance(sources.lower[p], sources.upper_share[p]));
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
                 last = size_t(row1 - o) * per_row, S = m.placed_sources.count;
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

}  // namespace wavecam::detail
