// What the kernel summation's runs cost on a device's GPU, in the cost model's terms (choose.h)
// at the device's direct rate (term_rate.h): their transforms and products run in the device's
// shaders (gpu_kernel_summation.h), one dispatch per kernel and one to finish, so a run pays
// each dispatch's latency besides its work, and the work at the shaders' own speed beside the
// device's direct terms. Both are the device's own: on lavapipe a 64 x 32 domain's run took 15
// times its terms' time, nearly all of it waiting on its 40 dispatches. Internal to core.
#pragma once
#include "wavecam/compute_device.h"

namespace wavecam::detail {

// A transform side the GPU's FFTs take (gpu_kernel_summation.h): the next power of two.
inline int gpu_transform_side(int n) {
    int p = 2;
    while (p < n) p *= 2;
    return p;
}

// A run of K kernels whose transforms and products the cost model counts as `terms` costs
// factor x terms + (K + 1) x per_dispatch on the device.
struct GpuRunCost {
    double factor = 1;        // the shaders' work against the model's terms at the direct rate
    double per_dispatch = 0;  // a dispatch's latency, in terms at the direct rate
    double of(double terms, double kernels) const { return factor * terms + (kernels + 1) * per_dispatch; }
};

// Measured, not assumed: the fastest of a few runs of a small domain of many kernels (latency)
// and of a large one of few (work) on the device, against their terms in the cost model; once
// per device per process. The model's own (1, 0) on the CPU, and where the device cannot hold
// the runs (they then run on the CPU, or the job is refused).
GpuRunCost gpu_run_cost(const ComputeDevice& device);

}  // namespace wavecam::detail
