// The kernel summation's error, checked at plan time (kernel_summation.h): before `auto` hands a job to
// it, the kernels it would blend are computed at a few probe sources and compared with the exact
// sums' own kernels there; with the far tail's cross terms, which the runs average out as
// 1/sqrt(runs), that bounds how far its runs can be from the point sums' same runs. Internal to
// core.
//
// The blend. Kernels are exact at the anchors and blended between them: the runs' mean takes the
// anchors' pixel images blended bilinearly, and each anchor's two layers' amplitudes blended with
// their power balanced (kernel_summation.h, the blend's mean). Probes:
//   - the centre of three anchor cells: the one on the optical axis, the outermost on the
//     horizontal axis and the outermost corner cell (the widest field, where the 1/cos^3 stretch
//     changes the kernels fastest), at the nearest layer;
//   - the middle of the two nearest layers (the most defocus) at an anchor of the axis cell.
// Each probe's error is the relative L2 difference of the pixel image (a pixel's mean of |K|^2
// over its film points) of the blend against the exact kernel's: a scene's mean image is the sum
// of its sources' images, so its error is at most the worst source's in that norm (a star field's
// is about that; a textured frame's less). On the bench frame (128 px at 50 deg, the 0.315 mm
// pinhole) the probes foresaw the kernel runs' stars at 0.16% and 0.27%; measured 0.14% and 0.26%
// (tests/core/test_kernel_blend_mean.cpp).
//
// The tail. The runs' cross terms of the light beyond the kernels (t of each PSF) with the rest
// average out as about 0.8 sqrt(t / K) RMS of the mean over K coded runs, measured where the Airy
// radius spans a pixel or more (kernel_summation.h); a PSF narrower than a pixel has its cross terms
// averaged by the film pixels (the bench frame's job, t = 3% at 64 runs: 0.48-0.64% per channel
// where the model gives 1.73%), and the incoherent sums have none.
#pragma once
#include <cmath>
#include <vector>

#include "summation/kernel/kernel_summation.h"

namespace wavecam::detail {

// The kernel summation's stated error: its runs within this RMS of the point sums' same runs, per
// channel.
constexpr double kKernelErrorBound = 0.015;

// A probe source's blend error: at camera pixel (x, y), nearest layer (or, for the layers' probe,
// the middle of the two nearest).
struct KernelProbe {
    int x = 0, y = 0;
    bool layers = false;
    double error = 0;
};

struct KernelErrorCheck {
    std::vector<KernelProbe> probes;
    double blend = 0;  // the worst probe's
    double tail = 0;   // the far tail's cross terms after the runs
    double total() const { return std::hypot(blend, tail); }
    bool within() const { return total() <= kKernelErrorBound; }
};

// Fails only when a probe's sums fail (cancelled, or the device).
Result<KernelErrorCheck> check_kernel_error(const ComputeDevice& device, const KernelSummationSpec& spec,
                                            double lattice_pitch, const UnitSource& unit);
// The same for a job's settings at `wavelength` (scene_summation_choice.cpp): the spec and lattice
// its kernel runs would take, for s.nearest_depth (NaN counts as all sky).
Result<KernelErrorCheck> kernel_error_check(const SceneSumSettings& s, const ComputeDevice& device, const PinholeCamera& c,
                                            double wavelength);

}  // namespace wavecam::detail
