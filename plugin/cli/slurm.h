// Slurm through its own programs: the `sbatch`, `squeue` on PATH (honouring SLURM_CONF, as they
// do). Nothing here schedules anything itself.
#pragma once
#include <map>
#include <string>
#include <vector>
#include "wavecam/result.h"

namespace wavecam::cli {

// 'text' for a POSIX shell.
std::string shell_quote(const std::string& text);

// Submits `script` with `options` (e.g. --dependency=afterok:12_0:12_1); returns the job id.
// Errors carry sbatch's own message.
Result<std::string> sbatch(const std::string& script, const std::vector<std::string>& options);

// Array task indices as sbatch's --array takes them: "0-3,5,7-8".
std::string index_list(const std::vector<int>& ids);

// Every job and array task Slurm still knows, "123" or "123_4" -> state (PENDING, RUNNING, ...).
Result<std::map<std::string, std::string>> squeue_states();

}  // namespace wavecam::cli
