// The kernel summation's convolution domain (kernel_summation.h): the kernel radius at the
// frame's widest field, the domain and its transform size, the anchors the kernels are
// computed at and the depth layers; and what it costs. Internal to wavecam_core.
#pragma once
#include "summation/kernel/kernel_summation.h"

namespace wavecam::detail {

// The convolution's geometry: kernel radius, domain, transform size, anchors and layers.
struct KernelSummationGeometry {
    int radius = 0, origin = 0, width = 0, height = 0, nx = 0, ny = 0;
    AnchorAxis ax, ay;
    DepthLayers layers;
    int anchors() const { return int(ax.knots.size() * ay.knots.size()); }
};

KernelSummationGeometry kernel_summation_geometry(const KernelSummationSpec& s);

// Which anchors' kernels are summed (kernel_summation_kernels.cpp); the others are read from them.
// Per anchor: `mirror`, the anchor whose kernels mirrored across the optical axis are its own
// (mirror_sources, kernel_table.h); `transpose`, where the frame is square and the opening its
// own mirror image across y = -x (Aperture::even_across_antidiagonal), the anchor of the
// transposed knots (kx, ky) -> (ky, kx) whose kernels transposed, rows for columns, are its own,
// of each such pair among the mirror sources the one of lower index; else -1.
struct KernelSources {
    std::vector<int> mirror, transpose;
    bool summed(int a) const { return mirror[size_t(a)] == a && transpose[size_t(a)] < 0; }
    int count() const;  // the anchors summed
};
KernelSources kernel_sources(const KernelSummationSpec& s, const KernelSummationGeometry& g);

// Whether the Airy radius 1.22 lambda f / D spans a pixel or more: below it the film pixels
// average the far tail's cross terms (kernel_summation.h, the far tail).
bool airy_spans_a_pixel(const KernelSummationSpec& s);

// The share of its PSF's power a kernel holds: kPsfKernelEnergy, or more for coherent runs of a
// job of few runs (kernel_summation.h, the far tail).
double kernel_energy(const KernelSummationSpec& s);

}  // namespace wavecam::detail
