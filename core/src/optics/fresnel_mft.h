// Few zones: the field PSF by a matrix Fourier transform of the sampled pupil onto exactly the
// output grid needed (fresnel_mft.cpp). Internal to core.
#pragma once
#include <vector>

#include "optics/fresnel_field.h"

namespace wavecam::detail {

struct MftPlan {
    int nr = 0, nt = 0;      // pupil samples across, radial and tangential
    int half = 0;            // output grid half-width in steps
    double step = 0;         // output grid spacing on the film (m)
    int points = 0;          // points per kernel pixel side averaged from the grid
    bool mirrored = false;   // evaluated on the halves xi > 0 and mu >= 0 only
    int kept(int n) const { return mirrored ? n / 2 : n; }
    int grid() const { return mirrored ? half + 1 : 2 * half + 1; }
    // real multiply-adds: open x M_t (real x complex), M_r x that (complex x complex), and
    // the matrices' sines and cosines (about 20 each)
    double cost() const {
        const double pr = kept(nr), pt = kept(nt), m = grid();
        return 2 * pr * pt * m + 4 * pr * m * m + 20 * (pr + pt) * m;
    }
};

MftPlan plan_mft(const FieldPsfRequest& q, const FieldGeometry& g);

// The kernel's (2 radius + 1)^2 weights by the plan.
std::vector<float> kernel_by_mft(const FieldPsfRequest& q, const FieldGeometry& g, const MftPlan& plan);

}  // namespace wavecam::detail
