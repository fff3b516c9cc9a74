// Which evaluator and which device run the scene-sum methods' sums, and what each costs: every cost
// model, memory model and tuning constant that decides between the evaluators (direct, nufft,
// kernel) and between the devices, in one place, as FINUFFT keeps its choices in heuristics.hpp.
// The evaluators' own physics (the kernel summation's layers and anchors, the NUFFT's kernel) stays
// with them; what only decides WHICH of them runs, and where, is here. Internal to core.
//
// Costs are in direct terms: the time of one term of the direct kernel (propagation.cpp), so
// that --max-terms and the time printed mean the same whatever runs; seconds are terms over the
// term rate measured here (term_rate.h).
#pragma once
#include <cmath>
#include <string>

#include "summation/kernel/kernel_summation.h"
#include "summation/kernel/kernel_summation_geometry.h"
#include "wavecam/summation_plan.h"

namespace wavecam::detail {

// ---- the nufft evaluator's cost, against the direct terms ----

// Cost of the nufft evaluator's parts in direct terms (one term of propagation.cpp's kernel, 1.5 ns
// on 2 cores), measured on a 620 x 620 lattice with 400k points in scan order: an FFT point x log2
// 2.0 ns, a kernel tap 4.3 ns (with the point's weights and phase), a chirp 22 ns (double sqrt and
// sincos). The ratios, not the times, are what the estimate uses.
constexpr double kFftCost = 1.33, kTapCost = 2.9, kChirpCost = 15.0;
// A complex multiply-add in double, a third of a term.
constexpr double kMacCost = 0.35;
// One evaluation of the chirp's remainder while the boxes are tiled (ChirpGeometry::tiling): the
// chirp at the box's parameter and at the probe point, two chirps. The tiling is a fixed cost
// per sum: nothing beside a frame's millions of points, but all of a kernel summation's kernel's sum where its
// chirp needs many boxes (kMaxNufftKernelField).
constexpr double kTilingProbeCost = 2 * kChirpCost;

// Sub-apertures per side tried: 1, 2, 4, ... while each keeps at least kMinCellsAcross cells across
// and the work falls.
constexpr int kMinCellsAcross = 24;
constexpr int kMaxBlocks = 16;

// Both evaluators' work for one sum's `counts` (SumChoice's direct_work, nufft_work, blocks,
// stencil, nufft_count; `evaluator` and `work` left for choose_sum, summation_plan.h). `bounded`
// (auto's estimate): the chirp's tiling stops at a quarter of the direct terms' work, the nufft
// work then infinite; an asked nufft is tiled to the end.
SumChoice sum_work(const SumCounts& counts, bool bounded);

// The evaluators' estimates of one sum (the table's estimate_sum column): the direct terms, and
// the nufft evaluator's work (sum_work) with it chosen.
SumChoice direct_sum_work(const SumCounts& counts, bool bounded);
SumChoice nufft_sum_work(const SumCounts& counts, bool bounded);

// ---- the kernel summation's cost and memory ----

// Frames whose kernels' anchors (the frame and its margin, R beyond it) reach beyond this field
// angle (radians, 45 deg) sum every kernel directly: there the nufft evaluator's chirp tilings for
// the outer kernels took minutes each (a 24 px frame at 90 deg), far more than their direct sums
// over a kernel's few thousand film points (kernels of 49 x 49 pixels in the margin of a 32 px
// frame at 60 deg, beyond 45 deg: 4e7 to 6e7 chirp evaluations in 2300 to 3400 boxes each,
// against 1.2e8 direct terms for the whole sum). The anchor nearest the frame's centre, which
// chooses for all of them, sees none of that: its own tiling is one box.
constexpr double kMaxNufftKernelField = M_PI / 4;

// How the kernel summation's kernels are summed: one source to the pinhole directly (a lattice of
// transforms for one source never pays), the film as `spec.settings` ask, directly beyond
// kMaxNufftKernelField.
struct KernelSums {
    SummationSettings to_pinhole, to_film;
};
// (`g`: the spec's kernel_summation_geometry, which the callers hold)
KernelSums kernel_sums(const KernelSummationSpec& spec, const KernelSummationGeometry& g);

// Work of one convolution in direct terms: the kernels' sums (`in` and `out`: the frame's two
// sums' counts on the kernels' lattice, their points replaced by one source and a kernel's film
// points), and per run the transforms and products (counted for every kernel: an upper bound,
// the basis being known only once the kernels are).
struct KernelSummationWork {
    double kernels = 0, per_run = 0;
};
// On `device`: a GPU's runs priced at what they take there (gpu_run_cost.h); runs in direction
// cosines (direction_runs.h) at their two NUFFTs' taps, transforms and products.
KernelSummationWork kernel_summation_work(const KernelSummationSpec& spec, SumCounts in, SumCounts out,
                                          const ComputeDevice& device);
// Bytes a convolution holds at once: the kernels' spectra and a run's sums (on the CPU; a GPU
// holds the same in its memory, padded to powers of two); in direction cosines the sources, the
// film points and each thread's transforms.
double kernel_summation_bytes(const KernelSummationSpec& spec, const ComputeDevice& device);

// ---- the devices ----

// (the device a job opens, choose_device, is declared in summation_plan.h for the job's front)

// A committed plan's evaluator on `device`: the job's `fixed` choice (a share's), or direct for
// no points, else choose_sum for `counts`; nufft on a GPU refused, a failed `gpu` handle refused.
struct PlanSumQuery {
    const SumCounts* counts = nullptr;  // the plan's own (unused for `fixed` or `empty`)
    bool empty = false;                 // no points, or no samples
    Summation asked = Summation::Auto;
    const SumChoice* fixed = nullptr;   // the job's choice, or null
};
Result<SumChoice> choose_plan_sum(const PlanSumQuery& q, const ComputeDevice& device);

// The kernel summation's runs where the device cannot take its transforms (`why`): under `gpu` the
// job fails, under `auto` they run on the CPU (success: the CPU).
Result<bool> kernel_runs_off_device(const ComputeDevice& device, const std::string& why, ErrorKind kind);

// ---- the one entry point: a frame's sums at one wavelength ----

// What the point sums' plans take for `asked`: nufft for one source at a time (the incoherent
// method, `single`) would pay a lattice of FFTs per source, so there the cheaper stands.
Summation point_sum_asked(Summation asked, bool single);

// What the chooser weighs: the two point sums' counts on the frame's lattice and how often a
// wavelength executes them; the kernel summation's counts on its kernels' lattice where it applies.
struct FrameSums {
    SumCounts in, out;       // sources -> pinhole (one source where `single`), pinhole -> film
    bool single = false;     // the incoherent method: each source through the pinhole alone
    double repeats = 1;      // executions of both sums: the runs, or (single) the sources
    double film_share = 1;   // the share of the film's rows counted (a share of a job)
    bool kernel_counted = false;  // the kernel summation's counts below are set (asked for, or weighed by `auto`)
    bool kernel_applies = false;  // sources at pixel centres, an opening of one piece, layers within reach
    KernelSummationSpec kernel;
    SumCounts kernel_in, kernel_out;  // the frame's sums on the kernels' lattice
    double kernel_runs = 1;        // runs (1 for the incoherent method: one pass of powers)
};

// What a job asks: the summation (auto weighs the kernel summation where `weigh_kernel`, else the
// point sums alone), and the term rate measured here (0: no seconds, the reason in terms).
struct ChoiceSettings {
    Summation asked = Summation::Auto;
    bool weigh_kernel = false;
    double term_rate = 0;
    // the job's decision of the point sums' evaluators at this wavelength (SummationDecision),
    // priced as decided instead of chosen again; null: chosen here
    const SumChoice* decided_in = nullptr;
    const SumChoice* decided_out = nullptr;
};

// The choice: the kernel summation, or the point sums with each sum's evaluator (`in`, `out`); the device; the
// estimated work (direct terms), seconds (0 without a rate) and bytes the evaluator holds at once
// beyond the frame's own arrays; and why, in a few words ("kernel: 1.9 s estimated against nufft 6.3 s").
struct SummationChoice {
    Summation summation = Summation::Auto;  // Kernel, or the point sums: Direct, Nufft, or Auto where they differ
    SumChoice in, out;
    KernelSummationWork kernel;
    bool gpu = false;
    double work = 0, seconds = 0, bytes = 0;
    std::string reason;
};
// Among the rows `device` (the job's handle) serves.
SummationChoice choose_summation(const FrameSums& frame, const ComputeDevice& device, const ChoiceSettings& settings);

// The kernel summation's work for the whole frame in direct terms (the evaluators' table's frame
// estimate for the rows that take whole runs, summation_evaluator.h): its kernels, then every
// run; infinite where the frame's kernel-summation counts are not set. (The rows of one sum are priced by
// their sums: choose_sum.)
double kernel_cost(const FrameSums& frame, const ComputeDevice& device, const ChoiceSettings& settings);

}  // namespace wavecam::detail
