// Phase codes for the random-phase runs (docs/phase_codes.md). Run k of K gives source s the
// phase 2 pi (theta_s + k m_s / K), m_s the source's code class, theta_s = Theta_c + sigma_s: Theta_c
// uniform and independent per cell c (per wavelength; a cell holds one pixel of every class) and
// sigma_s = k_c . r_s the cell's phase ramp at the pixel's offset r_s from the cell's centre, its
// frequency k_c stepping with the cell's place. Over the K runs the cross term of two sources carries
//   (1/K) sum_k exp(2 pi i k (m_s - m_t) / K) = [m_s == m_t (mod K)],
// so sources of different classes never interfere in the mean: only pairs of one class remain,
// with a random phase theta_s - theta_t (zero in expectation, as the paper's independent phases:
// two sources of one class lie in different cells). The K same-class pairs that join two nearby
// cells share the cells' Theta difference and differ by a plane wave (k_c - k_c') . r over the
// cell, so their residues partly cancel (2.1% -> 1.9% on a uniform wall, about 10% less at every
// field of view measured). Each run's marginal phase stays uniform. Classes follow a rank-1 lattice
// over pixel positions, m = (i + g j) mod K, g chosen so that pixels of one class are as far apart
// as K allows (4 pixels at K = 16, 8 at K = 64). Internal to core.
#pragma once
#include <cstdint>

namespace wavecam::detail {

class PhaseCode {
public:
    explicit PhaseCode(int runs);
    int runs() const { return runs_; }
    // Pixel (i, j)'s class, 0 <= m < runs.
    int code_class(long i, long j) const;
    // The run's phase offset of a class, in turns: k m / K (mod 1).
    double offset_turns(int run, int code_class) const;
    // The shortest distance, in pixels, between two pixels of one class (1 for a single run).
    double class_spacing() const { return spacing_; }
    // The cell of pixel (i, j): the class lattice's point nearest to it, in lattice coordinates
    // (each cell holds one pixel of every class).
    void cell(long i, long j, long& u, long& v) const;
    // Pixel (i, j)'s place in its cell, found with one cell lookup: a key for the cell's random
    // phase, and the cell's phase ramp there in turns [0, 1): k_c . r, r the pixel's offset from
    // the cell's lattice point, k_c = u a + v b (cycles per pixel) for the cell at lattice
    // coordinates (u, v), a = (11/16, 0), b = (0, 9/16): two nearby cells' same-class pairs differ
    // by a plane wave over the cell (docs/phase_codes.md).
    struct CellPhase {
        uint64_t key;
        double ramp_turns;
    };
    CellPhase cell_phase(long i, long j) const;

private:
    int runs_;
    long step_;  // g
    double spacing_;
    long b1x_ = 1, b1y_ = 0, b2x_ = 0, b2y_ = 1;  // a reduced basis of the class lattice
};

}  // namespace wavecam::detail
