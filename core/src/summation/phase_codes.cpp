// Phase codes for the random-phase runs (phase_codes.h, docs/phase_codes.md).
#include "summation/phase_codes.h"

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
    // a reduced (Lagrange-Gauss) basis of {(i, j): i + g j = 0 mod K}, from (K, 0) and (-g, 1)
    // (a the shorter; b reduced against it until it is no shorter: each pass shortens b)
    long ax = -step_, ay = 1, bx = K, by = 0;
    for (;;) {
        if (ax * ax + ay * ay > bx * bx + by * by) std::swap(ax, bx), std::swap(ay, by);
        const long q = std::lround(double(ax * bx + ay * by) / double(ax * ax + ay * ay));
        bx -= q * ax, by -= q * ay;
        if (bx * bx + by * by >= ax * ax + ay * ay) break;
    }
    b1x_ = ax, b1y_ = ay, b2x_ = bx, b2y_ = by;
}

void PhaseCode::cell(long i, long j, long& u, long& v) const {
    // lattice coordinates of (i, j), then the nearest of the four lattice points around them
    // (ties to the smaller (distance, u, v): the same rule everywhere, so the cells tile)
    const double det = double(b1x_) * b2y_ - double(b1y_) * b2x_;
    const double fu = (double(i) * b2y_ - double(j) * b2x_) / det, fv = (double(j) * b1x_ - double(i) * b1y_) / det;
    long best = -1;
    for (long du = 0; du <= 1; ++du)
        for (long dv = 0; dv <= 1; ++dv) {
            const long cu = long(std::floor(fu)) + du, cv = long(std::floor(fv)) + dv;
            const long dx = i - (cu * b1x_ + cv * b2x_), dy = j - (cu * b1y_ + cv * b2y_);
            const long d = dx * dx + dy * dy;
            if (best < 0 || d < best || (d == best && (cu < u || (cu == u && cv < v)))) best = d, u = cu, v = cv;
        }
}

PhaseCode::CellPhase PhaseCode::cell_phase(long i, long j) const {
    long u, v;
    cell(i, j, u, v);
    const uint64_t key = (uint64_t(uint32_t(u)) << 32) | uint64_t(uint32_t(v));
    if (runs_ < 2) return {key, 0.0};
    // the cell's frequency k_c = u a + v b, a = (11/16, 0), b = (0, 9/16) cycles per pixel, over the
    // pixel's offset from the cell's lattice point (docs/phase_codes.md: chosen with the residual's
    // variance formula, then measured)
    const double kx = 11.0 / 16 * double(u), ky = 9.0 / 16 * double(v);
    const double rx = double(i - (u * b1x_ + v * b2x_)), ry = double(j - (u * b1y_ + v * b2y_));
    const double t = kx * rx + ky * ry;
    return {key, t - std::floor(t)};
}

int PhaseCode::code_class(long i, long j) const {
    const long m = (i + step_ * j) % runs_;
    return int(m < 0 ? m + runs_ : m);
}

double PhaseCode::offset_turns(int run, int code_class) const {
    return double((long(run) * code_class) % runs_) / runs_;
}

}  // namespace wavecam::detail
