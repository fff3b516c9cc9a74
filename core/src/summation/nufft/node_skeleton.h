// Interpolative decomposition of a set of functions sampled at common points: a few of them (the
// skeleton) and coefficients that give every one as a combination of those, to a tolerance
// (Cheng, Gimbutas, Martinsson & Rokhlin, "On the compression of low rank matrices", SIAM J. Sci.
// Comput. 26 (2005)): here by Gram-Schmidt with pivoting on the largest residual. The fast
// summation's use (docs/summation.md): the chirps at a box's Chebyshev nodes, on one
// sub-aperture, are nearly dependent; one transform per skeleton node replaces one per node.
// Internal to core.
#pragma once
#include <complex>
#include <vector>

namespace wavecam::detail {

struct NodeSkeleton {
    std::vector<int> rows;                    // the skeleton: indices of the chosen functions
    std::vector<std::complex<double>> coeff;  // functions x skeleton, row-major: f_q ~ sum_j coeff[q][j] f_rows[j]
    int rank() const { return int(rows.size()); }
};

// `values`: `functions` x `points`, row-major. Stops when every function's residual has an RMS
// over the points of at most `tolerance`.
NodeSkeleton node_skeleton(const std::vector<std::complex<double>>& values, int functions, int points,
                           double tolerance);

}  // namespace wavecam::detail
