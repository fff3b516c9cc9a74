// The PSF's far tail, beyond the kernels. Internal to core.
//
// A kernel holds kPsfKernelEnergy (97%) of its PSF; the rest lands farther than the kernel
// radius R. Dropping it would darken every frame by up to 3%, by an amount that varies over
// the field (off-axis PSFs are wider), and a uniform wall would no longer come back uniform;
// folding it into the kernel would move it into the core. Here each source's missing share
// (interpolated over anchors and layers, as its kernel is) is spread over an annulus R <= r <=
// kTailReach R with the ring-averaged profile of a sharp-edged aperture's far tail, intensity
// ~ 1/r^3 (Born & Wolf 8.5.2: the energy beyond r falls as 1/r), carrying the share of such a
// tail that lies within the annulus, 1 - 1/kTailReach; the rest (0.2% of the light) is lost.
// Computing that far tail at film resolution would cost (kTailReach)^2 times the kernel; it is
// smooth, so it is summed on a grid coarser by about R/3 (the sources' light per cell, the
// missing shares interpolated at the cell's centre) and interpolated back bilinearly.
#pragma once
#include "output_window.h"
#include "kernel_table.h"
#include "wavecam/spectral_diffraction.h"

namespace wavecam::detail {

constexpr int kTailReach = 16;

// deficit(layer, anchor, m): the share of the power the kernel m = 3p + q does not hold.
// Adds the far tail of `scene` to `xyz` (out.width x out.height), whose pixel (0, 0) is the
// table's domain pixel (out.x0, out.y0) and camera pixel (out.x0 - origin, out.y0 - origin).
void add_far_tail(const KernelTable& table, const SpectralScene& scene, int origin, const OutputWindow& out, float* xyz,
                  int nthreads);

}  // namespace wavecam::detail
