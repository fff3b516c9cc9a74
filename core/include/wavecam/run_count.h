// How many coded random-phase runs a frame needs: the run count chosen from the PSF's area in
// pixels, so that every colour channel converges to within kRunNoiseGoal of the infinite-run
// limit at any PSF size (docs/phase_codes.md, "How many runs").
#pragma once
#include "wavecam/aperture.h"
#include "wavecam/pinhole_camera.h"

namespace wavecam {

constexpr double kRunNoiseGoal = 0.02;  // per channel, RMS over the mean, on a uniform wall
constexpr double kRunNoiseAim = 0.015;  // what the count aims at: the model leaves the rest to its floor
constexpr int kMinRuns = 64;            // the count that holds the goal for PSFs of a few pixels
constexpr int kMaxRuns = 1024;          // the price: beyond, the job says what noise to expect

struct RunCount {
    int runs = kMinRuns;
    double psf_pixels = 0;      // the PSF's area in film pixels, at the frame's widest field
    double expected_noise = 0;  // the model's per-channel noise at `runs` (0: within its floor)
    bool capped = false;        // kMaxRuns, fewer than the aim asks: expect `expected_noise`
};

// The runs for a frame through `aperture` whose nearest source is at `nearest_depth` (m,
// infinity for the sky), lit by `wavelengths` wavelengths up to `longest_wavelength` (m): the
// PSF's area N from the Airy radius (stretched 1/cos^3 by 1/cos at the widest field) and the
// pinhole's shadow, then the count the same-class pairs' noise model asks (at least kMinRuns,
// at most kMaxRuns, a multiple of 16).
RunCount runs_for_convergence(const PinholeCamera& camera, const Aperture& aperture, double longest_wavelength,
                              int wavelengths, double nearest_depth);

}  // namespace wavecam
