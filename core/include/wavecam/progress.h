// Progress and cancellation for long computations: a callback that receives the fraction done
// (0..1) and returns false to ask the computation to stop early.
#pragma once
#include <functional>

namespace wavecam {
using ProgressFn = std::function<bool(double fraction_done)>;

// A step's own 0..1 reported as the stretch [from, to] of `progress` (empty when it is).
inline ProgressFn progress_slice(const ProgressFn& progress, double from, double to) {
    if (!progress) return {};
    return [progress, from, to](double f) { return progress(from + (to - from) * f); };
}
}  // namespace wavecam
