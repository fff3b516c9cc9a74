// What every evaluator's runs share (scene_runs.h).
#include "summation/scene_runs.h"

#include <algorithm>
#include <cmath>

#include "base/counter_random.h"

namespace wavecam::detail {

void average_into_output(std::vector<float>& points, const SceneSum& sum, const PinholeCamera& c, int overscan,
                         const WorkRange& range, float* irradiance) {
    const size_t n2 = size_t(sum.subsamples) * sum.subsamples, width = size_t(c.width - 2 * overscan);
    for (size_t p = 0; p < points.size() / n2; ++p) {
        double total = 0;
        for (size_t k = 0; k < n2; ++k) total += points[p * n2 + k];
        irradiance[(range.row_begin + p / width) * c.width + overscan + p % width] += static_cast<float>(total / n2);
    }
    std::fill(points.begin(), points.end(), 0.0f);
}

PointSource centred(const PinholeCamera& c, const Emitter& e, double phase) {
    return source_at(c, {e.x + 0.5 * e.w, e.y + 0.5 * e.h, e.depth, e.meaning}, e.power, phase);
}

double cell_turns(const PhaseDraw& d, long i, long j) {
    const PhaseCode::CellPhase place = d.code.cell_phase(i, j);
    return counter_uniform(d.settings.seed ^ d.stream, 0, place.key, 4) + place.ramp_turns;
}

double source_turns(const PhaseDraw& d, long i, long j, uint64_t key, int run) {
    const SceneSumSettings& s = d.settings;
    if (!s.coded_phases) return counter_uniform(s.seed ^ d.stream, uint64_t(run), key, 3);
    return cell_turns(d, i, j) + d.code.offset_turns(run, d.code.code_class(i, j));
}

// Coded (phase_codes.h): each emitter's phase 2 pi (theta + k m / K), theta uniform per emitter
// and wavelength, m its class; with jitter, every emitter moved by one common random offset
// within its cell, the same in every run: the codes cancel the cross terms of different classes
// only if nothing moves between runs, and a common offset keeps a uniform wall uniform (an
// offset per emitter would leave lumps that no run averages away).
// Independent (the seed paper's own): a fresh uniform phase and place per emitter and run.
std::vector<PointSource> run_sources(const PinholeCamera& c, const std::vector<Emitter>& emitters, const PhaseDraw& d,
                                     int run) {
    const SceneSumSettings& s = d.settings;
    std::vector<PointSource> sources;
    sources.reserve(emitters.size());
    const uint64_t draw = s.coded_phases ? 0 : uint64_t(run);  // the counter the random numbers use
    for (const Emitter& e : emitters) {
        const long i = long(std::floor(e.x)), j = long(std::floor(e.y));
        const double phase = 2 * M_PI * source_turns(d, i, j, e.key, run);
        if (!s.jitter) {
            sources.push_back(centred(c, e, phase));
            continue;
        }
        const uint64_t place = s.coded_phases ? ~0ull : e.key;  // one offset for all, or one each
        const double jx = counter_uniform(s.seed, draw, place, 1);
        const double jy = counter_uniform(s.seed, draw, place, 2);
        sources.push_back(source_at(c, {e.x + jx * e.w, e.y + jy * e.h, e.depth, e.meaning}, e.power, phase));
    }
    return sources;
}

}  // namespace wavecam::detail
