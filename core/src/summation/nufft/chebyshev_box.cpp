// Chebyshev interpolation boxes (chebyshev_box.h).
#include "summation/nufft/chebyshev_box.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace wavecam::detail {
namespace {

// Chebyshev points of the first kind on [-1, 1]: s_i = cos((2i + 1) pi / 2n); barycentric weights
// (-1)^i sin((2i + 1) pi / 2n) (Berrut & Trefethen eq. 5.3).
double cheb_point(int i, int n) { return std::cos((2 * i + 1) * M_PI / (2 * n)); }
double cheb_weight(int i, int n) { return (i % 2 ? -1 : 1) * std::sin((2 * i + 1) * M_PI / (2 * n)); }

// L_i(s) for i < n at s in [-1, 1].
void lagrange_1d(double s, int n, double* L) {
    if (n == 1) {
        L[0] = 1;
        return;
    }
    double total = 0;
    for (int i = 0; i < n; ++i) {
        const double d = s - cheb_point(i, n);
        if (d == 0) {
            std::fill(L, L + n, 0.0);
            L[i] = 1;
            return;
        }
        L[i] = cheb_weight(i, n) / d;
        total += L[i];
    }
    for (int i = 0; i < n; ++i) L[i] /= total;
}

double to_unit(double p, double lo, double hi) { return hi > lo ? (2 * p - lo - hi) / (hi - lo) : 0.0; }
double from_unit(double s, double lo, double hi) { return 0.5 * (lo + hi) + 0.5 * (hi - lo) * s; }

// Largest interpolation error along axis d with n nodes, over lines through the box with the
// other axes at lo, centre and hi, at 3n + 4 points per line and every probe.
double axis_error(const ChebyshevBox& box, int d, int n, const KernelProbe& kernel, int probes) {
    std::vector<int> others;
    for (int a = 0; a < box.dims; ++a)
        if (a != d) others.push_back(a);
    const int lines = others.empty() ? 1 : (others.size() == 1 ? 3 : 9);
    double worst = 0;
    std::vector<double> L(n);
    std::vector<std::complex<double>> at_node(size_t(n) * probes);
    for (int line = 0; line < lines; ++line) {
        Parameter p = box.lo;
        int code = line;
        for (int a : others) {
            p[a] = from_unit(double(code % 3 - 1), box.lo[a], box.hi[a]);
            code /= 3;
        }
        for (int i = 0; i < n; ++i) {
            p[d] = from_unit(cheb_point(i, n), box.lo[d], box.hi[d]);
            for (int x = 0; x < probes; ++x) at_node[size_t(i) * probes + x] = kernel(p, x);
        }
        const int tests = 3 * n + 4;
        for (int t = 0; t <= tests; ++t) {
            const double s = -1.0 + 2.0 * t / tests;
            p[d] = from_unit(s, box.lo[d], box.hi[d]);
            lagrange_1d(s, n, L.data());
            for (int x = 0; x < probes; ++x) {
                std::complex<double> v = 0;
                for (int i = 0; i < n; ++i) v += L[i] * at_node[size_t(i) * probes + x];
                worst = std::max(worst, std::abs(v - kernel(p, x)));
            }
        }
    }
    return worst;
}

}  // namespace

Parameter ChebyshevBox::node(int q) const {
    Parameter p{0, 0, 0};
    for (int d = 0; d < dims; ++d) {
        p[d] = from_unit(cheb_point(q % nodes[d], nodes[d]), lo[d], hi[d]);
        q /= nodes[d];
    }
    return p;
}

void ChebyshevBox::weights(const Parameter& p, double* w) const {
    double axis[3][16];
    for (int d = 0; d < dims; ++d) lagrange_1d(std::clamp(to_unit(p[d], lo[d], hi[d]), -1.0, 1.0), nodes[d], axis[d]);
    const int r = rank();
    for (int q = 0; q < r; ++q) {
        int code = q;
        double v = 1;
        for (int d = 0; d < dims; ++d) {
            v *= axis[d][code % nodes[d]];
            code /= nodes[d];
        }
        w[q] = v;
    }
}

bool ChebyshevBox::contains(const Parameter& p) const {
    for (int d = 0; d < dims; ++d)
        if (p[d] < lo[d] || p[d] > hi[d]) return false;
    return true;
}

std::vector<ChebyshevBox> tile_boxes(ChebyshevBox box, const KernelProbe& kernel, int probes,
                                     const BoxSplitting& splitting, int depth) {
    const double tolerance = splitting.tolerance;
    const int max_rank = splitting.max_rank, max_nodes = std::min(splitting.max_nodes, 16);
    const bool economise = splitting.economise;
    auto spent = [&] { return splitting.evaluations && *splitting.evaluations > splitting.max_evaluations; };
    if (spent()) return {};
    const double per_axis = tolerance / box.dims;
    int widest = 0;
    bool split = false;
    for (int d = 0; d < box.dims; ++d) {
        int n = 1;
        while (n <= max_nodes && axis_error(box, d, n, kernel, probes) > per_axis) ++n;
        box.nodes[d] = n;
        if (n > max_nodes) split = true;
        if (box.nodes[d] > box.nodes[widest]) widest = d;
    }
    if (spent()) return {};
    // Halving an axis pays where the halves need fewer nodes in all than the whole (each node
    // costs one transform): every axis tried, a few levels deep; forced where an axis needs too many.
    const bool must = split || box.rank() > max_rank;
    std::vector<ChebyshevBox> best{box};
    int best_rank = must ? INT_MAX : box.rank();
    if (!must && (!economise || box.rank() <= 4 || depth >= 3)) return best;
    for (int d = 0; d < box.dims; ++d) {
        if (box.nodes[d] <= 1 || (must && d != widest)) continue;
        ChebyshevBox a = box, b = box;
        const double mid = 0.5 * (box.lo[d] + box.hi[d]);
        a.hi[d] = mid;
        b.lo[d] = mid;
        std::vector<ChebyshevBox> out = tile_boxes(a, kernel, probes, splitting, depth + 1);
        for (ChebyshevBox& c : tile_boxes(b, kernel, probes, splitting, depth + 1)) out.push_back(c);
        if (spent()) return {};
        int total = 0;
        for (const ChebyshevBox& c : out) total += c.rank();
        if (total < best_rank) best = out, best_rank = total;
    }
    return best;
}

}  // namespace wavecam::detail
