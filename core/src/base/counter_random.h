// Counter-based random numbers: a value is a pure function of (seed, run, index, stream), so
// results do not depend on thread count or scheduling. SplitMix64 finaliser (Steele, Lea &
// Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014).
#pragma once
#include <cstdint>

namespace wavecam::detail {

inline uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// Uniform in [0, 1).
inline double counter_uniform(uint64_t seed, uint64_t run, uint64_t index, uint64_t stream) {
    const uint64_t h = splitmix64(splitmix64(splitmix64(seed ^ (stream << 56)) ^ run) ^ index);
    return double(h >> 11) * 0x1.0p-53;
}

}  // namespace wavecam::detail
