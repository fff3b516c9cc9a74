// Phase codes for the random-phase runs (docs/phase_codes.md). Run k of K gives source s the
// phase 2 pi (theta_s + k m_s / K): theta_s uniform and independent per source (per wavelength),
// m_s the source's code class. Over the K runs the cross term of two sources carries
//   (1/K) sum_k exp(2 pi i k (m_s - m_t) / K) = [m_s == m_t (mod K)],
// so sources of different classes never interfere in the mean: only pairs of one class remain,
// with a random phase theta_s - theta_t (zero in expectation, as the paper's independent phases).
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

private:
    int runs_;
    long step_;  // g
    double spacing_;
};

}  // namespace wavecam::detail
