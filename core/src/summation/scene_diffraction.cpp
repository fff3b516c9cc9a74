// Diffracting a scene at one wavelength (scene_diffraction.h): the frame's sums built once
// (scene_sum.h), each point sum's evaluator decided, then its runs through the row of the
// evaluators' table (summation_evaluator.h) that the settings and device name: created, its
// points set, its runs executed, released.
#include "wavecam/scene_diffraction.h"

#include <cmath>

#include "summation/summation_evaluator.h"

namespace wavecam {

Result<bool> diffract_monochrome(const MonochromeScene& scene, double wavelength, const SceneSumSettings& s,
                                 const ComputeDevice& device, float* irradiance, const ProgressFn& progress,
                                 SumReport* report) {
    return detail::diffract_monochrome(scene, wavelength, s, device, irradiance, progress, report, nullptr);
}

Result<bool> detail::diffract_monochrome(const MonochromeScene& scene, double wavelength, const SceneSumSettings& s,
                                         const ComputeDevice& device, float* irradiance, const ProgressFn& progress,
                                         SumReport* report, KernelSummationMemo* memo) {
    const PinholeCamera& c = scene.camera;
    if (auto v = check_settings(c, wavelength, s); !v.ok()) return v;
    if (!scene.checked)
        if (auto v = check_pixels(c, scene.power, 1, true, scene.depth); !v.ok()) return v;
    const WorkRange range = work_range(s, c.height);
    const double nearest =
        std::isnan(s.nearest_depth) ? nearest_depth(c, scene.depth, scene.depth_meaning) : s.nearest_depth;
    // auto here: the point sums, each sum's evaluator the chooser's (a job has weighed the kernel summation before)
    const EvaluatorRow& row = evaluator_row(s.summation, device.gpu() ? Device::Gpu : Device::Cpu);
    const SceneSum sum = scene_sum(scene, wavelength, s, nearest, range, row.frame_lattice);
    // each point sum's evaluator: the job's decision (SceneSumSettings::decision), or, for a frame
    // diffracted alone, its own from the whole frame's counts; either way every share evaluates its
    // part as the job would, and nothing below decides again
    const SumChoices sums = row.create_sum ? decide_sums(s, device, sum, c, wavelength, nearest,
                                                       s.method == CoherenceMethod::Incoherent)
                                           : SumChoices{};
    std::unique_ptr<SummationEvaluator> evaluator =
        row.create({&scene, &sum, wavelength, &s, &device, report, range, nearest, memo, &sums});
    const double setup = evaluator->setup_share();
    if (auto r = evaluator->set_points(progress_slice(progress, 0.0, setup)); !r.ok()) return r;
    auto r = evaluator->execute({range.run_begin, range.run_end}, irradiance, progress_slice(progress, setup, 1.0));
    evaluator.reset();  // released
    return r;
}

}  // namespace wavecam
