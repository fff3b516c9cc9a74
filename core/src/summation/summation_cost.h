// The one cost model of the exact sums (docs/summation.md, "Cost"): a sum's work in direct
// terms by either evaluator, from counts alone, and the cheapest division of the lattice into
// sub-apertures. choose_sum (summation_plan.h) decides from it. Internal to core.
#pragma once
#include "wavecam/summation_plan.h"

namespace wavecam::detail {

// Cost of the nufft evaluator's parts in direct terms (one term of propagation.cpp's kernel, 1.5 ns
// on 2 cores), measured on a 620 x 620 lattice with 400k points in scan order: an FFT point x log2
// 2.0 ns, a kernel tap 4.3 ns (with the point's weights and phase), a chirp 22 ns (double sqrt and
// sincos). The ratios, not the times, are what the estimate uses.
constexpr double kFftCost = 1.33, kTapCost = 2.9, kChirpCost = 15.0;
// A complex multiply-add in double, a third of a term.
constexpr double kMacCost = 0.35;

// Sub-apertures per side tried: 1, 2, 4, ... while each keeps at least kMinCellsAcross cells across
// and the work falls.
constexpr int kMinCellsAcross = 24;
constexpr int kMaxBlocks = 16;

// Both evaluators' work for `counts` (SumChoice's direct_work, nufft_work, blocks, stencil,
// nufft_count; `evaluator` and `work` left for choose_sum).
SumChoice sum_work(const SumCounts& counts);

}  // namespace wavecam::detail
