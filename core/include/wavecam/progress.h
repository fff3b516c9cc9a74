// Progress and cancellation for long computations: a callback that receives the fraction done
// (0..1) and returns false to ask the computation to stop early.
#pragma once
#include <functional>

namespace wavecam {
using ProgressFn = std::function<bool(double fraction_done)>;
}
