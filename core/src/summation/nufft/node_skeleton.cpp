// Interpolative decomposition by pivoted Gram-Schmidt (node_skeleton.h).
//
// Rows f_q; chosen in turn the row whose residual (its part orthogonal to the rows chosen so far)
// is largest, e_l its normalised residual, so f_{J_i} = sum_{l <= i} R[i][l] e_l with R lower
// triangular. A row's coordinates c_q[l] = <f_q, e_l> then give coeff_q from coeff_q R = c_q by
// back substitution; what is left out is the final residual, below the tolerance.
#include "summation/nufft/node_skeleton.h"

#include <algorithm>
#include <cmath>

namespace wavecam::detail {

using cdouble = std::complex<double>;

NodeSkeleton node_skeleton(const std::vector<cdouble>& values, int functions, int points, double tolerance) {
    NodeSkeleton out;
    const size_t n = size_t(points);
    std::vector<cdouble> residual = values;
    std::vector<std::vector<cdouble>> basis;             // e_l
    std::vector<std::vector<cdouble>> coords(functions);  // c_q[l]
    std::vector<double> norm2(functions);
    auto row = [&](std::vector<cdouble>& m, int q) { return m.data() + size_t(q) * n; };
    const double limit = tolerance * tolerance * points;
    while (int(basis.size()) < std::min(functions, points)) {
        for (int q = 0; q < functions; ++q) {
            double s = 0;
            for (size_t i = 0; i < n; ++i) s += std::norm(row(residual, q)[i]);
            norm2[q] = s;
        }
        const int pick = int(std::max_element(norm2.begin(), norm2.end()) - norm2.begin());
        if (norm2[pick] <= limit) break;
        std::vector<cdouble> e(row(residual, pick), row(residual, pick) + n);
        const double scale = 1.0 / std::sqrt(norm2[pick]);
        for (cdouble& v : e) v *= scale;
        // every row's coordinate on e, taken off its residual (the chosen row's own goes to ~0)
        for (int q = 0; q < functions; ++q) {
            cdouble c = 0;
            for (size_t i = 0; i < n; ++i) c += std::conj(e[i]) * row(residual, q)[i];
            for (size_t i = 0; i < n; ++i) row(residual, q)[i] -= c * e[i];
            coords[q].push_back(c);
        }
        out.rows.push_back(pick);
        basis.push_back(std::move(e));
    }
    const int r = out.rank();
    out.coeff.assign(size_t(functions) * r, 0.0);
    for (int q = 0; q < functions; ++q) {
        cdouble* t = out.coeff.data() + size_t(q) * r;
        for (int l = r - 1; l >= 0; --l) {
            cdouble v = coords[q][l];
            for (int i = l + 1; i < r; ++i) v -= t[i] * coords[out.rows[i]][l];
            t[l] = v / coords[out.rows[l]][l];
        }
    }
    return out;
}

}  // namespace wavecam::detail
