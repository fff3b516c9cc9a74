#include "wavecam/spectral_diffraction.h"

#include <cmath>
#include <memory>

#include "summation/kernel/kernel_summation.h"

namespace wavecam {

MonochromePropagator wave_propagator(const SceneSumSettings& settings, const ComputeDevice& device,
                                     SumReport* report) {
    // one memo per propagator: a wavelength's negative power reuses its positive power's kernels
    auto memo = std::make_shared<detail::KernelSummationMemo>();
    return [settings, device, report, memo](const MonochromeScene& scene, double wavelength, float* irradiance,
                                            const ProgressFn& progress) {
        return detail::diffract_monochrome(scene, wavelength, settings, device, irradiance, progress, report,
                                           memo.get());
    };
}

RunPropagator run_propagator(const SceneSumSettings& settings, const ComputeDevice& device, SumReport* report) {
    auto memo = std::make_shared<detail::KernelSummationMemo>();
    return [settings, device, report, memo](const MonochromeScene& scene, double wavelength, int run,
                                            float* irradiance, const ProgressFn& progress) {
        SceneSumSettings one = settings;
        one.run_begin = run;
        one.run_end = run + 1;
        return detail::diffract_monochrome(scene, wavelength, one, device, irradiance, progress, report, memo.get());
    };
}

double exposure_scale(const Aperture& aperture, double film_distance) {
    return film_distance * film_distance / aperture.area();
}

Result<bool> diffract_spectral(const SpectralScene& scene, const SpectralBasis& basis, const Aperture& aperture,
                               const MonochromePropagator& propagate, const XyzOutput& out,
                               const ProgressFn& progress) {
    const bool vignetting = out.vignetting;
    float* xyz = out.xyz;
    const PinholeCamera& c = scene.camera;
    // the pixels are checked once for every wavelength: each wavelength's parts of a finite
    // radiance are finite and >= 0
    if (!scene.checked)
        if (auto v = check_pixels(c, scene.rgb, 3, false, scene.depth); !v.ok()) return v;
    const size_t n = size_t(c.width) * c.height;
    const int S = basis.size();
    std::vector<double> film_xyz(3 * n, 0.0);
    std::vector<float> positive(n), negative(n), irradiance(n);

    for (int s = 0; s < S; ++s) {
        bool any_negative = false;
        for (size_t p = 0; p < n; ++p) {
            const double power = basis.power(s, scene.rgb[3 * p], scene.rgb[3 * p + 1], scene.rgb[3 * p + 2]);
            positive[p] = static_cast<float>(std::max(power, 0.0));
            negative[p] = static_cast<float>(std::max(-power, 0.0));
            any_negative |= power < 0;
        }
        const auto xyz_s = basis.xyz_per_power(s);
        for (int sign : {+1, -1}) {
            if (sign < 0 && !any_negative) continue;
            std::fill(irradiance.begin(), irradiance.end(), 0.0f);
            const MonochromeScene mono{c, sign > 0 ? positive.data() : negative.data(), scene.depth,
                                       scene.depth_meaning, s, sign, true};
            ProgressFn report;
            if (progress)
                report = [&progress, s, S, sign](double f) { return progress((s + (sign > 0 ? 0.0 : 0.5) + 0.5 * f) / S); };
            if (auto r = propagate(mono, basis.wavelength(s), irradiance.data(), report); !r.ok()) return r;
            for (size_t p = 0; p < n; ++p)
                for (int k = 0; k < 3; ++k) film_xyz[3 * p + k] += sign * double(irradiance[p]) * xyz_s[k];
        }
    }
    const double exposure = exposure_scale(aperture, c.film_distance);
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            const size_t p = size_t(j) * c.width + i;
            // film flux = |U|^2 x cos(incidence); with the cos^3 of the pixel solid angle this
            // gives the natural cos^4 law, which --no-vignetting divides out
            const double scale = exposure * c.cos_incidence(i, j) / (vignetting ? 1.0 : c.cos4(i, j));
            for (int k = 0; k < 3; ++k) xyz[3 * p + k] = static_cast<float>(film_xyz[3 * p + k] * scale);
        }
    return Result<bool>::success(true);
}

}  // namespace wavecam
