#include "kernel_basis.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace wavecam::detail {

namespace {

// Eigenvalues and eigenvectors (the columns of v) of the real symmetric n x n matrix a
// (row-major, destroyed): cyclic Jacobi rotations, each zeroing one off-diagonal pair,
//   t = sgn(h) / (|h| + sqrt(h^2 + 1)),  h = (a_qq - a_pp) / (2 a_pq),  c = 1 / sqrt(t^2 + 1),  s = t c,
// until the off-diagonal part is below rounding of the diagonal (Golub & Van Loan, sec. 8.5).
void symmetric_eigen(std::vector<double>& a, int n, std::vector<double>& value, std::vector<double>& v) {
    v.assign(size_t(n) * n, 0.0);
    for (int i = 0; i < n; ++i) v[size_t(i) * n + i] = 1;
    auto at = [&](int i, int j) -> double& { return a[size_t(i) * n + j]; };
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = 0, diagonal = 0;
        for (int p = 0; p < n; ++p) {
            diagonal += at(p, p) * at(p, p);
            for (int q = p + 1; q < n; ++q) off += at(p, q) * at(p, q);
        }
        if (off <= 1e-30 * diagonal || off == 0) break;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) {
                const double apq = at(p, q);
                if (apq == 0) continue;
                const double h = (at(q, q) - at(p, p)) / (2 * apq);
                const double t = (h >= 0 ? 1.0 : -1.0) / (std::abs(h) + std::sqrt(h * h + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < n; ++k) {  // columns p, q
                    const double kp = at(k, p), kq = at(k, q);
                    at(k, p) = c * kp - s * kq;
                    at(k, q) = s * kp + c * kq;
                }
                for (int k = 0; k < n; ++k) {  // rows p, q
                    const double pk = at(p, k), qk = at(q, k);
                    at(p, k) = c * pk - s * qk;
                    at(q, k) = s * pk + c * qk;
                }
                for (int k = 0; k < n; ++k) {
                    double& kp = v[size_t(k) * n + p];
                    double& kq = v[size_t(k) * n + q];
                    const double vp = kp, vq = kq;
                    kp = c * vp - s * vq;
                    kq = s * vp + c * vq;
                }
            }
    }
    value.resize(n);
    for (int i = 0; i < n; ++i) value[i] = at(i, i);
}

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
    // H = X + iY as the real symmetric [[X, -Y], [Y, X]]: its eigenvector (x, y) is H's x + iy,
    // each eigenvalue twice (x + iy and i (x + iy))
    const int n = 2 * K;
    std::vector<double> real(size_t(n) * n);
    for (int i = 0; i < K; ++i)
        for (int j = 0; j < K; ++j) {
            const std::complex<double> h = gram[size_t(i) * K + j];
            real[size_t(i) * n + j] = real[size_t(i + K) * n + j + K] = h.real();
            real[size_t(i) * n + j + K] = -h.imag();
            real[size_t(i + K) * n + j] = h.imag();
        }
    std::vector<double> value, vector;
    symmetric_eigen(real, n, value, vector);
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return value[a] > value[b]; });
    // H's eigenvectors, largest first: each pair's second (and any vector within the span of
    // those kept) removed by Gram-Schmidt
    std::vector<std::vector<std::complex<double>>> kept;
    std::vector<double> eigenvalue;
    for (const int e : order) {
        if (int(kept.size()) == K || !(value[e] > 0)) break;
        std::vector<std::complex<double>> u(K);
        for (int k = 0; k < K; ++k) u[k] = {vector[size_t(k) * n + e], vector[size_t(k + K) * n + e]};
        for (const auto& w : kept) {
            std::complex<double> dot = 0;
            for (int k = 0; k < K; ++k) dot += std::conj(w[k]) * u[k];
            for (int k = 0; k < K; ++k) u[k] -= dot * w[k];
        }
        double norm = 0;
        for (const auto& x : u) norm += std::norm(x);
        if (norm < 0.5) continue;  // (x, y) has unit length: the pair's partner leaves nothing
        for (auto& x : u) x /= std::sqrt(norm);
        double l = 0;  // u^H H u
        for (int i = 0; i < K; ++i)
            for (int j = 0; j < K; ++j) l += (std::conj(u[i]) * gram[size_t(i) * K + j] * u[j]).real();
        if (!(l > 0)) break;
        kept.push_back(std::move(u));
        eigenvalue.push_back(l);
    }
    // the fewest that leave no kernel more than `tolerance` of its power out
    int rank = 0;
    std::vector<double> held(K, 0.0);
    for (;; ++rank) {
        bool enough = true;
        for (int k = 0; k < K; ++k) {
            const double power = gram[size_t(k) * K + k].real();
            enough = enough && power - held[k] <= tolerance * power;
        }
        if (enough) break;
        if (rank == int(kept.size())) return identity(K);  // (rounding: the kernels themselves)
        for (int k = 0; k < K; ++k) held[k] += std::norm(kept[rank][k]) * eigenvalue[rank];
    }
    if (rank == 0 || rank >= K) return identity(K);
    KernelBasis b;
    b.kernels = K;
    b.rank = rank;
    b.coefficient.resize(size_t(K) * rank);
    b.mix.resize(size_t(rank) * K);
    for (int r = 0; r < rank; ++r) {
        const double sigma = std::sqrt(eigenvalue[r]);
        for (int k = 0; k < K; ++k) {
            b.coefficient[size_t(k) * rank + r] = kept[r][k] * sigma;
            b.mix[size_t(r) * K + k] = std::conj(kept[r][k]) / sigma;
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
