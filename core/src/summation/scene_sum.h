// One wavelength's sums over a frame, as the scene-sum methods build them: the sources (the input's
// pixels and the margin beyond it), the pinhole lattice, the film points (scene_sum.cpp); how
// the two sums are counted for the chooser (scene_summation_choice.cpp); the runs themselves
// are the evaluators' (summation/summation_evaluator.h). Internal to wavecam_core.
#pragma once
#include <cstdint>
#include <vector>

#include "summation/kernel/kernel_summation.h"
#include "summation/choose.h"
#include "wavecam/scene_diffraction.h"
#include "wavecam/summation_plan.h"

namespace wavecam::detail {

// What emits light: a lit pixel of the input, or a lit cell of the margin beyond it (its edge
// pixel's radiance over the cell's solid angle, at the edge pixel's planar depth). A source is
// placed within [x, x + w) x [y, y + h): at the centre, or anywhere (jitter) in a run.
struct Emitter {
    double x, y, w, h;
    double power;  // radiance x solid angle
    double depth;
    DepthMeaning meaning;
    uint64_t key;  // its random numbers' index
};

// The widest tangents |u|, |v| of a set of directions: a lattice axis at a time (below).
struct Extent {
    double u = 0, v = 0;
    void add(const PinholeCamera& c, double x0, double y0, double x1, double y1) {
        for (double x : {x0, x1})
            for (double y : {y0, y1}) {
                double tu, tv;
                c.tangent(x, y, tu, tv);
                u = std::max(u, std::abs(tu));
                v = std::max(v, std::abs(tv));
            }
    }
};

// The share of the work the settings ask for: film rows (within the overscan) and runs,
// clamped to the job.
struct WorkRange {
    int row_begin, row_end, run_begin, run_end;
};

// The frame's sources (the input's pixels and its margin's cells), the pinhole lattice and the
// film points of one wavelength's sum.
struct SceneSum {
    std::vector<Emitter> emitters;  // empty where only counted (a scene without its power)
    size_t emitter_count = 0;       // the sources: emitters' size, or what a count-only sum would hold
    ApertureSamples samples;
    FilmPoints film;
    int subsamples = 1;
    Extent source_extent, film_extent;  // tangents of the widest source and film point
};

// How one run's two sums (or one source's, `single`) are evaluated, and their work in direct
// terms: sum 1 from the sources to the pinhole, sum 2 to the film, each by the evaluator
// s.summation asks for (summation/choose.h). Decided from the whole frame's counts, so
// that every share of a job evaluates its part as the job would; the film's chirps tiled over
// the frame.
struct SumChoices {
    SummationSettings settings;
    PlanScope in, out;
    double in_work = 0, out_work = 0;  // the film's for the whole frame
};

// The settings one wavelength's sum needs (the pixels are check_pixels').
Result<bool> check_settings(const PinholeCamera& c, double wavelength, const SceneSumSettings& s);

// A point of the scene: image position (x, y) (camera pixels) and its depth, read as `meaning`.
struct ScenePoint {
    double x, y, depth;
    DepthMeaning meaning;
};

// A point source at `at` with power `power_on_pinhole` = radiance x solid angle: the irradiance
// it puts on the pinhole whatever its depth.
PointSource source_at(const PinholeCamera& c, const ScenePoint& at, double power_on_pinhole, double phase);

WorkRange work_range(const SceneSumSettings& s, int height);

// The wavelength's own stream of random numbers: its bits.
uint64_t wavelength_stream(double wavelength);

// Film points per pixel side: as asked, or auto_film_subsamples.
int film_subsamples(const SceneSumSettings& s, const PinholeCamera& camera, double wavelength);

// With `scene.power` null every pixel and margin cell counts as lit (estimates).
SceneSum scene_sum(const MonochromeScene& scene, double wavelength, const SceneSumSettings& s, double nearest,
                   const WorkRange& range, bool with_samples);

// The two sums' evaluators and work for a run (or one source's, `single`).
SumChoices decide_sums(const SceneSumSettings& s, const ComputeDevice& device, const SceneSum& sum, const PinholeCamera& c, double wavelength,
                  double nearest, bool single);

// The runs as convolutions with amplitude PSFs (kernel_summation.h) for this wavelength.
KernelSummationSpec kernel_summation_spec(const SceneSumSettings& s, const PinholeCamera& c, double wavelength,
                                    double nearest, int subsamples);

// Whether the scene's depths, nearest at `nearest`, need more amplitude layers than the kernel
// summation takes (kernel_summation.h).
bool too_deep_for_kernel(double nearest, const Aperture& aperture, double wavelength);

// The kernel summation's work: its kernels' sums counted on their own lattice of `pitch`.
KernelSummationWork kernel_work(const SceneSumSettings& s, const SceneSum& sum, const KernelSummationSpec& spec,
                                double nearest, double pitch, const ComputeDevice& device);

}  // namespace wavecam::detail
