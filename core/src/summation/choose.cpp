// The one chooser (choose.h): the point sums' cost model, the kernel summation's cost and memory,
// the devices, and the frame's choice between them.
#include "summation/choose.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/parallel.h"
#include "convolution/kernel_table.h"
#include "summation/nufft/chirp_interpolation.h"
#include "summation/kernel/direction_runs.h"
#include "summation/kernel/gpu_run_cost.h"
#include "summation/kernel/kernel_summation_geometry.h"
#include "summation/nufft/lattice_nufft.h"
#include "summation/nufft/stencil_choice.h"
#include "summation/summation_evaluator.h"

namespace wavecam {

SumChoice choose_sum(const SumCounts& counts, Summation asked, bool on_gpu) {
    // the lowest estimate among the rows that serve `asked` on the device (the CPU's where the
    // device has none: such a plan is refused when it commits, choose_plan_sum)
    using detail::kEvaluators;
    const Device device = on_gpu ? Device::Gpu : Device::Cpu;
    bool on_device = false;
    for (const detail::EvaluatorRow& row : kEvaluators)
        on_device = on_device || (row.estimate_sum && detail::serves(row, asked, device));
    SumChoice best;
    bool found = false;
    double direct = NAN, nufft = NAN;
    for (const detail::EvaluatorRow& row : kEvaluators) {
        if (!row.estimate_sum || !detail::serves(row, asked, on_device ? device : Device::Cpu)) continue;
        const SumChoice e = row.estimate_sum(counts, asked == Summation::Auto);
        (e.evaluator == Evaluator::Direct ? direct : nufft) = e.work;
        if (!found || e.work < best.work) best = e;
        found = true;
    }
    // both evaluators' work where both were weighed (the reasons quote the other's)
    best.direct_work = std::isnan(direct) ? best.direct_work : direct;
    best.nufft_work = std::isnan(nufft) ? best.direct_work : nufft;
    return best;
}

namespace detail {
namespace {

// What a sum pairs: its samples on the lattice and off it, and its points (as SumCounts).
struct SumTerms {
    double lattice_samples, off_lattice, points;
};

// A disc of radius a on a lattice of n cells across, pitch h.
struct DiscLattice {
    int n;
    double a, h;
};

// The nufft evaluator's work for one division into sub-apertures (`discs`, each of bnx x bny
// cells): per sub-aperture and skeleton node an FFT and a lattice of chirps; per point and
// sub-aperture its frequency and phase, its skeleton coefficients and each skeleton node's kernel
// taps; the off-lattice samples direct. Skeleton ranks from the probed sub-apertures. The tiling
// spends `budget` (the chirp's evaluations); where it runs out, the work is infinite.
SumChoice division_work(const ChirpGeometry& geo, const DirectionRange& range, const std::vector<ProbeDisc>& discs,
                        int bnx, int bny, const SumTerms& terms, double& budget) {
    const double lattice_samples = terms.lattice_samples, off_lattice = terms.off_lattice, points = terms.points;
    SumChoice w;
    double tiling = 0;
    const std::vector<ChebyshevBox> boxes = geo.tiling(range, discs, &tiling, budget);
    budget -= tiling;
    if (boxes.empty()) {
        w.nufft_work = INFINITY;
        return w;
    }
    const std::vector<ProbeDisc> probed = probe_discs(discs);
    const LatticeNufft nufft(bnx, bny, geo.tolerance, 1);
    const double parts = double(discs.size()), dims = geo.dims();
    // each point meets one box (in proportion to its volume): its skeleton's taps and coefficients
    double transforms = 0, point_work = 0, volume = 0;
    for (const ChebyshevBox& b : boxes) {
        double v = 1, rank = 0;
        for (int d = 0; d < b.dims; ++d) v *= std::max(b.hi[d] - b.lo[d], 1e-12);
        for (const ProbeDisc& d : probed) rank += box_skeleton(geo, b, d).rank();
        rank /= double(probed.size());
        volume += v;
        point_work += v * (rank * kTapCost * nufft.taps_per_point() + b.rank() * (rank + dims) * kMacCost);
        transforms += rank;
    }
    w.nufft_count = int(std::lround(transforms * parts));
    w.nufft_work = transforms * (parts * kFftCost * nufft.fft_work() + kChirpCost * lattice_samples) +
                   points * parts * (point_work / volume + 2 * kChirpCost) + off_lattice * points +
                   tiling * kTilingProbeCost;
    return w;
}

// Sub-apertures of a disc of radius a on a lattice of n cells across, pitch h: those whose square
// meets the disc, reaching half their diagonal and a cell.
std::vector<ProbeDisc> disc_division(int n, double a, double h, int blocks) {
    std::vector<ProbeDisc> d;
    const int bn = (n + blocks - 1) / blocks;
    const double side = bn * h;
    for (int by = 0; by < blocks; ++by)
        for (int bx = 0; bx < blocks; ++bx) {
            const double x0 = -a - 0.5 * h + bx * side, y0 = -a - 0.5 * h + by * side;
            const double nxp = std::clamp(0.0, x0, x0 + side), nyp = std::clamp(0.0, y0, y0 + side);
            if (std::hypot(nxp, nyp) > a) continue;
            // reach: the farthest of a 9 x 9 grid over the square that lies in the disc
            const double cx = x0 + 0.5 * side, cy = y0 + 0.5 * side;
            double reach = 0;
            for (int j = 0; j <= 8; ++j)
                for (int i = 0; i <= 8; ++i) {
                    const double x = x0 + side * i / 8, y = y0 + side * j / 8;
                    if (std::hypot(x, y) <= a + h) reach = std::max(reach, std::hypot(x - cx, y - cy));
                }
            d.push_back({cx, cy, reach + h});
        }
    return d;
}

// The cheapest division (blocks per side): 1, 2, 4, ... while the work falls.
SumChoice cheapest_division(const ChirpGeometry& geo, const DirectionRange& range, const DiscLattice& disc,
                            const SumTerms& terms, double& budget) {
    const int n = disc.n;
    const double a = disc.a, h = disc.h;
    SumChoice best;
    for (int blocks = 1; blocks <= kMaxBlocks; blocks *= 2) {
        const int bn = (n + blocks - 1) / blocks;
        if (blocks > 1 && bn < kMinCellsAcross) break;
        SumChoice w = division_work(geo, range, disc_division(n, a, h, blocks), bn, bn, terms, budget);
        w.blocks = blocks;
        if (blocks > 1 && w.nufft_work >= best.nufft_work) break;
        best = w;
    }
    return best;
}

}  // namespace

SumChoice sum_work(const SumCounts& c, bool bounded) {
    const double direct = (c.lattice_samples + c.off_lattice) * c.points;
    // the chirp's tiling runs on one thread, the direct terms on every core: where it would
    // cost a quarter of the direct terms' work, tiling stops and the direct terms are taken
    // (at 120 deg a 32 px frame's tiling took more than ten minutes, its direct terms four)
    double budget = bounded ? direct / (4 * kTilingProbeCost) : INFINITY;
    if (c.lattice_samples <= 0 || c.samples_across < 1) {
        SumChoice w;
        w.direct_work = w.nufft_work = direct;
        return w;
    }
    const int n = c.samples_across;
    const double a = c.aperture_radius, h = 2 * a / std::max(1, n - 1);
    const DirectionRange& range = c.range;
    // off-lattice samples through the stencil where the band allows: their stencils' cells join
    // the lattice (about one row of `width` per rim sample), their spreading costs little; points
    // beyond its reach (as a share of the range's area) take them directly, with transforms of
    // their own
    const StencilChoice sc =
        choose_stencil(range, 2 * M_PI / c.wavelength, h, {c.lattice_samples, c.off_lattice, a}, c.tolerance);
    const double width = sc.stencil.width();
    double outside = 1;
    if (sc.inner > 0) {
        const double sx = std::max(std::fabs(range.ux0), std::fabs(range.ux1)),
                     sy = std::max(std::fabs(range.uy0), std::fabs(range.uy1));
        outside = 1 - std::min(1.0, sc.inner / std::max(sx, 1e-12)) * std::min(1.0, sc.inner / std::max(sy, 1e-12));
    }
    // the rim direct for every point, or the stencil (with the split) where it is cheaper
    const ChirpGeometry geo = chirp_geometry(c.film, c.wavelength, c.tolerance, range);
    const DiscLattice disc{n, a, h};
    SumChoice f = cheapest_division(geo, range, disc, {c.lattice_samples, c.off_lattice, c.points}, budget);
    f.stencil = false;
    if (sc.inner > 0) {
        SumChoice s = cheapest_division(geo, range, disc,
                                        {c.lattice_samples + c.off_lattice * width, 0.0, (1 - outside) * c.points}, budget);
        s.nufft_work += c.off_lattice * width * width * kMacCost;
        if (outside > 0) {
            const SumChoice o =
                cheapest_division(geo, range, disc, {c.lattice_samples, c.off_lattice, outside * c.points}, budget);
            s.nufft_work += o.nufft_work;
            s.nufft_count += o.nufft_count;
        }
        s.stencil = true;
        if (s.nufft_work < f.nufft_work) f = s;
    }
    f.direct_work = direct;
    return f;
}


SumChoice direct_sum_work(const SumCounts& c, bool) {
    SumChoice w;
    w.evaluator = Evaluator::Direct;
    w.work = w.direct_work = w.nufft_work = (c.lattice_samples + c.off_lattice) * c.points;
    return w;
}

SumChoice nufft_sum_work(const SumCounts& c, bool bounded) {
    SumChoice w = sum_work(c, bounded);
    w.evaluator = Evaluator::Nufft;
    w.work = w.nufft_work;
    return w;
}

KernelSums kernel_sums(const KernelSummationSpec& spec, const KernelSummationGeometry& g) {
    KernelSums k;
    k.to_pinhole = k.to_film = spec.settings;
    k.to_pinhole.summation = Summation::Direct;
    // the anchors span the frame and its margin, R beyond the output frame
    const PinholeCamera& c = spec.camera;
    const int o = spec.overscan, r = g.radius;
    if (c.cos_widest(o - r, o - r, c.width - o + r, c.height - o + r) < std::cos(kMaxNufftKernelField))
        k.to_film.summation = Summation::Direct;
    return k;
}

namespace {

// The runs in directions (direction_runs.h): per run a type 1 from every domain pixel per layer
// and a type 2 to the film points, their transforms and the layers' products; nothing to sum
// beforehand but the transfer (a pass over the pinhole's samples).
KernelSummationWork direction_runs_work(const KernelSummationSpec& spec) {
    const DirectionGeometry g = direction_geometry(spec);
    const LatticeNufft nufft(g.modes, g.modes, spec.settings.tolerance, 1);
    const PinholeCamera& c = spec.camera;
    const int o = spec.overscan;
    const double sources = double(g.width) * g.height, layers = g.layers.count;
    const double film = double(c.width - 2 * o) * (c.height - 2 * o) * spec.subsamples * spec.subsamples;
    KernelSummationWork w;
    w.per_run = (sources * layers + film) * nufft.taps_per_point() * kTapCost +
                (layers + 1) * nufft.fft_work() * kFftCost + layers * double(g.modes) * g.modes * kMacCost;
    return w;
}

// What the runs in directions hold at once: the sources' places and a batch's weights, the film
// points, and per thread its transforms' grids and lattices and a run's image.
double direction_runs_bytes(const KernelSummationSpec& spec) {
    const DirectionGeometry g = direction_geometry(spec);
    const LatticeNufft nufft(g.modes, g.modes, spec.settings.tolerance, 1);
    const PinholeCamera& c = spec.camera;
    const int o = spec.overscan, threads = thread_count(spec.settings.nthreads);
    const double sources = double(g.width) * g.height, layers = g.layers.count;
    const double pixels = double(c.width - 2 * o) * (c.height - 2 * o), film = pixels * spec.subsamples * spec.subsamples;
    const double grid = double(nufft.grid_x() + nufft.kernel_width()) * nufft.grid_y();
    const double lattice = double(g.modes) * g.modes;
    return sources * (16 + 5 + 8 * threads) + film * 24 + layers * lattice * 8 +
           threads * (8 * (grid * layers + lattice * (layers + 1) + sources * layers + film) + 4 * pixels);
}

}  // namespace

KernelSummationWork kernel_summation_work(const KernelSummationSpec& spec, SumCounts in, SumCounts out,
                                          const ComputeDevice& device) {
    if (runs_in_directions(spec, device)) return direction_runs_work(spec);
    const KernelSummationGeometry g = kernel_summation_geometry(spec);
    const double side = 2.0 * g.radius + 1, S = double(spec.subsamples) * spec.subsamples;
    const int layers = std::min(g.layers.count, kMaxKernelLayers + 1);
    const double kernels = double(g.anchors()) * layers;
    // the kernels summed: one of each mirror pair (kernel_summation_kernels.cpp), a quarter of the
    // anchors for a circle or a square, about an eighth on a square frame (kernel_sources)
    const double computed = double(kernel_sources(spec, g).count()) * layers;
    in.points = 1;
    out.points = side * side * S;
    const double N = double(g.nx) * g.ny, transform = kFftCost * N * std::log2(N);
    const KernelSums sums = kernel_sums(spec, g);
    KernelSummationWork w;
    w.kernels = computed * (choose_sum(in, sums.to_pinhole.summation).work +
                            choose_sum(out, sums.to_film.summation, device.gpu()).work + S * transform);
    // a run's transforms and products, at what they cost where they run: on a GPU its
    // power-of-two transforms, each kernel a dispatch (gpu_run_cost.h)
    const double n = device.gpu() ? double(gpu_transform_side(g.width)) * gpu_transform_side(g.height) : N;
    const double run_transform = kFftCost * n * std::log2(n);
    w.per_run = gpu_run_cost(device).of(kernels * run_transform + (kernels + 1) * S * n * kMacCost + S * run_transform,
                                        kernels);
    return w;
}

double kernel_summation_bytes(const KernelSummationSpec& spec, const ComputeDevice& device) {
    if (runs_in_directions(spec, device)) return direction_runs_bytes(spec);
    const KernelSummationGeometry g = kernel_summation_geometry(spec);
    const double N = double(g.nx) * g.ny, S = double(spec.subsamples) * spec.subsamples;
    const double kernels = double(g.anchors()) * std::min(g.layers.count, kMaxKernelLayers + 1);
    const double complex_float = 8;
    // (upper bounds: the basis holds at most every kernel) spectra, and the runs at once' images,
    // sums and film (runs_at_once: within the spectra's size, one run at least)
    const double spectra = complex_float * N * kernels * S, run = N * (complex_float * (kernels + S) + sizeof(double));
    // coherent runs: each kernel's pixel image and those of its differences with its 27
    // neighbours, floats (the blend's mean, kernel_summation.h)
    const double side = 2.0 * g.radius + 1, images = spec.incoherent ? 0 : sizeof(float) * kernels * 28 * side * side;
    return spectra + images + std::max(run, std::min(spectra, kMaxRunsAtOnce * run));
}

namespace {

// The refusal of a summation that has no GPU evaluator on a GPU device (`setting` gpu, or auto
// that found one), naming those that have one (the evaluators' table).
std::string no_gpu_evaluator(Summation asked, Device setting) {
    std::string on_gpu;
    for (const EvaluatorRow& row : kEvaluators)
        if (row.device == Device::Gpu) on_gpu += std::string(row.word) + ", ";
    return std::string("device ") + device_word(setting) + ": the " + summation_word(asked) +
           " summation has no GPU evaluator; expected summation " + on_gpu.substr(0, on_gpu.size() - 2) +
           " or auto, or device " + (setting == Device::Gpu ? "auto or cpu" : "cpu");
}

// Whether the evaluator `asked` runs on a GPU (auto: what the device runs).
bool runs_on_gpu(Summation asked) {
    for (const EvaluatorRow& row : kEvaluators)
        if (serves(row, asked, Device::Gpu)) return true;
    return false;
}

}  // namespace

}  // namespace detail

DeviceChoice choose_device(Summation asked, Device setting) {
    DeviceChoice d;
    d.open = setting;
    if (setting == Device::Cpu || detail::runs_on_gpu(asked)) return d;
    if (setting == Device::Gpu) {
        d.refusal = detail::no_gpu_evaluator(asked, setting);
    } else {
        d.open = Device::Cpu;
        d.on_cpu = std::string("not used: the ") + summation_word(asked) + " summation has no GPU evaluator";
    }
    return d;
}

namespace detail {

Result<SumChoice> choose_plan_sum(const PlanSumQuery& q, const ComputeDevice& device) {
    using R = Result<SumChoice>;
    if (!device.ok()) return R::failure("device gpu: " + device.error(), ErrorKind::Failed, "device");
    const bool empty = q.empty;
    SumChoice c = q.fixed    ? *q.fixed
                  : empty    ? choose_sum(SumCounts{}, Summation::Direct)
                             : choose_sum(*q.counts, q.asked, device.gpu());
    // a GPU runs the evaluators whose rows say so (auto takes the direct terms there, choose_sum)
    const Summation runs = summation_of(c.evaluator);
    if (device.gpu() && !empty && !runs_on_gpu(runs))
        return R::failure(no_gpu_evaluator(runs, device.setting()), ErrorKind::Invalid, "summation");
    c.gpu = device.gpu() && !empty;
    return R::success(c);
}

Result<bool> kernel_runs_off_device(const ComputeDevice& device, const std::string& why, ErrorKind kind) {
    if (device.setting() == Device::Gpu) return Result<bool>::failure("device gpu: " + why, kind, "device");
    return Result<bool>::success(true);  // auto: the runs on the CPU (the device notes both)
}

namespace {

// An estimate in words: seconds at the measured rate, or direct terms without one.
std::string amount(double work, double rate) {
    char s[48];
    if (rate > 0) std::snprintf(s, sizeof s, "%.2g s", work / rate);
    else std::snprintf(s, sizeof s, "%.3g terms", work);
    return s;
}

// The point sums' evaluators in words, as the header names them (summation_plan.h).
std::string point_sum_words(const SumChoice& in, const SumChoice& out) {
    EvaluatorSet e;
    e.add(false, in.evaluator);
    e.add(true, out.evaluator);
    return e.words();
}

}  // namespace

Summation point_sum_asked(Summation asked, bool single) {
    return single && asked == Summation::Nufft ? Summation::Auto : asked;
}

SummationChoice choose_summation(const FrameSums& f, const ComputeDevice& device, const ChoiceSettings& cs) {
    const bool gpu = device.gpu();
    SummationChoice c;
    c.gpu = gpu;
    const double rate = cs.term_rate;
    // the point sums, each the cheaper where auto (direct on a GPU)
    double points = 0, all_direct = 0, all_nufft = 0;
    if (cs.asked != Summation::Kernel) {
        const Summation asked = point_sum_asked(cs.asked, f.single);
        // the job's decision where it holds one (read, not made again), else the chooser's
        c.in = cs.decided_in ? *cs.decided_in : choose_sum(f.in, asked, gpu);
        c.out = cs.decided_out ? *cs.decided_out : choose_sum(f.out, asked, gpu);
        points = (c.in.work + c.out.work * f.film_share) * f.repeats;
        all_direct = (c.in.direct_work + c.out.direct_work * f.film_share) * f.repeats;
        all_nufft = (c.in.nufft_work + c.out.nufft_work * f.film_share) * f.repeats;
    }
    // the kernel summation: its kernels, then every run
    if (f.kernel_counted) c.kernel = kernel_summation_work(f.kernel, f.kernel_in, f.kernel_out, device);
    // (the kernel row on the device: its estimate, the table's)
    const double kernel = f.kernel_counted ? evaluator_row(Summation::Kernel, gpu ? Device::Gpu : Device::Cpu).estimate(f, device, cs) : 0;
    const bool weighed = cs.asked == Summation::Auto && cs.weigh_kernel && f.kernel_applies && f.kernel_counted;
    const bool take_kernel = cs.asked == Summation::Kernel || (weighed && kernel < points);
    const std::string words = point_sum_words(c.in, c.out);
    if (take_kernel) {
        c.summation = Summation::Kernel;
        c.work = kernel;
        c.bytes = kernel_summation_bytes(f.kernel, device);
    } else {
        c.summation = c.in.evaluator != c.out.evaluator ? Summation::Auto
                      : c.in.evaluator == Evaluator::Nufft ? Summation::Nufft
                                                           : Summation::Direct;
        c.work = points;
    }
    c.seconds = rate > 0 ? c.work / rate : 0;
    const std::string on = gpu ? " on the GPU" : "";
    if (cs.asked != Summation::Auto) {
        c.reason = std::string(take_kernel ? "kernel" : words) + on + ": asked, " + amount(c.work, rate) + " estimated";
    } else if (weighed) {
        c.reason = take_kernel ? "kernel" + on + ": " + amount(kernel, rate) + " estimated against " + words + " " +
                                  amount(points, rate)
                            : words + on + ": " + amount(points, rate) + " estimated against kernel " + amount(kernel, rate);
    } else if (gpu) {
        c.reason = "direct on the GPU (its one evaluator of the point sums): " + amount(points, rate) + " estimated";
    } else {
        const bool nufft = c.summation == Summation::Nufft;
        c.reason = words + ": " + amount(points, rate) + " estimated against " + (nufft ? "direct " : "nufft ") +
                   amount(nufft ? all_direct : all_nufft, rate);
    }
    return c;
}

double kernel_cost(const FrameSums& f, const ComputeDevice& device, const ChoiceSettings&) {
    if (!f.kernel_counted) return INFINITY;
    const KernelSummationWork w = kernel_summation_work(f.kernel, f.kernel_in, f.kernel_out, device);
    return w.kernels + w.per_run * f.kernel_runs;
}

}  // namespace detail
}  // namespace wavecam
