// The PSF's far tail, beyond the kernels. Internal to core.
//
// A kernel holds kPsfKernelEnergy (97%) of its PSF; the rest lands farther than the kernel
// radius R. Dropping it would darken every frame by up to 3%, by an amount that varies over
// the field (off-axis PSFs are wider), and a uniform wall would no longer come back uniform;
// folding it into the kernel would move it into the core. Here each source's missing share
// (interpolated over anchors and layers, as its kernel is) is spread over an annulus R <= r <=
// kTailReach R with the ring-averaged profile of a sharp-edged aperture's far tail, intensity
// ~ 1/r^3 (Born & Wolf 8.5.2: the energy beyond r falls as 1/r), holding all of the share.
// The annulus lies in direction cosines, not on the film: in them a PSF is one function of the
// difference of directions for every source (Fraunhofer optics), and a film pixel takes cos^4
// of a source's spread light by its share of that space, so a uniform wall gets its deficit
// back uniformly where every direction of its annulus is a film point. The annulus starts where
// the kernel ends in directions (far_tail.cpp). Spread on the film instead, a pixel got back the
// cos^4-weighted average of its neighbours' tails out to 16 R, tens of degrees at wide fields: a
// wall at 60 deg came back 1-1.6% low. The paraxial 1/r^3 profile reaches beyond the disc of directions where R is wide
// against the frame (R is sized for the corners; at 90-120 deg 16 R outruns every direction):
// no film point lies there (the angular spectrum beyond it is evanescent), and that part is
// dropped. The point sums agree: on a 32 px frame at 60 deg with R = 24, the kernel summation's
// incoherent image is 0.7% above theirs so, 3.5% above when that part was folded back in. The
// far tail is smooth, so it is summed on a grid of cells about R/3 axis pixels wide (the
// sources' light per cell) and interpolated back bilinearly.
#pragma once
#include "convolution/output_window.h"
#include "convolution/kernel_table.h"
#include "wavecam/spectral_scene.h"

namespace wavecam::detail {

constexpr int kTailReach = 16;

// Where film kernels of `radius` pixels end, in axis pixels of direction: on the axis, where they
// reach least far in directions.
double film_kernel_edge(int radius, double tan_pitch);

// deficit(layer, anchor, m): the share of the power the kernel m = 3p + q does not hold.
// Adds the far tail of `scene` to `xyz` (out.width x out.height), whose pixel (0, 0) is the
// table's domain pixel (out.x0, out.y0) and camera pixel (out.x0 - origin, out.y0 - origin). The
// annulus starts at `kernel_edge` axis pixels, where the kernels end in directions. `oblique`:
// each source's light weighted by cos(out) / cos(in), as the kernels in direction cosines weight
// theirs (direction_convolution.h); film kernels hold the weight of their own field instead.
void add_far_tail(const KernelTable& table, double kernel_edge, bool oblique, const SpectralScene& scene, int origin,
                  const OutputWindow& out, float* xyz, int nthreads);

}  // namespace wavecam::detail
