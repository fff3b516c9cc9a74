// Each point's coefficients on a batch of skeleton nodes: sum_q L_q(p) coeff[q][j], L_q the point's
// Lagrange weight on box node q (a product of per-axis values, axis 0 fastest), coeff the
// skeleton's (node_skeleton.h). Internal to core.
#pragma once
#include <complex>
#include <vector>

#include "summation/nufft/chirp_interpolation.h"

namespace wavecam::detail {

// Transforms run in batches of up to this many skeleton nodes: a point's kernel weights are
// computed once per batch, at the memory of this many grids.
constexpr int kNodeBatch = 8;

// A box's points: `count` points' per-axis Lagrange weights `axis` on the box's `nodes` nodes
// in `dims` dimensions.
struct BoxPointWeights {
    const AxisWeights& axis;
    int dims;
    size_t count;
    int nodes;
};

// Skeleton nodes j0 .. j0 + batch - 1 of `skeleton`.
struct SkeletonBatch {
    const NodeSkeleton& skeleton;
    int j0, batch;
};

// The batch's nodes for the box's points, times factor[i] if given, into out[i * batch + j - j0].
void skeleton_coefficients(const BoxPointWeights& points, const SkeletonBatch& skeleton_batch,
                           const std::complex<double>* factor, std::vector<std::complex<float>>& out, int nthreads);

}  // namespace wavecam::detail
