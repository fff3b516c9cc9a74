// Tensor-product Chebyshev interpolation over a box of up to three parameters, and the choice of
// its nodes per axis for a given kernel and tolerance: the low-rank separation behind the fast
// summation (docs/summation.md). A kernel h(p, xi) smooth in p is replaced by
//   h(p, xi) ~= sum_q L_q(p) h(p_q, xi),
// L_q the Lagrange polynomials on Chebyshev points of the first kind (barycentric form, Berrut &
// Trefethen, "Barycentric Lagrange interpolation", SIAM Review 46 (2004)). Internal to core.
#pragma once
#include <array>
#include <cmath>
#include <complex>
#include <functional>
#include <vector>

namespace wavecam::detail {

using Parameter = std::array<double, 3>;

struct ChebyshevBox {
    int dims = 1;
    Parameter lo{0, 0, 0}, hi{0, 0, 0};
    std::array<int, 3> nodes{1, 1, 1};  // per axis

    int rank() const { return nodes[0] * (dims > 1 ? nodes[1] : 1) * (dims > 2 ? nodes[2] : 1); }
    // The parameter of node q (0 <= q < rank()), axis 0 fastest.
    Parameter node(int q) const;
    // L_q(p) for every node q into weights[0 .. rank()).
    void weights(const Parameter& p, double* weights) const;
    bool contains(const Parameter& p) const;
};

// h(p, xi) for the parameter p and one of the probe points xi (index into the caller's probes).
using KernelProbe = std::function<std::complex<double>(const Parameter& p, int probe)>;

// What each tiled box must meet and how far splitting goes (tile_boxes).
struct BoxSplitting {
    double tolerance;
    int max_rank;
    int max_nodes = 10;
    bool economise = true;
    // Where given, the kernel's evaluations so far: tiling gives up, returning no boxes, once
    // they pass max_evaluations (a chooser's budget, choose.cpp).
    const double* evaluations = nullptr;
    double max_evaluations = INFINITY;
};

// Splits `box` into boxes each interpolating `kernel` to within `tolerance` (max error over the
// probes along every axis, the other axes at their ends and centre) with at most `max_rank` nodes,
// at most `max_nodes` per axis: halves the axis needing the most nodes until both bounds hold, and,
// if `economise`, further where the halves need fewer nodes in all than the whole. No boxes where
// the evaluations' budget ran out.
std::vector<ChebyshevBox> tile_boxes(ChebyshevBox box, const KernelProbe& kernel, int probes,
                                     const BoxSplitting& splitting, int depth = 0);

}  // namespace wavecam::detail
