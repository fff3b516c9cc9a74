// The creation table of the frame's evaluators (summation_evaluator.h): one row per evaluator
// and device, its word, create functions and estimates. Add an evaluator here, and its file.
#include "summation/summation_evaluator.h"

namespace wavecam {
namespace detail {
namespace {

// The direct terms of one sum on the GPU of the plan's device.
std::unique_ptr<SumEvaluator> gpu_direct_sum(const SumGeometry& g, const SumChoice&) {
    return make_gpu_direct_evaluator(g);
}
std::unique_ptr<SumEvaluator> direct_sum(const SumGeometry& g, const SumChoice&) { return make_direct_evaluator(g); }

const EvaluatorRow kRows[] = {
    // summation, word, device, on the frame's lattice, a frame's runs, one sum, estimates (one sum, a frame)
    {Summation::Direct, "direct", Device::Cpu, true, make_point_sum_runs, direct_sum, direct_sum_work, nullptr},
    {Summation::Direct, "direct", Device::Gpu, true, make_point_sum_runs, gpu_direct_sum, direct_sum_work, nullptr},
    {Summation::Nufft, "nufft", Device::Cpu, true, make_point_sum_runs, make_nufft_evaluator, nufft_sum_work, nullptr},
    {Summation::Kernel, "kernel", Device::Cpu, false, make_kernel_runs, nullptr, nullptr, kernel_cost},
    {Summation::Kernel, "kernel", Device::Gpu, false, make_kernel_runs, nullptr, nullptr, kernel_cost},
};

}  // namespace

const EvaluatorRows kEvaluators{kRows, kRows + sizeof(kRows) / sizeof(kRows[0])};

const EvaluatorRow& evaluator_row(Summation s, Device device) {
    const Summation wanted = s == Summation::Auto ? Summation::Direct : s;  // auto: the point sums
    for (const EvaluatorRow& row : kEvaluators)
        if (serves(row, wanted, device)) return row;
    for (const EvaluatorRow& row : kEvaluators)
        if (serves(row, wanted, Device::Cpu)) return row;
    return kRows[0];
}

}  // namespace detail

const char* summation_word(Summation s) { return s == Summation::Auto ? "auto" : detail::evaluator_row(s).word; }

std::vector<std::pair<const char*, Summation>> summation_choices() {
    std::vector<std::pair<const char*, Summation>> words{{"auto", Summation::Auto}};
    for (const detail::EvaluatorRow& row : detail::kEvaluators) {
        bool listed = false;
        for (const auto& [word, summation] : words) listed = listed || summation == row.summation;
        if (!listed) words.emplace_back(row.word, row.summation);
    }
    return words;
}

}  // namespace wavecam
