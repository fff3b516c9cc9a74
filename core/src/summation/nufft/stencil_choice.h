// Which band-limited stencil a sum's off-lattice samples take, and which points it serves
// (docs/summation.md). Internal to core.
//
// A point's band is k h times its largest direction component plus the chirp's slope |grad psi|
// <= 2 rho reach (chirp.h). The stencil's error is on the off-lattice samples' terms only: a share
// off / (on + off) of the sum (rim cells, about 4 / samples across), so the sum keeps within a
// third of the tolerance, relative to the sum of its terms' sizes, with each of those terms within
// tolerance / 3 x (on + off) / off, at most 1e-2. Where the range's band is too wide (a frame's
// margin of sources beyond a lattice sized for the frame), the widest band the stencil serves:
// the points beyond take the direct terms for their off-lattice samples.
#pragma once
#include <cmath>

#include "summation/nufft/band_limited_stencil.h"
#include "summation/nufft/lattice_layout.h"
#include "wavecam/summation_plan.h"

namespace wavecam::detail {

struct StencilChoice {
    BandLimitedStencil stencil = no_stencil();
    double inner = -1;  // largest direction component served (inf: every point; < 0: none)
    // No stencil: every off-lattice sample summed directly.
    static BandLimitedStencil no_stencil() { return {M_PI, 1e-2}; }
};

// For a sum over `range` on a lattice of pitch h, wavenumber k, its `samples` within samples.reach
// of the axis, samples.on of them on the lattice and samples.off off it.
StencilChoice choose_stencil(const DirectionRange& r, double k, double h, const SampleCount& samples,
                             double tolerance);

// Whether a point (in-plane direction components) is within the stencil's reach.
inline bool within(double inner, double ux, double uy) { return std::max(std::fabs(ux), std::fabs(uy)) <= inner; }

}  // namespace wavecam::detail
