// The chirps' remainder interpolated over the points' parameters (docs/summation.md): the
// parameter range tiled by Chebyshev boxes (chebyshev_box.h), each point's Lagrange weights on its
// box's nodes, and each box's node chirps compressed on a sub-aperture to a few skeleton nodes
// (node_skeleton.h), one NUFFT each. Sources have 3 parameters (ux, uy, rho; chirp / g), film
// points 2 (nx, ny; rho from the film distance; chirp / g^2). Internal to core.
#pragma once
#include <array>
#include <vector>

#include "summation/nufft/chebyshev_box.h"
#include "summation/nufft/chirp.h"
#include "summation/nufft/node_skeleton.h"
#include "summation/nufft/sub_apertures.h"
#include "wavecam/summation_plan.h"

namespace wavecam::detail {

struct ChirpGeometry {
    bool film = false;
    double f = 0, k = 0, tolerance = kSummationTolerance;
    int power() const { return film ? 2 : 1; }
    int dims() const { return film ? 2 : 3; }
    ChebyshevBox box(const DirectionRange& r) const;
    ChirpAtCentre at(const Parameter& p, double cx, double cy) const {
        return {p[0], p[1], film ? film_rho(p[0], p[1], f) : p[2], cx, cy};
    }
    // The boxes tiling `r`, split only where an axis needs more than kMaxNodes: the nodes' count
    // costs only per-point arithmetic, the transforms are the skeleton's. `probed` (where given)
    // is set to the kernel's evaluations the tiling took: a fixed cost per sum that small sums
    // (a kernel summation's kernel's few film points) feel. No boxes once the evaluations pass `max_evaluations`.
    std::vector<ChebyshevBox> tiling(const DirectionRange& r, const std::vector<ProbeDisc>& discs,
                                   double* probed = nullptr, double max_evaluations = INFINITY) const;
    static constexpr int kMaxRank = 4096, kMaxNodes = 12;
};

// The geometry of a sum: the film's distance is 1/R on axis.
ChirpGeometry chirp_geometry(bool film, double wavelength, double tolerance, const DirectionRange& range);

// Per-axis Lagrange values of each point in a box, so that node q's weight is a product of three.
struct AxisWeights {
    std::array<int, 3> n{1, 1, 1}, offset{0, 0, 0};
    int stride = 0;
    std::vector<float> w;  // point-major, stride values per point
    AxisWeights(const ChebyshevBox& b, const std::vector<Parameter>& p, const std::vector<size_t>& points, int nthreads);
};

// Points grouped by the first box holding them (the boxes tile the range; a point on a shared
// face goes to the first).
std::vector<std::vector<size_t>> group(const std::vector<ChebyshevBox>& boxes, const std::vector<Parameter>& p);

// The range the points' parameters span.
DirectionRange range_of(const std::vector<Parameter>& p, int dims);

// A box's skeleton on one sub-aperture's disc: its nodes' remainders fitted at an 11 x 11 grid
// over the disc and 16 points on its rim, to a quarter of the tolerance (the Lagrange weights' sum
// of magnitudes, a few, multiplies it; the interpolation's own and the NUFFT's error are the rest
// of the budget).
NodeSkeleton box_skeleton(const ChirpGeometry& geo, const ChebyshevBox& bx, const ProbeDisc& d);

}  // namespace wavecam::detail
