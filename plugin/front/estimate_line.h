// A job's estimate in words, the same in every front: the command's `apply` and `estimate`
// lines, the plugin's log and (through `wavecam estimate`) Blender's panel.
#pragma once
#include <string>

#include "wavecam/diffract_image.h"

namespace wavecam::front {

// "1h02m", "3m20s", "12s".
std::string format_duration(double seconds);

// "JOB = T terms, about D on N threads at R terms/s measured here": the job's estimate
// (diffract_image.h), its rate measured where the job runs.
std::string estimate_line(const JobEstimate& estimate);

}  // namespace wavecam::front
