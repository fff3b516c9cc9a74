// What a job's sums ran, in words (summation_plan.h: EvaluatorSet, SumReport): the words come
// from the evaluators' table (evaluator_table.cpp), so a new evaluator of one sum needs none here.
#include "wavecam/summation_plan.h"

#include "summation/summation_evaluator.h"

namespace wavecam {
namespace {

// A report's bits: each sum's evaluators (bit 1 << e, the film's shifted by kFilmShift), and where.
constexpr unsigned kFilmShift = 8;
constexpr unsigned kRanOnGpu = 1u << 16, kRanOnCpu = 1u << 17;

// "direct", "nufft", "direct and nufft": the evaluators whose bits `mask` holds, in the table's order.
std::string either(unsigned mask) {
    std::string words;
    for (unsigned e = 0; mask >> e; ++e)
        if (mask >> e & 1) words += (words.empty() ? "" : " and ") + std::string(evaluator_word(Evaluator(e)));
    return words;
}

}  // namespace

const char* evaluator_word(Evaluator e) { return summation_word(detail::summation_of(e)); }

std::string EvaluatorSet::words() const {
    const std::string in = either(to_pinhole), out = either(to_film);
    if (in == out || out.empty()) return in;
    if (in.empty()) return out;
    return in + " to the pinhole, " + out + " to the film";
}

void SumReport::note(SumKind kind, const SumChoice& committed) {
    const unsigned shift = kind == SumKind::PinholeToFilm ? kFilmShift : 0;
    ran_ |= (1u << unsigned(committed.evaluator)) << shift | (committed.gpu ? kRanOnGpu : kRanOnCpu);
}

void SumReport::note_runs(bool on_gpu) { ran_ |= on_gpu ? kRanOnGpu : kRanOnCpu; }

EvaluatorSet SumReport::evaluators() const {
    const unsigned ran = ran_.load(), sums = (1u << kFilmShift) - 1;
    return {ran & sums, ran >> kFilmShift & sums};
}

std::string SumReport::ran_on(const ComputeDevice& device) const {
    const unsigned ran = ran_.load();
    if (!(ran & kRanOnCpu)) return device.description();
    if (!(ran & kRanOnGpu)) return "cpu";
    return device.description() + " and the CPU";
}

}  // namespace wavecam
