#include "summation/kernel/kernel_error_check.h"


#include <algorithm>
#include <array>
#include <mutex>

#include "base/parallel.h"
#include "summation/kernel/direction_runs.h"
#include "summation/kernel/source_kernels.h"

namespace wavecam::detail {
namespace {

using Field = std::vector<std::complex<double>>;

// A kernel's pixel image: per pixel, the mean of |K|^2 over its `points` film points.
std::vector<double> pixel_image(const Field& k, int points) {
    const size_t pixels = k.size() / size_t(points);
    std::vector<double> image(pixels, 0.0);
    for (int sub = 0; sub < points; ++sub)
        for (size_t t = 0; t < pixels; ++t) image[t] += std::norm(k[size_t(sub) * pixels + t]) / points;
    return image;
}

double power(const Field& k) {
    double p = 0;
    for (const auto& v : k) p += std::norm(v);
    return p;
}

// The blend of `parts` with `share`s as the runs' mean takes it (kernel_summation.h, the blend's
// mean): their pixel images blended (anchors; a layer pair of the incoherent sums), or their
// amplitudes blended with the power balanced (a layer pair of coherent runs); against `exact`:
// relative L2 of the pixel images.
double blend_error(const std::vector<const Field*>& parts, const std::vector<double>& share, const Field& exact,
                   int points, bool amplitudes) {
    std::vector<double> blended;
    if (!amplitudes) {
        for (size_t i = 0; i < parts.size(); ++i) {
            const std::vector<double> image = pixel_image(*parts[i], points);
            blended.resize(image.size(), 0.0);
            for (size_t t = 0; t < image.size(); ++t) blended[t] += share[i] * image[t];
        }
    } else {
        Field sum(exact.size(), 0.0);
        double target = 0;
        for (size_t i = 0; i < parts.size(); ++i) {
            for (size_t t = 0; t < sum.size(); ++t) sum[t] += share[i] * (*parts[i])[t];
            target += share[i] * power(*parts[i]);
        }
        const double p = power(sum), scale = p > 0 ? std::sqrt(target / p) : 0.0;
        for (auto& v : sum) v *= scale;
        blended = pixel_image(sum, points);
    }
    const std::vector<double> truth = pixel_image(exact, points);
    double e = 0, r = 0;
    for (size_t t = 0; t < truth.size(); ++t) {
        e += (blended[t] - truth[t]) * (blended[t] - truth[t]);
        r += truth[t] * truth[t];
    }
    return r > 0 ? std::sqrt(e / r) : 0.0;
}

// A probe source: domain pixel (x, y), at `depths` (inverse depths).
struct Probe {
    int x, y;
    std::vector<double> depths;
};

// The probe cells (x cell, y cell): on the axis, the outermost on the horizontal axis, the
// outermost corner.
using ProbeCells = std::array<std::array<int, 2>, 3>;

// Every source the probes need: a cell's corners and centre at the nearest layer, the axis cell's
// centre also at the two nearest layers' middle (axis_x, axis_y: the axis cell).
std::vector<Probe> place_probes(const KernelSummationGeometry& g, const ProbeCells& cells, int axis_x, int axis_y) {
    const int L = g.layers.count;
    const double nearest = g.layers.inverse_depth(L - 1);
    std::vector<Probe> probes;
    const auto centre = [&](const AnchorAxis& a, int cell) { return (a.knots[cell] + a.knots[cell + 1]) / 2; };
    for (const auto& cell : cells) {
        const int cx = std::min(cell[0], int(g.ax.knots.size()) - 2), cy = std::min(cell[1], int(g.ay.knots.size()) - 2);
        if (cx < 0 || cy < 0) continue;  // one knot along an axis: no cell, nothing blended
        for (int corner = 0; corner < 4; ++corner)
            probes.push_back({g.ax.knots[cx + (corner & 1)], g.ay.knots[cy + (corner >> 1)], {nearest}});
        probes.push_back({centre(g.ax, cx), centre(g.ay, cy), {nearest}});
    }
    const bool layered = L > 1;
    if (layered && g.ax.knots.size() > 1 && g.ay.knots.size() > 1) {
        const double below = g.layers.inverse_depth(L - 2);
        probes.push_back({g.ax.knots[axis_x], g.ay.knots[axis_y], {below, 0.5 * (below + nearest), nearest}});
    }
    return probes;
}

// The probes' exact kernels, probe by probe into `fields`: the first fixes the film sums'
// evaluator (`kernel_settings`), the others follow, one per thread on the CPU.
Result<bool> probe_kernels(const KernelSummationSpec& spec, const KernelSetup& setup,
                           const SummationSettings& kernel_settings, const std::vector<Probe>& probes,
                           std::vector<std::vector<Field>>& fields) {
    const KernelSummationGeometry& g = *setup.g;
    PlanScope film_scope;
    if (auto r = source_kernels(setup, probes[0].x - g.origin, probes[0].y - g.origin, probes[0].depths,
                                kernel_settings, film_scope, fields[0]);
        !r.ok())
        return r;
    const bool on_cpu = !setup.device->gpu();
    SummationSettings one_thread = kernel_settings;
    one_thread.nthreads = on_cpu ? 1 : spec.settings.nthreads;
    const int threads = thread_count(spec.settings.nthreads);
    Result<bool> failed = Result<bool>::success(true);
    std::mutex failure;
    parallel_for_dynamic(1, probes.size(), 1, on_cpu ? threads : 1, [&](int64_t i_) {
        const size_t i = size_t(i_);
        PlanScope scope = film_scope;
        auto r = source_kernels(setup, probes[i].x - g.origin, probes[i].y - g.origin, probes[i].depths, one_thread,
                                scope, fields[i]);
        if (!r.ok()) {
            std::lock_guard<std::mutex> lock(failure);
            failed = r;
        }
    });
    return failed;
}

// The probes' blend errors into `check`: the cells' blends, bilinear at their centres, then the
// layers' where there is one.
void check_blends(const KernelSummationGeometry& g, const ProbeCells& cells, const std::vector<Probe>& probes,
                  const std::vector<std::vector<Field>>& fields, int points, bool incoherent, KernelErrorCheck& check) {
    size_t at = 0;
    for (const auto& cell : cells) {
        const int cx = std::min(cell[0], int(g.ax.knots.size()) - 2), cy = std::min(cell[1], int(g.ay.knots.size()) - 2);
        if (cx < 0 || cy < 0) continue;
        const double tx = double(probes[at + 4].x - g.ax.knots[cx]) / (g.ax.knots[cx + 1] - g.ax.knots[cx]);
        const double ty = double(probes[at + 4].y - g.ay.knots[cy]) / (g.ay.knots[cy + 1] - g.ay.knots[cy]);
        const std::vector<const Field*> parts{&fields[at][0], &fields[at + 1][0], &fields[at + 2][0],
                                              &fields[at + 3][0]};
        const std::vector<double> share{(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
        const double e = blend_error(parts, share, fields[at + 4][0], points, false);
        check.probes.push_back({probes[at + 4].x - g.origin, probes[at + 4].y - g.origin, false, e});
        check.blend = std::max(check.blend, e);
        at += 5;
    }
    if (at < probes.size()) {
        const std::vector<Field>& f = fields[at];
        const double e = blend_error({&f[0], &f[2]}, {0.5, 0.5}, f[1], points, !incoherent);
        check.probes.push_back({probes[at].x - g.origin, probes[at].y - g.origin, true, e});
        check.blend = std::max(check.blend, e);
    }
}

// The runs in directions (direction_runs.h): probe stars at the nearest source's depth on the
// axis, at the middle of the frame's left edge and at its corner (the widest field, where the
// curvature the runs drop is largest), and on the axis midway between the two nearest layers
// (their amplitudes' blend), each the runs' own field against the point sums' kernel there,
// over the window of the light the Airy pattern holds within 97% (an anchor kernel's share).
Result<KernelErrorCheck> check_direction_runs(const KernelSummationSpec& spec, const KernelSetup& setup,
                                              const SummationSettings& to_film) {
    using R = Result<KernelErrorCheck>;
    const PinholeCamera& c = spec.camera;
    const DirectionTransfer transfer = direction_transfer(spec);
    const DepthLayers& layers = transfer.g.layers;
    // a window that holds about 97% of a star's light (the Airy pattern's 2 λ / (π^2 D r) beyond r),
    // in the pixels of the frame's corner, where the field makes them smallest in direction
    double u, v;
    c.tangent(0, 0, u, v);
    const double corner = c.tan_pitch() * (1 + v * v) / std::pow(1 + u * u + v * v, 1.5);
    const double reach = airy_reach(spec.aperture, spec.wavelength, 1 - kPsfKernelEnergy);
    const int o = spec.overscan, n = spec.subsamples;
    const int radius = std::min(setup.g->radius, int(std::ceil(reach / corner)));
    std::vector<Probe> probes{{c.width / 2, c.height / 2, {spec.max_inverse_depth}},
                              {o, c.height / 2, {spec.max_inverse_depth}},
                              {o, o, {spec.max_inverse_depth}}};
    const bool layer_probe = layers.count > 1;  // (the last)
    if (layer_probe) {
        const int L = layers.count;
        probes.push_back({c.width / 2, c.height / 2,
                          {0.5 * (layers.inverse_depth(L - 2) + layers.inverse_depth(L - 1))}});
    }
    std::vector<std::vector<Field>> fields(probes.size());
    KernelSetup shifted = setup;  // (probe_kernels counts in domain pixels)
    KernelSummationGeometry g = *setup.g;
    g.origin = 0;
    g.radius = radius;
    shifted.g = &g;
    if (auto r = probe_kernels(spec, shifted, to_film, probes, fields); !r.ok()) return R::failure(r);
    KernelErrorCheck check;
    for (size_t i = 0; i < probes.size(); ++i) {
        const Probe& p = probes[i];
        std::vector<double> fx, fy;  // the probe kernel's film points, as source_kernels orders them
        for (int sb = 0; sb < n; ++sb)
            for (int sa = 0; sa < n; ++sa)
                for (int dy = -radius; dy <= radius; ++dy)
                    for (int dx = -radius; dx <= radius; ++dx) {
                        fx.push_back(p.x + dx + (sa + 0.5) / n);
                        fy.push_back(p.y + dy + (sb + 0.5) / n);
                    }
        const Field star = star_field(transfer, spec, p.x + 0.5, p.y + 0.5, p.depths[0], fx, fy);
        const double e = blend_error({&star}, {1.0}, fields[i][0], n * n, false);
        check.probes.push_back({p.x, p.y, layer_probe && i + 1 == probes.size(), e});
        check.blend = std::max(check.blend, e);
    }
    return R::success(check);
}

}  // namespace

Result<KernelErrorCheck> check_kernel_error(const ComputeDevice& device, const KernelSummationSpec& spec,
                                            double lattice_pitch, const UnitSource& unit) {
    using R = Result<KernelErrorCheck>;
    const KernelSummationGeometry g = kernel_summation_geometry(spec);
    KernelErrorCheck check;
    const PinholeCamera& c = spec.camera;
    if (!spec.incoherent && airy_spans_a_pixel(spec) && !runs_in_directions(spec, device))
        check.tail = 0.8 * std::sqrt((1 - kernel_energy(spec)) / std::max(1, spec.runs));
    const KernelSums sums = kernel_sums(spec, g);
    const ApertureSamples samples = sample_aperture(spec.aperture, lattice_pitch);
    const KernelSetup setup{&spec, &g, &samples, sums.to_pinhole, unit, &device};
    if (runs_in_directions(spec, device)) return check_direction_runs(spec, setup, sums.to_film);
    const int points = spec.subsamples * spec.subsamples;
    const int axis_x = g.ax.cell_of(g.origin + c.width / 2);
    const int axis_y = g.ay.cell_of(g.origin + c.height / 2);
    const ProbeCells cells{{{axis_x, axis_y}, {0, axis_y}, {0, 0}}};
    const std::vector<Probe> probes = place_probes(g, cells, axis_x, axis_y);
    std::vector<std::vector<Field>> fields(probes.size());
    if (probes.empty()) return R::success(check);
    if (auto r = probe_kernels(spec, setup, sums.to_film, probes, fields); !r.ok()) return R::failure(r);
    check_blends(g, cells, probes, fields, points, spec.incoherent, check);
    return R::success(check);
}

}  // namespace wavecam::detail
