// The threads wavecam works on: teams from one pool of its own, whose threads spin briefly and
// then sleep (core/src/base/parallel.h), so that inside a host (oiiotool, Blender) they neither
// depend on nor disturb the host's threads, and on shared cores they give their core back.
#pragma once
#include <cstdint>
#include <functional>

namespace wavecam {

// The threads a job takes where it names none: OMP_NUM_THREADS where set (the variable that VFX
// hosts and render farms already set), else the CPUs this process may run on.
int default_threads();

// f(i) for i in [begin, end), in contiguous blocks over `threads` threads (0: default_threads()).
void parallel_for(int64_t begin, int64_t end, int threads, const std::function<void(int64_t)>& f);

}  // namespace wavecam
