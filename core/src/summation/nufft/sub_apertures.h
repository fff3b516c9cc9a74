// The lattice box cut into B x B sub-apertures of bnx x bny cells (the last row and column of
// them may overhang the box), each expanded about its centre (chirp.h); those holding no sample
// dropped. And the discs the chirps' remainder is probed on to choose the interpolation nodes.
// Internal to core.
#pragma once
#include <vector>

#include "summation/nufft/lattice_layout.h"

namespace wavecam::detail {

struct SubAperture {
    long i0 = 0, j0 = 0;        // its first cell, in lattice indices
    double cx = 0, cy = 0;      // the expansion centre (metres)
    double reach = 0;           // farthest sample from the centre, plus a cell: the probes' reach
    std::vector<long> cells;    // per local cell n * bnx + m: the layout's cell, or -1
};
struct SubApertures {
    int blocks = 1, bnx = 0, bny = 0;
    std::vector<SubAperture> parts;
};

SubApertures split_lattice(const LatticeLayout& L, int blocks, double h);

// The lattice cells of a sub-aperture in metres: local cell c = n * bnx + m.
inline double cell_x(const SubAperture& a, const SubApertures& S, long c, double h) { return (a.i0 + c % S.bnx) * h; }
inline double cell_y(const SubAperture& a, const SubApertures& S, long c, double h) { return (a.j0 + c / S.bnx) * h; }

struct ProbeDisc {
    double cx, cy, reach;
};
std::vector<ProbeDisc> discs_of(const SubApertures& S);

// Where the remainder is probed to choose the nodes: the central sub-aperture and the four
// outermost along the diagonals (the Hessian of psi, hence psi2, changes a little across the
// pinhole; one plan serves every sub-aperture).
std::vector<ProbeDisc> probe_discs(const std::vector<ProbeDisc>& all);

}  // namespace wavecam::detail
