// The image of one point source: `wavecam psf`, and the reference for every other path.
#pragma once
#include "wavecam/summation_plan.h"
#include <cmath>
#include <string>
#include <vector>
#include "wavecam/aperture.h"
#include "wavecam/progress.h"
#include "wavecam/result.h"

namespace wavecam {

struct PsfParams {
    Aperture aperture{ApertureShape::Circle, 0.3e-3};
    double film_distance = 65e-3;    // f, metres
    double source_distance = INFINITY;  // along the source's ray from the pinhole centre; inf = plane wave
    double source_angle = 0.0;       // field angle in the x-z plane, radians
    double wavelength = 550e-9;
    double film_size = 0.6e-3;       // width of the square film window, centred on the geometric image
    int resolution = 255;            // pixels across; odd puts a pixel on the geometric image point
    double sin_theta_max = 1.0;      // aperture sampling at lambda / (2 sin theta_max)
    double max_terms = 5e12;         // refuse work beyond this many terms (samples x film points)
    int nthreads = 0;                // 0 = every core
    Summation summation = Summation::Auto;  // how the two sums are evaluated (summation_plan.h)
};

struct PsfImage {
    std::vector<float> irradiance;  // relative irradiance, row-major, upright (row 0 = top)
    int resolution = 0;
    double pixel_pitch = 0;         // metres on the film
    double centre_x = 0, centre_y = 0;  // geometric image point on the film (m)
    size_t sample_count = 0;
    double sample_pitch = 0;
    double fresnel_number = 0;
    double peak = 0;
    double seconds = 0;
};

// Checks parameters; errors read "field: what was expected" with the field named as the
// command line names it (pinhole, film-distance, ...).
Result<bool> validate(const PsfParams& p);

// Terms (pinhole samples x film points) a PSF with these parameters costs.
double psf_terms(const PsfParams& p);

// Film position of pixel (i, j) of the upright image `img` (img.resolution pixels across,
// img.pixel_pitch apart, centred on (img.centre_x, img.centre_y)): column i grows toward the
// scene's +x, which the pinhole maps to film -x; row j grows downward in the scene, film +y.
inline void film_position(const PsfImage& img, int i, int j, double& x, double& y) {
    const int n = img.resolution;
    const double pitch = img.pixel_pitch, cx = img.centre_x, cy = img.centre_y;
    const double c = 0.5 * (n - 1);
    x = cx - (i - c) * pitch;
    y = cy + (j - c) * pitch;
}

// Computes the PSF, its two sums on `device` (compute_device.h: the direct terms on a GPU where
// it has one). Fails on invalid parameters, on the device, or when cancelled through `progress`.
Result<PsfImage> compute_psf(const PsfParams& p, const ComputeDevice& device, const ProgressFn& progress = {});

}  // namespace wavecam
