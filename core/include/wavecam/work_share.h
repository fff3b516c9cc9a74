// Splitting one scene-sum job into N shares for a cluster (wavecam farm). The work is a set
// of units, one per (wavelength, run), in wavelength-major order. A unit's film irradiance is a
// pure function of the input, the settings and the unit (counter-based random phases: the
// phases of run r depend on (seed, wavelength, r, pixel) only), so it does not matter which
// share computes it or how many shares there are: the merge is exact.
// With N <= units, share K holds a contiguous range of units on the whole film; with more
// shares than units, every unit is cut into bands of film rows and a share is one band.
#pragma once
#include <string>
#include "wavecam/result.h"

namespace wavecam {

struct WorkShare {
    int index = 0, count = 0;          // K of N, K from 1; count 0 = the whole job
    int unit_begin = 0, unit_end = 0;  // units [begin, end); unit u = wavelength u / runs, run u % runs
    int row_begin = 0, row_end = 0;    // film rows [begin, end)
    bool whole() const { return count == 0; }
};

// The K-th of N shares of `wavelengths` x `runs` units on a film `height` rows high.
// Errors name what is wrong ("share: ..."): K outside 1..N, or more shares than unit rows.
Result<WorkShare> work_share(int index, int count, int wavelengths, int runs, int height);

// "K/N" -> (K, N); errors read "--share: expected K/N with 1 <= K <= N, e.g. 3/8, got '...'".
Result<WorkShare> parse_share(const std::string& text);

// "wavelengths 0-2 x runs 0-1, rows 0-15": what a share sums, for headers and messages.
std::string describe_share(const WorkShare& share, int runs);

}  // namespace wavecam
