// Phase codes for the random-phase runs (phase_codes.h, docs/phase_codes.md).
#include "phase_codes.h"

#include <algorithm>
#include <cmath>

namespace wavecam::detail {
namespace {

// Squared length of the shortest nonzero vector (i, j) with i + g j = 0 (mod K): pixels that
// far apart share a class. Vectors with |j| > sqrt(2K) + 1 are longer than the best possible.
long shortest_squared(long K, long g) {
    long best = K * K;  // (K, 0) is always in the lattice
    const long jmax = long(std::sqrt(2.0 * K)) + 2;
    for (long j = 1; j <= jmax; ++j) {
        const long r = ((-g * j) % K + K) % K;  // i = r or r - K
        const long i = std::min(r, K - r);
        best = std::min(best, i * i + j * j);
    }
    return best;
}

}  // namespace

PhaseCode::PhaseCode(int runs) : runs_(std::max(1, runs)), step_(1), spacing_(1) {
    const long K = runs_;
    if (K == 1) return;
    long best = 0;
    // The best multiplier among the first few thousand (K up to 1e5 runs: a 0.1 s search at most).
    for (long g = 1; g < std::min<long>(K, 4096); ++g) {
        const long d = shortest_squared(K, g);
        if (d > best) best = d, step_ = g;
    }
    spacing_ = std::sqrt(double(best));
}

int PhaseCode::code_class(long i, long j) const {
    const long m = (i + step_ * j) % runs_;
    return int(m < 0 ? m + runs_ : m);
}

double PhaseCode::offset_turns(int run, int code_class) const {
    return double((long(run) * code_class) % runs_) / runs_;
}

}  // namespace wavecam::detail
