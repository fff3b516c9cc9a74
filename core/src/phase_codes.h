// Phase codes for the random-phase runs (docs/phase_codes.md). Run k of K gives source s the
// phase 2 pi (theta_s + k m_s / K), m_s the source's code class, theta_s = Theta_c + sigma_s: Theta_c
// uniform and independent per cell c (per wavelength; a cell holds one pixel of every class) and
// sigma_s half a turn or none, the class's sign in a Walsh row set by the cell's colour. Over the K runs the cross term of two sources carries
//   (1/K) sum_k exp(2 pi i k (m_s - m_t) / K) = [m_s == m_t (mod K)],
// so sources of different classes never interfere in the mean: only pairs of one class remain,
// with a random phase theta_s - theta_t (zero in expectation, as the paper's independent phases:
// two sources of one class lie in different cells). Between two nearby cells the signs differ for
// half the classes, so those pairs' residues partly cancel (2.35% -> 2.1% on a uniform wall).
// Each run's marginal phase stays uniform. Classes follow a rank-1 lattice over pixel positions,
// m = (i + g j) mod K, g chosen so that pixels of one class are as far apart as K allows
// (about sqrt(2K / sqrt 3) pixels, a near-hexagonal lattice). Internal to core.
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
    // (each cell holds one pixel of every class); and a key for the cell's random phase.
    void cell(long i, long j, long& u, long& v) const;
    uint64_t cell_key(long i, long j) const;
    // Half a turn or none: pixel (i, j)'s sign in its cell's Walsh row (class m against the
    // cell's colour, (u mod 4) + 4 (v mod 4)), so that the same-class pairs between two nearby
    // cells carry opposite signs for half the classes (docs/phase_codes.md).
    double sign_turns(long i, long j) const;

private:
    int runs_;
    long step_;  // g
    double spacing_;
    long b1x_ = 1, b1y_ = 0, b2x_ = 0, b2y_ = 1;  // a reduced basis of the class lattice
    int colours_ = 1;                             // Walsh rows used: a power of two, at most 16 and K
};

}  // namespace wavecam::detail
