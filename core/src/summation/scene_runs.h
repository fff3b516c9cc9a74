// What every evaluator's runs share (summation_evaluator.h): a run's sources and their phases,
// coded or independent, and the film points averaged into the output. Internal to wavecam_core.
#pragma once
#include <cstdint>
#include <vector>

#include "summation/phase_codes.h"
#include "summation/scene_sum.h"

namespace wavecam::detail {

// The film points' irradiance of one sum, n x n points per output pixel averaged into the output
// rows of `range` (within the overscan), then cleared for the next run.
void average_into_output(std::vector<float>& points, const SceneSum& sum, const PinholeCamera& c, int overscan,
                         const WorkRange& range, float* irradiance);

// An emitter's source at its cell's centre.
PointSource centred(const PinholeCamera& c, const Emitter& e, double phase);

// Where a wavelength's phases come from: the settings (seed, coded or independent), the runs'
// code and the wavelength's stream of random numbers.
struct PhaseDraw {
    const SceneSumSettings& settings;
    const PhaseCode& code;
    uint64_t stream;
};

// A source's phase in one run, in turns. Coded (phase_codes.h): its cell's random phase and ramp
// at pixel (i, j) plus its class's offset for the run; independent: a fresh draw per run for
// `key`, the source's random numbers.
double source_turns(const PhaseDraw& d, long i, long j, uint64_t key, int run);
// Coded: the part of source_turns that is the same in every run (its cell's random phase and
// ramp at pixel (i, j)); source_turns is this plus the class's offset for the run, to the bit.
double cell_turns(const PhaseDraw& d, long i, long j);

// One run's sources (scene_runs.cpp says how they move and what phases they take).
std::vector<PointSource> run_sources(const PinholeCamera& c, const std::vector<Emitter>& emitters, const PhaseDraw& d,
                                     int run);

}  // namespace wavecam::detail
