// The one summation loop of the exact propagator (propagation.cpp): sum_s a_s w_s exp(2 pi i t_s)
// over n terms, with a complex weight w_s = (wr[s], wi[s]) from arrays and the path's amplitude
// a_s and phase t_s (in turns) from `path(s, t, a)`. Float terms summed in blocks of kBlock
// (vectorised: `omp simd`, phases by sincos_turns), double across blocks, so rounding does not
// grow with the number of terms. Internal to core.
#pragma once
#include <algorithm>
#include <cstddef>

#include "base/sincos_turns.h"

namespace wavecam::detail {

constexpr size_t kPhasorBlock = 1024;

template <class Path>
[[gnu::always_inline]] inline void phasor_sum(size_t n, const float* __restrict wr, const float* __restrict wi,
                                              Path path, double& re, double& im) {
    for (size_t b = 0; b < n; b += kPhasorBlock) {
        const size_t e = std::min(n, b + kPhasorBlock);
        float sr = 0, si = 0;
#pragma omp simd reduction(+ : sr, si)
        for (size_t s = b; s < e; ++s) {
            float turns, amp;
            path(s, turns, amp);
            float sn, cs;
            sincos_turns(turns, sn, cs);
            sr += amp * (wr[s] * cs - wi[s] * sn);
            si += amp * (wr[s] * sn + wi[s] * cs);
        }
        re += sr;
        im += si;
    }
}

}  // namespace wavecam::detail
