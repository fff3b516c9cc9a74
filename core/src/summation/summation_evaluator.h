// Every evaluator of a frame's runs behind one interface, and the table that creates them.
//
// An evaluator runs one wavelength's frame (the scene-sum methods' random-phase runs or incoherent
// sum), explicitly, in the manner of FINUFFT's plans and Embree's objects:
//   create      a row's `create`, for the frame (scene, its sources and film points, settings,
//               the share's rows and runs);
//   set_points  the frame's sources and film points fixed: the plans committed (direct, nufft)
//               or the kernels computed (kernel);
//   execute     a batch of runs, each added to the output on its own (a job is the sum of its
//               shares to the bit);
//   release     destroying it (`reset()` of its unique_ptr).
//
// The creation table, kEvaluators, is the one list of evaluators: one row per evaluator and
// device (direct on the CPU, direct on a GPU, nufft on the CPU, kernel on the CPU, kernel on a GPU),
// each with its word (the `summation` setting's value), its create functions and its estimates;
// the chooser (choose.h) takes the row of lowest estimate among those the job's device and
// setting allow. Adding an evaluator (a CUDA one, say) is one new file that implements
// SummationEvaluator (or, for one sum, SumEvaluator) and one row. The command line's words for
// `summation` come from it (summation_choices, summation_plan.h), `auto` added. Internal to core.
#pragma once
#include <cmath>
#include <memory>

#include "summation/choose.h"
#include "summation/scene_sum.h"
#include "summation/sum_evaluator.h"

namespace wavecam::detail {

// What an evaluator is created for: one wavelength's frame and the share of it to run.
struct EvaluatorSetup {
    const MonochromeScene* scene = nullptr;
    const SceneSum* sum = nullptr;  // its sources; with the frame's lattice and film points where the row samples them
    double wavelength = 0;
    const SceneSumSettings* settings = nullptr;
    const ComputeDevice* device = nullptr;  // where its sums run (the job's handle)
    SumReport* report = nullptr;            // what ran, noted for the job (or none)
    WorkRange range{};
    double nearest = INFINITY;       // the scene's nearest planar depth
    KernelSummationMemo* memo = nullptr;    // kernel: the job's kept kernels, or none
    const SumChoices* sums = nullptr;    // the exact rows: each sum's evaluator, decided for the frame
};

// The runs one execute adds: [run_begin, run_end) of the settings' runs.
struct RunBatch {
    int run_begin = 0, run_end = 0;
};

class SummationEvaluator {
public:
    virtual ~SummationEvaluator() = default;
    // The share of the frame's work that set_points does (for progress), from the cost model.
    virtual double setup_share() const { return 0; }
    // Fails when cancelled through `progress`, on the device, or where the frame is beyond the
    // evaluator (kernel: depths beyond its layers).
    virtual Result<bool> set_points(const ProgressFn& progress) = 0;
    // Adds the batch's runs (each weighted 1/runs) to irradiance (camera width x height).
    virtual Result<bool> execute(const RunBatch& batch, float* irradiance, const ProgressFn& progress) = 0;
};

// One row of the creation table: one evaluator on one kind of device, with its estimate.
struct EvaluatorRow {
    Summation summation;
    const char* word;       // the `summation` setting's value
    Device device;          // Device::Cpu or Device::Gpu
    bool frame_lattice;     // runs on the frame's pinhole lattice and film points (kernel samples its kernels' own)
    // a frame's runs through it
    std::unique_ptr<SummationEvaluator> (*create)(const EvaluatorSetup& setup);
    // one sum through it, for the point sums' plans (summation_plan.h); null where the evaluator
    // takes whole runs (kernel)
    std::unique_ptr<SumEvaluator> (*create_sum)(const SumGeometry& g, const SumChoice& choice);
    // its estimate in direct terms: of one sum (choose.h; `bounded`: auto's, whose tiling may
    // stop early) for a row of sums, whose frames are priced by their sums (choose_summation);
    // of a frame's runs for a row that takes whole runs (kernel); null where the other is set
    SumChoice (*estimate_sum)(const SumCounts& counts, bool bounded);
    double (*estimate)(const FrameSums& frame, const ComputeDevice& device, const ChoiceSettings& settings);
};

// The table's rows, for range-for (evaluator_table.cpp lists them: a row added there is counted).
struct EvaluatorRows {
    const EvaluatorRow* first;
    const EvaluatorRow* last;
    const EvaluatorRow* begin() const { return first; }
    const EvaluatorRow* end() const { return last; }
};
extern const EvaluatorRows kEvaluators;

// Whether `row` serves `asked` (auto: every row) on `device` (Cpu or Gpu).
inline bool serves(const EvaluatorRow& row, Summation asked, Device device) {
    return row.device == device && (asked == Summation::Auto || asked == row.summation);
}

// The summation that runs a committed plan's evaluator.
inline Summation summation_of(Evaluator e) { return e == Evaluator::Nufft ? Summation::Nufft : Summation::Direct; }

// The row of `s` on `device` (Cpu or Gpu; the CPU's where the device has none); `auto` (the exact
// sums, each sum's evaluator the chooser's, after a job has weighed the kernel summation) is direct's, whose runs
// are the point sums' whichever evaluates each sum.
const EvaluatorRow& evaluator_row(Summation s, Device device = Device::Cpu);

// The rows' create functions (one file each).
std::unique_ptr<SummationEvaluator> make_point_sum_runs(const EvaluatorSetup& setup);  // point_sum_runs.cpp
std::unique_ptr<SummationEvaluator> make_kernel_runs(const EvaluatorSetup& setup);    // kernel_runs.cpp

}  // namespace wavecam::detail
