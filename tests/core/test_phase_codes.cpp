// Coded phases for the random-phase runs (core/src/phase_codes.h, docs/phase_codes.md): the
// classes' geometry, each run's offsets and what nearby cells' same-class pairs carry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <map>
#include <set>
#include <vector>

#include "summation/phase_codes.h"

using namespace wavecam;

TEST(PhaseCode, ClassesAreEvenAndFarApartAndEveryRunsOffsetsCancel) {
    for (int K : {1, 2, 4, 7, 16, 64}) {
        const detail::PhaseCode code(K);
        // every class equally often over K consecutive pixels of a row
        std::vector<int> count(K, 0);
        for (int i = 0; i < K; ++i) ++count[code.code_class(i + 5, 3)];
        for (int m = 0; m < K; ++m) EXPECT_EQ(count[m], 1) << K;
        // the shortest distance between two pixels of one class, by brute force over a window
        double shortest = 1e9;
        for (int j = 0; j <= K; ++j)
            for (int i = -K; i <= K; ++i)
                if ((i || j) && code.code_class(i, j) == code.code_class(0, 0))
                    shortest = std::min(shortest, std::hypot(i, j));
        EXPECT_DOUBLE_EQ(shortest, code.class_spacing()) << K;
        // a near-hexagonal lattice of K points per cell: spacing close to sqrt(2 K / sqrt 3)
        if (K >= 4) {
            EXPECT_GE(shortest, 0.75 * std::sqrt(2 * K / std::sqrt(3.0))) << K;
        }
        // over the K runs, classes m != m' cancel: sum_k exp(2 pi i k (m - m') / K) = 0
        for (int m = 0; m < K; ++m)
            for (int n = 0; n < K; ++n) {
                std::complex<double> sum = 0;
                for (int k = 0; k < K; ++k)
                    sum += std::polar(1.0, 2 * M_PI * (code.offset_turns(k, m) - code.offset_turns(k, n)));
                EXPECT_NEAR(std::abs(sum) / K, m == n ? 1.0 : 0.0, 1e-9) << K << " " << m << " " << n;
            }
    }
}

// The cells the phase ramps use tile the pixels: every pixel in one cell, each cell's pixels one
// of every class (so two sources of one class are never in one cell, and their phases' difference,
// the cells' own random phases, stays uniform), and a pixel's ramp is in [0, 1) turns.
TEST(PhaseCode, CellsHoldOnePixelOfEveryClass) {
    for (int K : {4, 7, 16, 64}) {
        const detail::PhaseCode code(K);
        std::map<std::pair<long, long>, std::set<int>> classes;
        std::map<std::pair<long, long>, int> count;
        for (long j = -40; j < 40; ++j)
            for (long i = -40; i < 40; ++i) {
                long u, v;
                code.cell(i, j, u, v);
                classes[{u, v}].insert(code.code_class(i, j));
                ++count[{u, v}];
                const double s = code.cell_phase(i, j).ramp_turns;
                EXPECT_TRUE(s >= 0.0 && s < 1.0) << K;
            }
        int full = 0;
        for (const auto& [cell, n] : count) {
            EXPECT_EQ(size_t(n), classes[cell].size()) << K;  // no class twice in a cell
            if (n == K) ++full;
        }
        EXPECT_GT(full, 20) << K;  // cells inside the window are whole
    }
}

// What the ramps are for: the K same-class pairs joining a cell to a nearby cell (one pixel of
// each pair in each) carry phase differences that average out over the cell, so pairs of similar
// weight cancel instead of adding. Against the same phase for all K pairs (|mean| = 1, what a
// sign-free cell would give), the mean phasor over the cell is at most 0.2 for the nearest cells
// (the class lattice's shortest vectors, cells 4 pixels apart at K = 16, 8 at K = 64).
TEST(PhaseCode, SameClassPairsBetweenNearbyCellsCarryPhasesThatAverageOut) {
    for (int K : {16, 64}) {
        const detail::PhaseCode code(K);
        // the cell at the origin's pixels, one per class
        std::vector<std::pair<long, long>> home;
        for (long j = -K; j <= K; ++j)
            for (long i = -K; i <= K; ++i) {
                long u, v;
                code.cell(i, j, u, v);
                if (u == 0 && v == 0) home.push_back({i, j});
            }
        ASSERT_EQ(home.size(), size_t(K));
        // every class-lattice vector L within 1.3 spacings: pixel p's partner p + L is in the
        // cell L away, the same class
        int near = 0;
        for (long dj = -K; dj <= K; ++dj)
            for (long di = -K; di <= K; ++di) {
                const double length = std::hypot(di, dj);
                if (length == 0 || length > 1.3 * code.class_spacing() || code.code_class(di, dj) != code.code_class(0, 0))
                    continue;
                ++near;
                std::complex<double> mean = 0;
                for (const auto& [i, j] : home) {
                    EXPECT_EQ(code.code_class(i + di, j + dj), code.code_class(i, j));
                    mean += std::polar(1.0, 2 * M_PI * (code.cell_phase(i + di, j + dj).ramp_turns - code.cell_phase(i, j).ramp_turns)) / double(K);
                }
                EXPECT_LE(std::abs(mean), 0.2) << "K " << K << ", cells " << di << "," << dj << " apart";
            }
        EXPECT_GE(near, 4) << K;
    }
}
