// The pinhole samples as the nufft evaluator sees them (docs/summation.md): the lattice box
// they sit on (cell centres m h, n h), and the rest (rim centroids, grey or holed apertures),
// which are read from (sources' sum) or spread onto (film's sum) the lattice around them with
// the band-limited stencil where the sum's band allows (the box then takes in their stencils'
// cells), else summed directly. Internal to core.
#pragma once
#include <cstddef>
#include <vector>

#include "summation/nufft/band_limited_stencil.h"
#include "wavecam/aperture.h"

namespace wavecam::detail {

struct LatticeLayout {
    long i0 = 0, j0 = 0;
    int nx = 0, ny = 0;
    std::vector<long> cell;          // per sample: (n - j0) * nx + (m - i0), or -1 off the lattice
    std::vector<char> used;          // per lattice cell: a sample or a stencil sits there
    ApertureSamples off;             // off-lattice samples summed directly
    std::vector<size_t> off_index;   // their indices in the samples
    size_t on = 0;                   // lattice samples
    // off-lattice samples through the stencil: their indices, their stencil's first cell, and
    // `width` weights per axis each
    std::vector<size_t> spread_index;
    std::vector<long> spread_cell;
    std::vector<double> spread_wx, spread_wy;
    int width = 0;
};

// Samples laid out on the lattice; those off it through `stencil` if usable, else direct.
LatticeLayout lattice_layout(const ApertureSamples& s, const BandLimitedStencil& stencil);

// Whether sample k sits on the lattice, and at which cell: a float position within 1e-4 pitch of a
// cell centre is that cell's centre.
bool on_lattice(const ApertureSamples& s, size_t k, long& i, long& j);

// Samples on the lattice and off it (as lattice_layout tells them), and the farthest from the axis.
struct SampleCount {
    double on = 0, off = 0, reach = 0;
};
SampleCount count_samples(const ApertureSamples& s);

}  // namespace wavecam::detail
