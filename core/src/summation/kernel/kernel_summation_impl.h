// What a kernel summation holds (kernel_summation.h): the state its kernels' creation leaves for the
// runs and for the runs' mean, and the blend each source takes of the kernels. Internal to core.
#pragma once
#include <algorithm>
#include <complex>
#include <memory>
#include <mutex>
#include <vector>

#include "convolution/kernel_table.h"
#include "fft/complex_fft2d.h"
#include "gpu/gpu_kernel_summation.h"
#include "summation/kernel/basis_spectra.h"
#include "summation/kernel/direction_runs.h"
#include "summation/kernel/kernel_basis.h"
#include "summation/kernel/kernel_summation.h"
#include "summation/kernel/kernel_summation_geometry.h"

namespace wavecam::detail {

struct KernelSummation::Impl {
    ComputeDevice device;
    KernelSummationSpec spec;
    KernelSummationGeometry g;  // (in directions: the domain and layers alone)
    int threads = 1;
    // the runs in direction cosines where the pinhole is in the Fraunhofer regime (direction_runs.h),
    // else none: the anchors' kernels below
    std::unique_ptr<DirectionRuns> directions;
    std::unique_ptr<ComplexFft2D> fft;
    KernelBasis basis;  // the kernels (layer x anchors + anchor) as combinations of a few
    BasisSpectra spectra;  // the basis kernels' spectra per mode (none on a GPU)
    // the runs on a Vulkan device (the spectra kept there), or none: on the CPU
    std::unique_ptr<GpuKernelSummation> gpu;
    // a run's images (one per basis kernel), sums (one per sub-point) and film values, kept from
    // run to run (hundreds of MiB at 1080p: allocated once, not every run); one run at a time
    mutable std::mutex busy;
    mutable std::vector<std::complex<float>> image, total;
    mutable std::vector<double> film;
    KernelTable tail;  // layers, anchors and, in deficit's first entry, the light beyond each kernel
    // Re <K_i, K_j> (the pixel-mean over sub-points) for kernels i = layer x anchors + anchor
    // and, where there are more than kMaxBasisKernels, only their neighbours j in layer and
    // both anchor axes (0 elsewhere)
    std::vector<double> gram;
    size_t kernel_index(int layer, int anchor) const { return size_t(layer) * g.anchors() + anchor; }
    // Coherent runs: per kernel its pixel image I (each pixel's mean of |K|^2 over its film
    // points), and per kernel and neighbour (kNeighbours: layer and both anchor axes within one)
    // the pixel image J of |K - K'|^2, (2R + 1)^2 values each (add_blend_mean)
    static constexpr int kNeighbours = 27;
    std::vector<float> pixel_image, difference_image;
    int neighbour(size_t k, size_t other) const {
        const int A = g.anchors(), nax = int(g.ax.knots.size());
        const int l = int(k) / A, a = int(k) % A, l2 = int(other) / A, a2 = int(other) % A;
        return (l2 - l + 1) * 9 + (a2 / nax - a / nax + 1) * 3 + (a2 % nax - a % nax + 1);
    }

    int points() const { return spec.subsamples * spec.subsamples; }
    // The film's sub-point fields U_sub, as the runs sum them: modes U_m = sum_sub mode[m][sub] U_sub
    // (sub_point_modes)
    SubPointModes modes;

    // The bilinear hat of knot `k` at pixel `i`: 1 on the knot itself, falling to 0 at its
    // neighbours; the outermost knots keep 1 beyond them.
    static double hat(const AnchorAxis& axis, int k, int i) {
        const int cell = axis.cell_of(i);
        const double t =
            std::clamp(double(i - axis.knots[cell]) / (axis.knots[cell + 1] - axis.knots[cell]), 0.0, 1.0);
        return k == cell ? 1 - t : k == cell + 1 ? t : 0.0;
    }
    // The kernels that domain pixel (i, j)'s source blends, and their weights (at most 8): bilinear
    // over the anchors round it, linear between its two layers.
    int blend_of(const KernelSummationSources& s, int i, int j, size_t* index, double* weight) const {
        const size_t p = size_t(j) * g.width + i;
        const int cx = g.ax.cell_of(i), cy = g.ay.cell_of(j), lower = s.lower[p], nax = int(g.ax.knots.size());
        int used = 0;
        for (int dl = 0; dl < 2; ++dl) {
            const double share = dl == 0 ? 1.0 - s.upper_share[p] : s.upper_share[p];
            if (share == 0 || lower + dl >= g.layers.count) continue;
            for (int corner = 0; corner < 4; ++corner) {
                const int kx = cx + (corner & 1), ky = cy + (corner >> 1);
                if (kx >= nax || ky >= int(g.ay.knots.size())) continue;
                const double w = share * hat(g.ax, kx, i) * hat(g.ay, ky, j);
                if (w == 0) continue;
                index[used] = kernel_index(lower + dl, ky * nax + kx);
                weight[used++] = w;
            }
        }
        return used;
    }
};

}  // namespace wavecam::detail
