// How fast the exact kernel runs here and now: the rate behind every time estimate wavecam
// prints ("about 20 min at 1.3e9 terms/s measured here"), measured, not assumed.
#pragma once

namespace wavecam {

// Terms per second of the exact propagation (pinhole samples x film points) on `nthreads`
// threads (0 = every core), the fastest pass of a small synthetic job timed for about `seconds`
// (at least three passes). Measured once
// per thread count per process; later calls return the first measurement.
double measured_term_rate(int nthreads = 0, double seconds = 0.1);

}  // namespace wavecam
