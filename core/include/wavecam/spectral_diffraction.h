// Diffracting a rendered scene in colour: RGB radiance -> spectra (a linear basis per primary)
// -> one monochrome diffraction per wavelength -> CIE XYZ on the film, exposed so that a
// uniform scene gives back its own radiance at the image centre.
#pragma once
#include <functional>
#include "wavecam/scene_diffraction.h"
#include "wavecam/spectral_scene.h"
#include "wavecam/spectrum.h"

namespace wavecam {

// One wavelength's propagation: adds film irradiance for `scene` to `irradiance`.
// diffract_monochrome is the physical one; tests substitute an ideal (delta) propagator.
using MonochromePropagator = std::function<Result<bool>(const MonochromeScene& scene, double wavelength,
                                                        float* irradiance, const ProgressFn& progress)>;

// diffract_monochrome's, on `device`, noting what ran in `report` (the caller's, kept alive) where given.
MonochromePropagator wave_propagator(const SceneSumSettings& settings, const ComputeDevice& device,
                                     SumReport* report = nullptr);

// One run of `settings` at a time, each into an image of its own (a share's units, work_share.h):
// adds run `run`'s film irradiance, weighted 1/settings.runs, for `scene` to `irradiance`. Its
// calls share a wavelength's kernel summation's kernels, as one wave_propagator's runs do.
using RunPropagator = std::function<Result<bool>(const MonochromeScene& scene, double wavelength, int run,
                                                 float* irradiance, const ProgressFn& progress)>;
RunPropagator run_propagator(const SceneSumSettings& settings, const ComputeDevice& device,
                             SumReport* report = nullptr);

// Exposure: a uniform radiance L through a pinhole of area A at film distance f gives film
// irradiance L A / f^2 at the centre (the cos^4 law at angle 0), so the film is scaled by
// f^2 / A. Off axis the film records flux through its plane, |U|^2 cos(incidence).
double exposure_scale(const Aperture& aperture, double film_distance);

// Writes the film image to `out`.
// Spectral power can be negative for saturated colours (the basis is calibrated, not
// physical); each wavelength then propagates its positive and negative power separately,
// which keeps the method linear in RGB.
Result<bool> diffract_spectral(const SpectralScene& scene, const SpectralBasis& basis, const Aperture& aperture,
                               const MonochromePropagator& propagate, const XyzOutput& out,
                               const ProgressFn& progress = {});

}  // namespace wavecam
