// The exact sums' cost model (summation_cost.h).
#include "summation_cost.h"

#include <algorithm>
#include <cmath>

#include "chirp_interpolation.h"
#include "lattice_nufft.h"
#include "stencil_choice.h"

namespace wavecam::detail {
namespace {

// What a sum pairs: its samples on the lattice and off it, and its points (as SumCounts).
struct SumTerms {
    double lattice_samples, off_lattice, points;
};

// A disc of radius a on a lattice of n cells across, pitch h.
struct DiscLattice {
    int n;
    double a, h;
};

// The nufft evaluator's work for one division into sub-apertures (`discs`, each of bnx x bny
// cells): per sub-aperture and skeleton node an FFT and a lattice of chirps; per point and
// sub-aperture its frequency and phase, its skeleton coefficients and each skeleton node's kernel
// taps; the off-lattice samples direct. Skeleton ranks from the probed sub-apertures.
SumChoice division_work(const ChirpGeometry& geo, const DirectionRange& range, const std::vector<ProbeDisc>& discs,
                        int bnx, int bny, const SumTerms& terms) {
    const double lattice_samples = terms.lattice_samples, off_lattice = terms.off_lattice, points = terms.points;
    SumChoice w;
    const std::vector<ChebyshevBox> boxes = geo.plan(range, discs);
    const std::vector<ProbeDisc> probed = probe_discs(discs);
    const LatticeNufft nufft(bnx, bny, geo.tolerance, 1);
    const double parts = double(discs.size()), dims = geo.dims();
    // each point meets one box (in proportion to its volume): its skeleton's taps and coefficients
    double transforms = 0, point_work = 0, volume = 0;
    for (const ChebyshevBox& b : boxes) {
        double v = 1, rank = 0;
        for (int d = 0; d < b.dims; ++d) v *= std::max(b.hi[d] - b.lo[d], 1e-12);
        for (const ProbeDisc& d : probed) rank += box_skeleton(geo, b, d).rank();
        rank /= double(probed.size());
        volume += v;
        point_work += v * (rank * kTapCost * nufft.taps_per_point() + b.rank() * (rank + dims) * kMacCost);
        transforms += rank;
    }
    w.nufft_count = int(std::lround(transforms * parts));
    w.nufft_work = transforms * (parts * kFftCost * nufft.fft_work() + kChirpCost * lattice_samples) +
                   points * parts * (point_work / volume + 2 * kChirpCost) + off_lattice * points;
    return w;
}

// Sub-apertures of a disc of radius a on a lattice of n cells across, pitch h: those whose square
// meets the disc, reaching half their diagonal and a cell.
std::vector<ProbeDisc> disc_division(int n, double a, double h, int blocks) {
    std::vector<ProbeDisc> d;
    const int bn = (n + blocks - 1) / blocks;
    const double side = bn * h;
    for (int by = 0; by < blocks; ++by)
        for (int bx = 0; bx < blocks; ++bx) {
            const double x0 = -a - 0.5 * h + bx * side, y0 = -a - 0.5 * h + by * side;
            const double nxp = std::clamp(0.0, x0, x0 + side), nyp = std::clamp(0.0, y0, y0 + side);
            if (std::hypot(nxp, nyp) > a) continue;
            // reach: the farthest of a 9 x 9 grid over the square that lies in the disc
            const double cx = x0 + 0.5 * side, cy = y0 + 0.5 * side;
            double reach = 0;
            for (int j = 0; j <= 8; ++j)
                for (int i = 0; i <= 8; ++i) {
                    const double x = x0 + side * i / 8, y = y0 + side * j / 8;
                    if (std::hypot(x, y) <= a + h) reach = std::max(reach, std::hypot(x - cx, y - cy));
                }
            d.push_back({cx, cy, reach + h});
        }
    return d;
}

// The cheapest division (blocks per side): 1, 2, 4, ... while the work falls.
SumChoice cheapest_division(const ChirpGeometry& geo, const DirectionRange& range, const DiscLattice& disc,
                            const SumTerms& terms) {
    const int n = disc.n;
    const double a = disc.a, h = disc.h;
    SumChoice best;
    for (int blocks = 1; blocks <= kMaxBlocks; blocks *= 2) {
        const int bn = (n + blocks - 1) / blocks;
        if (blocks > 1 && bn < kMinCellsAcross) break;
        SumChoice w = division_work(geo, range, disc_division(n, a, h, blocks), bn, bn, terms);
        w.blocks = blocks;
        if (blocks > 1 && w.nufft_work >= best.nufft_work) break;
        best = w;
    }
    return best;
}

}  // namespace

SumChoice sum_work(const SumCounts& c) {
    const double direct = (c.lattice_samples + c.off_lattice) * c.points;
    if (c.lattice_samples <= 0 || c.samples_across < 1) {
        SumChoice w;
        w.direct_work = w.nufft_work = direct;
        return w;
    }
    const int n = c.samples_across;
    const double a = c.aperture_radius, h = 2 * a / std::max(1, n - 1);
    const DirectionRange& range = c.range;
    // off-lattice samples through the stencil where the band allows: their stencils' cells join
    // the lattice (about one row of `width` per rim sample), their spreading costs little; points
    // beyond its reach (as a share of the range's area) take them directly, with transforms of
    // their own
    const StencilChoice sc =
        choose_stencil(range, 2 * M_PI / c.wavelength, h, a, c.lattice_samples, c.off_lattice, c.tolerance);
    const double width = sc.stencil.width();
    double outside = 1;
    if (sc.inner > 0) {
        const double sx = std::max(std::fabs(range.ux0), std::fabs(range.ux1)),
                     sy = std::max(std::fabs(range.uy0), std::fabs(range.uy1));
        outside = 1 - std::min(1.0, sc.inner / std::max(sx, 1e-12)) * std::min(1.0, sc.inner / std::max(sy, 1e-12));
    }
    // the rim direct for every point, or the stencil (with the split) where it is cheaper
    const ChirpGeometry geo = chirp_geometry(c.film, c.wavelength, c.tolerance, range);
    const DiscLattice disc{n, a, h};
    SumChoice f = cheapest_division(geo, range, disc, {c.lattice_samples, c.off_lattice, c.points});
    f.stencil = false;
    if (sc.inner > 0) {
        SumChoice s = cheapest_division(geo, range, disc,
                                        {c.lattice_samples + c.off_lattice * width, 0.0, (1 - outside) * c.points});
        s.nufft_work += c.off_lattice * width * width * kMacCost;
        if (outside > 0) {
            const SumChoice o =
                cheapest_division(geo, range, disc, {c.lattice_samples, c.off_lattice, outside * c.points});
            s.nufft_work += o.nufft_work;
            s.nufft_count += o.nufft_count;
        }
        s.stencil = true;
        if (s.nufft_work < f.nufft_work) f = s;
    }
    f.direct_work = direct;
    return f;
}

}  // namespace wavecam::detail
