// A few kernels whose combinations give every kernel of a set within a tolerance: the kernel
// summation's runs transform one image per basis kernel instead of one per anchor and layer
// (kernel_summation.h). Internal to core.
//
// With the kernels as the rows of M (K x P) and their Gram matrix G = M M^H = V L V^H
// (eigenvectors v_r, eigenvalues l_r, largest first), the kernels are
//   K_k = sum_r V_kr sqrt(l_r) B_r,   B_r = sum_k conj(V_kr) K_k / sqrt(l_r)
// (B_r orthonormal: the singular value decomposition of M). Kept: the fewest r that leave no
// kernel with more than `tolerance` of its power outside them; the power kernel k leaves out is
// G_kk - sum_{r kept} |V_kr|^2 l_r.
#pragma once
#include <complex>
#include <vector>

namespace wavecam::detail {

// Above this many kernels no basis is sought (their Gram matrix is K^2 dot products of kernels,
// its eigen-decomposition K^3): each kernel is its own basis kernel. Wide frames need hundreds of anchors
// (kernel_table.h, kMaxAnchorStep: 13 x 13 at 60 deg, 21 x 21 at 90), whose kernels a few dozen
// basis kernels carry.
constexpr int kMaxBasisKernels = 512;
// A kernel's power left out of its basis, as a fraction: amplitudes within sqrt of it (0.3%).
constexpr double kBasisTolerance = 1e-5;

struct KernelBasis {
    int kernels = 0, rank = 0;
    // kernel k = sum_r coefficient[k * rank + r] basis_r
    std::vector<std::complex<double>> coefficient;
    // basis_r = sum_k mix[r * kernels + k] kernel_k
    std::vector<std::complex<double>> mix;
};

// The basis of `kernels` kernels from their Gram matrix (row-major, Hermitian, positive
// semi-definite): gram[i * K + j] = <K_i, K_j>. More than kMaxBasisKernels kernels, or none
// fewer than the kernels themselves: the identity (rank = kernels).
KernelBasis kernel_basis(const std::vector<std::complex<double>>& gram, int kernels,
                         double tolerance = kBasisTolerance);

// The film's n x n sub-point fields U_sub, as the kernel runs sum their powers: sum_sub |U_sub|^2 is
// unchanged by a unitary mix of them, U_m = sum_sub weight[m][sub] U_sub, and the sub-points of a
// pixel many fringes wide sample one band-limited field, so neighbouring sub-points' fields are
// much alike. With the sub-points' Gram matrix over every kernel, G = F F^H = V L V^H (F's rows:
// each sub-point's values of every kernel), the mix weight[m][sub] = conj(V_sub,m) keeps the
// fewest modes (kernel_basis) that leave no sub-point more than kSubPointTolerance of its power
// out: a run transforms back one sum per mode instead of one per sub-point (24 of 36 on the
// 128 x 128 bench frame at 550 nm). What is left out is light lost, at most that share of any
// sub-point's; on that frame, against every mode kept, the image's mean was 0.016% lower, 0.03%
// RMS, 0.5% at worst. Incoherent (Re U summed, linear): one mode, every weight 1, exact.
constexpr double kSubPointTolerance = 1e-3;
struct SubPointModes {
    int count = 0;
    std::vector<std::complex<double>> weight;  // [mode * sub-points + sub]
};

// `kernels`: each kernel's values, sub-point by sub-point (`points` blocks of equal length).
SubPointModes sub_point_modes(const std::vector<std::vector<std::complex<double>>>& kernels, int points,
                              bool incoherent);

}  // namespace wavecam::detail
