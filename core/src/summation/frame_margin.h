// The scene beyond the frame, for the point sums. Internal to core.
//
// Film pixels near the border receive light from scene points outside the frame. As the fast
// path does (convolution_method.h), the scene beyond the input is its edge continued: a point
// outside takes the radiance (bounded by its neighbours' along the edge, edge_continuation.h)
// and planar depth of the nearest edge pixel, at its own field position. The margin reaches kTailReach R beyond the output frame (R: psf_kernel_radius, the
// kPsfKernelEnergy radius): the light the convolution method's kernels and far tail hold, all but about
// (1 - kPsfKernelEnergy) / kTailReach of each PSF. Never farther than one frame side, though (a
// PSF wider than the frame would make the scene mostly invented edge), and no farther than the
// frame's own pinhole lattice carries (below), down to kMinReachRadii R: a tail whose energy
// beyond r falls as 1/r (Born & Wolf 8.5.2) puts 1/pi of it across a straight edge, so a border
// pixel then misses at most (1 - kPsfKernelEnergy) / (kMinReachRadii pi) = 0.24% of its light,
// a corner twice that.
//
// Cost. Out to the PSF's geometric shadow (radius rho pixels) margin sources are single pixels;
// beyond it a PSF is its smooth diffraction tail, so pixels are merged into cells no wider than a
// quarter of their distance past rho (a tail ~ 1/s^2..1/s^3 varies by < 1.6% to second order over
// such a cell, about its centre). Cells stay one pixel wide along the edge, so each holds one
// edge pixel's light. Per side that is rho + 4 + ~4.5 ln(reach / 4) cells across instead of
// `reach`: the margin adds about perimeter x (rho + 20) sources, not perimeter x 16 R.
// Margin sources arrive from wider angles than the frame's, and a square pinhole lattice of
// pitch h sends a source's light also to directions shifted by lambda / h (its grating orders):
// h <= lambda / (sin(widest source) + sin(widest film point)) along each lattice axis keeps them
// off the film. The frame's lattice (both at the frame's corner) carries margin sources out to
// where the axis sums reach its corner's; a lit margin beyond that refines the lattice, which
// happens only for reaches under kMinReachRadii R (narrow fields, very wide frames).
#pragma once
#include <vector>
#include "wavecam/aperture.h"
#include "wavecam/pinhole_camera.h"

namespace wavecam::detail {

constexpr int kMinReachRadii = 4;

// Pixels [x0, x1) x [y0, y1) (camera coordinates, beyond the input) lit as the input's edge
// pixel (edge_x, edge_y).
struct MarginCell {
    int x0, x1, y0, y1;
    int edge_x, edge_y;
};

// The radii the margin is built from, in pixels beyond the output frame (`overscan` pixels inside
// the camera's on every side), for sources as near as `nearest_depth` (planar, m) at `wavelength`.
struct MarginRadii {
    int kernel = 0;  // R, psf_kernel_radius as the convolution method finds it
    int rho = 0;     // the geometric shadow's radius: margin sources are single pixels out to it
    int reach = 0;   // the most the margin reaches: kTailReach R, at most one frame side
};
MarginRadii margin_radii(const Aperture& aperture, const PinholeCamera& camera, int overscan, double nearest_depth,
                         double wavelength);

// The cells beyond the camera's pixels out to `reach` beyond the output frame.
std::vector<MarginCell> margin_cells(const PinholeCamera& camera, int overscan, int reach, int rho);

// Solid angle (sr) of the pixel block [x0, x1) x [y0, y1) seen from the pinhole (exact for a
// tangent-plane rectangle: sum of +-atan(u v / sqrt(1 + u^2 + v^2)) over its corners).
double block_solid_angle(const PinholeCamera& camera, double x0, double x1, double y0, double y1);

}  // namespace wavecam::detail
