// The creation table of the frame's evaluators (summation_evaluator.h): one row per evaluator,
// its word, devices, create functions and cost. Add an evaluator here, and its file.
#include "summation/summation_evaluator.h"

namespace wavecam {
namespace detail {
namespace {

// The direct terms of one sum: on the GPU of the plan's device where it committed there.
std::unique_ptr<SumEvaluator> direct_sum(const SumGeometry& g, const SumChoice& choice) {
    return choice.gpu ? make_gpu_direct_evaluator(g) : make_direct_evaluator(g);
}

}  // namespace

const EvaluatorRow kEvaluators[kEvaluatorCount] = {
    // summation, word, devices, on the frame's lattice, a frame's runs, one sum, cost
    {Summation::Direct, "direct", kOnCpu | kOnGpu, true, make_exact_runs, direct_sum, direct_cost},
    {Summation::Nufft, "nufft", kOnCpu, true, make_exact_runs, make_nufft_evaluator, nufft_cost},
    {Summation::Psf, "psf", kOnCpu | kOnGpu, false, make_psf_runs, nullptr, psf_cost},
};

const EvaluatorRow& evaluator_row(Summation s) {
    for (const EvaluatorRow& row : kEvaluators)
        if (row.summation == s) return row;
    return kEvaluators[0];  // auto: the exact sums
}

}  // namespace detail

const char* summation_word(Summation s) { return s == Summation::Auto ? "auto" : detail::evaluator_row(s).word; }

std::vector<std::pair<const char*, Summation>> summation_choices() {
    std::vector<std::pair<const char*, Summation>> words{{"auto", Summation::Auto}};
    for (const detail::EvaluatorRow& row : detail::kEvaluators) words.emplace_back(row.word, row.summation);
    return words;
}

}  // namespace wavecam
