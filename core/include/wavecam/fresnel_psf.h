// Point-source images for the fast path, by a matrix Fourier transform of the sampled pupil
// with the wavefront's quadratic phase (Fresnel diffraction about the chief ray).
//
// Method. The path source -> pupil point xi -> film point, expanded to second order in xi
// about the chief ray at field angle theta (planar source depth z, film distance f), is
//   r ~ r0 + (cos^3 theta alpha xi_r^2 + cos theta alpha xi_t^2) / 2
//          - xi_r d_r cos^3 theta / f - xi_t d_t cos theta / f,     alpha = 1/z + 1/f,
// with r, t the radial and tangential axes and d the film offset from the geometric image.
// So the PSF is |FT[P(xi) exp(i pi/lambda (cos^3 alpha xi_r^2 + cos alpha xi_t^2))]|^2 at
// frequencies (d_r cos^3 / (lambda f), d_t cos / (lambda f)): the on-axis Fresnel PSF,
// astigmatic in its defocus term and stretched 1/cos^3 radially, 1/cos tangentially.
// The transform is evaluated on exactly the output grid needed by a matrix Fourier transform
// (Soummer et al., Optics Express 15, 15935 (2007)), not an FFT with its fixed sampling.
// Validity: Fresnel number from ~0 to the geometric regime (the quadratic phase is exact in
// xi to second order); third-order terms (coma, xi^3 sin theta / r^2) are dropped, which
// holds while d^3 sin(theta) / (lambda f^2) << 1 - true for pinholes, whose d << f.
#pragma once
#include <cmath>
#include <vector>
#include "wavecam/aperture.h"

namespace wavecam {

struct FieldPsfRequest {
    Aperture aperture{ApertureShape::Circle, 0.0};
    double film_distance = 0;      // f (m)
    double depth = INFINITY;       // planar depth of the source (m); inf = plane wave
    double wavelength = 0;         // m
    double u = 0, v = 0;           // the source's direction in the tangent plane (right, up)
    double pixel_pitch = 0;        // film pixel pitch (m)
    int radius = 8;                // kernel half-width in pixels
    int subsamples = 3;            // each kernel pixel averages n x n points over its area
    int pupil_samples = 0;         // pupil grid across the aperture; 0 = enough for its Fresnel zones
};

// (2 radius + 1)^2 weights, row-major, upright image orientation (column a grows toward the
// scene's +x, row b downward), centred on the geometric image; they sum to 1.
struct PsfKernel {
    int radius = 0;
    std::vector<float> weight;
    float at(int a, int b) const { return weight[size_t(b + radius) * (2 * radius + 1) + (a + radius)]; }
};

PsfKernel field_psf_kernel(const FieldPsfRequest& request);

// Kernel half-width (pixels) that holds the PSF: the geometric shadow d (1 + f/z) stretched
// 1/cos^3, plus five Airy radii, capped at `max_radius`.
int psf_kernel_radius(const Aperture& aperture, double film_distance, double nearest_depth, double wavelength,
                      double cos_theta_max, double pixel_pitch, int max_radius);

}  // namespace wavecam
