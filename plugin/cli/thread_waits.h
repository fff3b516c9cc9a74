// How wavecam's OpenMP threads wait at their barriers. libgomp's threads spin there by default
// (about 300000 rounds before they sleep), which on a machine whose cores other work shares
// takes those cores from the thread being waited for: a scene-sum job beside two CPU-bound loops
// on 2 cores took 1.4x its fair share (twice its quiet time), 1.1x with a spin of 10000 rounds
// then sleep, and the same quiet time either way (docs/performance.md, a busy machine).
#pragma once
#include <string>

namespace wavecam::cli {

// Where the environment says nothing of OpenMP's waiting (neither OMP_WAIT_POLICY nor
// GOMP_SPINCOUNT), the command runs with GOMP_SPINCOUNT=10000: thread_waits.cpp hands it to
// libgomp before libgomp reads the environment (once, as it initialises, before main). A user's
// own setting is kept.

// "threads wait at barriers: GOMP_SPINCOUNT=10000" (what `wavecam estimate` says): the settings
// in effect.
std::string barrier_waits();

}  // namespace wavecam::cli
