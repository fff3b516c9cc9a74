// One source's amplitude kernels for the kernel summation (kernel_summation.h): the point sums from a
// unit source at a pixel's centre, at given inverse depths, to the film points of the
// (2R + 1)^2 pixels round its image, n x n per pixel, sub-point by sub-point; the same lattice,
// film points, amplitudes and obliquity as the direct sums. Internal to core.
#pragma once
#include <complex>
#include <vector>

#include "summation/kernel/kernel_summation_geometry.h"
#include "summation/choose.h"

namespace wavecam::detail {

struct KernelSetup {
    const KernelSummationSpec* spec = nullptr;
    const KernelSummationGeometry* g = nullptr;
    const ApertureSamples* samples = nullptr;  // the kernels' pinhole lattice
    SummationSettings to_pinhole;             // how the source's sum is evaluated (kernel_sums)
    UnitSource unit;
    const ComputeDevice* device = nullptr;    // where the sums run
};

// Unit sources as the point sums place them in camera c: (x, y) in camera pixels, at planar
// inverse depth w.
UnitSource unit_sources(const PinholeCamera& c);

// The kernels of a source at camera pixel (px, py), one per inverse depth, into `fields`;
// `settings` evaluates the sum to the film, `film_scope` carries its evaluator's choice from
// kernel to kernel (fixed after the first).
Result<bool> source_kernels(const KernelSetup& k, int px, int py, const std::vector<double>& inverse_depths,
                            const SummationSettings& settings, PlanScope& film_scope,
                            std::vector<std::vector<std::complex<double>>>& fields);

}  // namespace wavecam::detail
