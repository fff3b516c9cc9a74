// How the scene-sum methods sample a frame (wavecam/scene_diffraction.h): the pinhole lattice's pitch,
// the film points per pixel, and the nearest source that both depend on.
#include <algorithm>
#include <cmath>

#include "summation/pixel_average.h"
#include "wavecam/scene_diffraction.h"

namespace wavecam {

double scene_sample_pitch(const SceneSumSettings& s, const PinholeCamera& camera, double wavelength,
                          double nearest) {
    if (s.sin_theta_max > 0) return sample_pitch(wavelength, s.sin_theta_max);
    const double sin_corner = camera.sin_max_field_angle();
    const double tan_corner = sin_corner / std::sqrt(1.0 - sin_corner * sin_corner);
    const double t = tan_corner + 0.5 * s.aperture.diameter / std::min(camera.film_distance, nearest);
    const double sin_max = t / std::sqrt(1.0 + t * t) + wavelength / s.aperture.diameter;
    // At least kMinSamplesAcross across the pinhole, so the rim is resolved as a quadrature.
    return std::min(sample_pitch(wavelength, std::min(1.0, sin_max)), s.aperture.diameter / kMinSamplesAcross);
}

int auto_film_subsamples(const Aperture& aperture, const PinholeCamera& camera, double wavelength) {
    // The film field is the pupil's transform (fresnel_psf.h), so the irradiance holds no
    // frequency above span / (lambda f): its finest fringe is lambda f / span, at any depth
    // (cos theta only widens it off axis). Film points closer than that sum every pixel's
    // fringes to their area average; one point per pixel samples them instead. And the points
    // must average well what the optics pass: the midpoint rule's error, weighted by the OTF,
    // within kPixelAverageError (pixel_average.h; a textured frame's pixels were 3.4% RMS off
    // their area averages with the first rule alone at a pixel of 1.3 fringes, 1.6% with this).
    const double span = 2 * aperture.bounding_radius();
    const double finest_fringe = wavelength * camera.film_distance / span;
    const double pixel = camera.pixel_pitch();
    int n = std::clamp(int(std::floor(pixel / finest_fringe)) + 1, 1, kMaxFilmSubsamples);
    while (n < kMaxFilmSubsamples && detail::pixel_average_error(n, pixel / finest_fringe) > kPixelAverageError) ++n;
    return n;
}

}  // namespace wavecam
