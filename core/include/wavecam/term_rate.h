// How fast the exact kernel runs here and now: the rate behind every time estimate wavecam
// prints ("about 20 min at 1.3e9 terms/s measured here"), measured, not assumed.
#pragma once

namespace wavecam {

// Terms per second of the exact propagation (pinhole samples x film points) on `nthreads`
// threads (0 = every core), the fastest pass of a small synthetic job timed for about `seconds`
// (at least three passes). Measured once
// per thread count per process; later calls return the first measurement.
double measured_term_rate(int nthreads = 0, double seconds = 0.3);

class ComputeDevice;
// The same terms' rate where a job's sums run: measured_term_rate on the CPU, else the direct
// kernel's on the device's GPU (its fastest pass: the first pays for the pipelines), measured
// once per device per process. A job's time is its terms at this rate.
double measured_term_rate(const ComputeDevice& device, int nthreads = 0, double seconds = 0.3);

}  // namespace wavecam
