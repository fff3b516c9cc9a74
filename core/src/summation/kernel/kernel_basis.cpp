#include "summation/kernel/kernel_basis.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Eigenvalues>

namespace wavecam::detail {

namespace {

KernelBasis identity(int K) {
    KernelBasis b;
    b.kernels = b.rank = K;
    b.coefficient.assign(size_t(K) * K, 0.0);
    b.mix.assign(size_t(K) * K, 0.0);
    for (int k = 0; k < K; ++k) b.coefficient[size_t(k) * K + k] = b.mix[size_t(k) * K + k] = 1.0;
    return b;
}

}  // namespace

KernelBasis kernel_basis(const std::vector<std::complex<double>>& gram, int K, double tolerance) {
    if (K < 2 || K > kMaxBasisKernels) return identity(K);
    // G = V L V^H: Householder tridiagonalisation and implicit QL (Eigen's self-adjoint solver;
    // Golub & Van Loan, sec. 8.3), eigenvalues ascending
    const Eigen::Map<const Eigen::Matrix<std::complex<double>, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> g(
        gram.data(), K, K);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> solver(g);
    if (solver.info() != Eigen::Success) return identity(K);
    const Eigen::VectorXd& value = solver.eigenvalues();
    const Eigen::MatrixXcd& vector = solver.eigenvectors();
    // the fewest, largest first, that leave no kernel more than `tolerance` of its power out
    int rank = 0;
    std::vector<double> held(K, 0.0);
    for (;; ++rank) {
        bool enough = true;
        for (int k = 0; k < K; ++k) {
            const double power = gram[size_t(k) * K + k].real();
            enough = enough && power - held[k] <= tolerance * power;
        }
        if (enough) break;
        const int e = K - 1 - rank;
        if (rank == K || !(value[e] > 0)) return identity(K);  // (rounding: the kernels themselves)
        for (int k = 0; k < K; ++k) held[k] += std::norm(vector(k, e)) * value[e];
    }
    if (rank == 0 || rank >= K) return identity(K);
    KernelBasis b;
    b.kernels = K;
    b.rank = rank;
    b.coefficient.resize(size_t(K) * rank);
    b.mix.resize(size_t(rank) * K);
    for (int r = 0; r < rank; ++r) {
        const int e = K - 1 - r;
        const double sigma = std::sqrt(value[e]);
        for (int k = 0; k < K; ++k) {
            b.coefficient[size_t(k) * rank + r] = vector(k, e) * sigma;
            b.mix[size_t(r) * K + k] = std::conj(vector(k, e)) / sigma;
        }
    }
    return b;
}

SubPointModes sub_point_modes(const std::vector<std::vector<std::complex<double>>>& kernels, int points,
                              bool incoherent) {
    SubPointModes modes;
    if (incoherent || points == 1) {
        modes.count = 1;
        modes.weight.assign(points, 1.0);
        return modes;
    }
    const int S = points;
    if (S > kMaxBasisKernels) {  // (as kernel_basis: each sub-point its own mode)
        modes.count = S;
        modes.weight.assign(size_t(S) * S, 0.0);
        for (int sub = 0; sub < S; ++sub) modes.weight[size_t(sub) * S + sub] = 1.0;
        return modes;
    }
    std::vector<std::complex<double>> gram(size_t(S) * S, 0.0);
    for (const auto& k : kernels) {
        const size_t length = k.size() / S;
        for (int i = 0; i < S; ++i)
            for (int j = i; j < S; ++j) {
                std::complex<double> dot = 0;
                for (size_t t = 0; t < length; ++t) dot += k[i * length + t] * std::conj(k[j * length + t]);
                gram[size_t(i) * S + j] += dot;
            }
    }
    for (int i = 0; i < S; ++i)
        for (int j = 0; j < i; ++j) gram[size_t(i) * S + j] = std::conj(gram[size_t(j) * S + i]);
    // basis_m = sum_sub mix[m][sub] U_sub = sum_sub conj(V_sub,m) U_sub / sigma_m, and
    // coefficient[sub][m] = V_sub,m sigma_m: the unit mix is mix x sigma
    const KernelBasis b = kernel_basis(gram, S, kSubPointTolerance);
    modes.count = b.rank;
    modes.weight.resize(size_t(b.rank) * S);
    for (int m = 0; m < b.rank; ++m) {
        double sigma = 0;
        for (int sub = 0; sub < S; ++sub) sigma += std::norm(b.coefficient[size_t(sub) * b.rank + m]);
        sigma = std::sqrt(sigma);
        for (int sub = 0; sub < S; ++sub) modes.weight[size_t(m) * S + sub] = b.mix[size_t(m) * S + sub] * sigma;
    }
    return modes;
}

}  // namespace wavecam::detail
