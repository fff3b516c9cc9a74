#include "wavecam/run_count.h"

#include <algorithm>
#include <cmath>

namespace wavecam {

namespace {
// Coded phases leave the pairs of one class within a PSF correlated (docs/phase_codes.md): with
// N sources of comparable light in the PSF and K classes, N^2 / K - N pairs, each of weight
// (I / N)^2, so the noise relative to the mean is about kSpeckle sqrt(1/K - 1/N) for N > K.
// kSpeckle is what averaging a channel's wavelengths leaves of one speckle pattern: fitted on
// a grey wall at 2 m, f = 50 mm, 0.2 mm, 8 wavelengths, the worst channel (0.43 to 0.51 for
// PSFs of 150 to 650 pixels at 64 and 256 runs). Neighbouring wavelengths' speckle is alike, so
// it falls slower than 1/sqrt(wavelengths): the same wall at 64 runs measured 5.4%, 4.1% and
// 3.6% with 3, 8 and 16 wavelengths, about (8 / S)^(1/4).
constexpr double kSpeckle = 0.5;
constexpr int kSpeckleWavelengths = 8;
// The PSF's reach: N counts the sources whose amplitudes overlap at a film point, which the
// rings carry beyond the Airy disc. With N the disc's area the model says 0 once K passes it, but
// the wall at 145 pixels measured 1.86%, 1.02% and 0.60% at 144, 208 and 288 runs (1.82% at 192
// with another seed), and 1.87% at 416 runs for 644 pixels: twice the area asks 288 and 608.
constexpr double kReach = 2.0;
}  // namespace

RunCount runs_for_convergence(const PinholeCamera& camera, const Aperture& aperture, double longest_wavelength,
                              int wavelengths, double nearest_depth) {
    RunCount r;
    const double pitch = camera.pixel_pitch(), f = camera.film_distance;
    const double d = 2 * aperture.bounding_radius();
    const double c = camera.cos_widest(0, 0, camera.width, camera.height);
    // the Airy radius 1.22 lambda f / D, an ellipse 1/cos^3 by 1/cos at field angle acos(c);
    // the shadow's radius D/2 (1 + f / z), the same at every field (the film is parallel to the pinhole)
    const double airy = 1.22 * longest_wavelength * f / d;
    const double shadow = 0.5 * d * (1 + (std::isfinite(nearest_depth) ? f / nearest_depth : 0.0));
    r.psf_pixels = M_PI * (airy * airy / std::pow(c, 4) + shadow * shadow) / (pitch * pitch);
    const double speckle = kSpeckle * std::pow(double(kSpeckleWavelengths) / std::max(1, wavelengths), 0.25);
    const double goal = std::pow(kRunNoiseAim / speckle, 2);
    const double reach = kReach * std::max(r.psf_pixels, 1.0);
    const double wanted = 1 / (goal + 1 / reach);
    r.runs = std::clamp(16 * int(std::ceil(wanted / 16)), kMinRuns, kMaxRuns);
    r.capped = wanted > kMaxRuns;
    r.expected_noise = speckle * std::sqrt(std::max(0.0, 1.0 / r.runs - 1 / reach));
    return r;
}

}  // namespace wavecam
