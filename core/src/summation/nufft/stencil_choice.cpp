// The stencil a sum's off-lattice samples take (stencil_choice.h).
#include "summation/nufft/stencil_choice.h"

#include <algorithm>

namespace wavecam::detail {

StencilChoice choose_stencil(const DirectionRange& r, double k, double h, const SampleCount& samples,
                             double tolerance) {
    const double on = samples.on, off = samples.off, reach = samples.reach;
    const double u = std::max({std::fabs(r.ux0), std::fabs(r.ux1), std::fabs(r.uy0), std::fabs(r.uy1)});
    const double slope = 2 * std::max(std::fabs(r.rho0), std::fabs(r.rho1)) * reach;
    const double per_term = std::min(1e-2, tolerance / 3 * (on + off) / std::max(1.0, off));
    const double band = k * h * (u + slope);
    StencilChoice c;
    if (band < M_PI) c.stencil = BandLimitedStencil(band, per_term);
    if (c.stencil.usable()) {
        c.inner = INFINITY;
        return c;
    }
    for (double narrower : {0.9, 0.8, 0.7, 0.6, 0.5}) {
        if (narrower * M_PI >= band) continue;
        c.stencil = BandLimitedStencil(narrower * M_PI, per_term);
        if (c.stencil.usable()) {
            c.inner = narrower * M_PI / (k * h) - slope;
            return c;
        }
    }
    return c;
}

}  // namespace wavecam::detail
