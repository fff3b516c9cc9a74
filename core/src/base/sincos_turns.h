// sin and cos of 2 pi t for a phase t given in turns, written so that a loop calling it
// vectorises (no branches, no library calls). Internal to core.
//
// Reduction: q = nearest quarter turn, r = t - q/4 in [-1/8, 1/8] turns, x = 2 pi r in
// [-pi/4, pi/4]; Taylor series to x^9 (sin) and x^8 (cos), truncation error < 3e-8; then the
// quadrant identities sin(x + q pi/2), cos(x + q pi/2). Absolute accuracy is set by float
// rounding of t itself: |t| < 1e3 turns keeps the phase error below 4e-4 rad.
#pragma once
#include <cmath>

namespace wavecam::detail {

inline void sincos_turns(float t, float& s, float& c) {
    const float q = std::nearbyint(4.0f * t);
    const float x = (t - 0.25f * q) * 6.28318530717958647692f;
    const float x2 = x * x;
    const float sp = x * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 * (1.0f / 362880)))));
    const float cp = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320))));
    const int iq = static_cast<int>(q) & 3;
    const bool swap = iq & 1;
    const float sin_sign = 1.0f - static_cast<float>(iq & 2);        // - for quadrants 2, 3
    const float cos_sign = 1.0f - static_cast<float>((iq + 1) & 2);  // - for quadrants 1, 2
    s = sin_sign * (swap ? cp : sp);
    c = cos_sign * (swap ? sp : cp);
}

}  // namespace wavecam::detail
