// Point-source images for the convolution method: Fresnel diffraction of the pupil with the wavefront's
// quadratic phase about the chief ray, as shares of the power through the pinhole.
//
// Method. The path source -> pupil point xi -> film point, expanded to second order in xi
// about the chief ray at field angle theta (planar source depth z, film distance f), is
//   r ~ r0 + (cos^3 theta alpha xi_r^2 + cos theta alpha xi_t^2) / 2
//          - xi_r d_r cos^3 theta / f - xi_t d_t cos theta / f,     alpha = 1/z + 1/f,
// with r, t the radial and tangential axes and d the film offset from the geometric image.
// So the PSF is |FT[P(xi) exp(i pi/lambda (cos^3 alpha xi_r^2 + cos alpha xi_t^2))]|^2 at
// frequencies (d_r cos^3 / (lambda f), d_t cos / (lambda f)): the on-axis Fresnel PSF,
// astigmatic in its defocus term and stretched 1/cos^3 radially, 1/cos tangentially.
// Two evaluations of the same integral, the cheaper one chosen per request (both are exact to
// the sampling stated in fresnel_mft.cpp and fresnel_transfer.cpp):
//  - few zones: a matrix Fourier transform of the sampled pupil onto exactly the output grid
//    needed (Soummer et al., Optics Express 15, 15935 (2007)); its pupil grid grows with the
//    zone count, so its cost does too;
//  - many zones: Fresnel propagation of the pupil by an FFT transfer function on a grid at a
//    fraction of a film pixel; its cost is set by the kernel's extent in film pixels.
// Validity: Fresnel number from ~0 to the geometric regime (the quadratic phase is exact in
// xi to second order); third-order terms (coma, xi^3 sin theta / r^2) are dropped, which
// holds while d^3 sin(theta) / (lambda f^2) << 1 - true for pinholes, whose d << f.
#pragma once
#include <cmath>
#include <vector>
#include "wavecam/aperture.h"

namespace wavecam {

enum class FieldPsfMethod { Auto, MatrixFourier, TransferFunction };  // Auto: the cheaper

struct FieldPsfRequest {
    Aperture aperture{ApertureShape::Circle, 0.0};
    double film_distance = 0;      // f (m)
    double depth = INFINITY;       // planar depth of the source (m); inf = plane wave
    double wavelength = 0;         // m
    double u = 0, v = 0;           // the source's direction in the tangent plane (right, up)
    double pixel_pitch = 0;        // film pixel pitch (m)
    int radius = 8;                // kernel half-width in pixels
    int subsamples = 3;            // each kernel pixel averages n x n points over its area
    int pupil_samples = 0;         // matrix transform's pupil grid; 0 = enough for its Fresnel zones
    FieldPsfMethod method = FieldPsfMethod::Auto;
    int transfer_grid = 0;         // the transfer function's grid at least this wide (share_transfer_grids)
};

// (2 radius + 1)^2 weights, row-major, upright image orientation (column a grows toward the
// scene's +x, row b downward), centred on the geometric image. Each weight is the fraction of
// the power through the pinhole that lands on that pixel (Parseval over the pupil, nothing
// renormalised): they sum to the share of the PSF inside the kernel, below 1 when it cuts a tail.
struct PsfKernel {
    int radius = 0;
    std::vector<float> weight;
    // The half-width (m) of the film square about the image beyond which the weights hold none of
    // the PSF: the matrix transform covers only the PSF's own kPsfKernelEnergy radius where that is
    // less than the kernel (pixels far wider than the PSF), so the weights then sum to the share
    // within `reach`, not within the kernel. Infinite where they cover the kernel.
    double reach = INFINITY;
    float at(int a, int b) const { return weight[size_t(b + radius) * (2 * radius + 1) + (a + radius)]; }
};

PsfKernel field_psf_kernel(const FieldPsfRequest& request);

// Requests at one depth through one aperture (a table's wavelengths and field anchors): sets
// each one's transfer_grid so that the transfer function's grids come in a few common sizes,
// widest first, each at most kSharedGridArea times a member's own grid in area (a wider period
// only moves the wrap-around farther away). Requests on one size share their pupil's spectrum
// (a forward transform costs about twice an inverse one), and each request's kernel depends on
// the set alone, not on which requests its thread served before: the same image however the
// work is spread over threads.
constexpr double kSharedGridArea = 1.25;
void share_transfer_grids(std::vector<FieldPsfRequest>& requests);

// The working memory (bytes) field_psf_kernel needs for `request` on one thread, by the method
// it would choose (the matrix transform's grids, or the transfer function's n x n arrays and
// the spectra each thread keeps): what a plan's memory estimate counts before building a table.
double field_psf_scratch_bytes(const FieldPsfRequest& request);

// Share of the PSF's power that a kernel of psf_kernel_radius holds, at least.
constexpr double kPsfKernelEnergy = 0.97;

// The widest PSF of a set of sources through `aperture` at `film_distance`: every depth >=
// nearest_depth, wavelength <= `wavelength` and field angle up to acos(cos_theta_max); `energy`,
// the share of its power a kernel is to hold.
struct WidestPsf {
    const Aperture& aperture;
    double film_distance, nearest_depth, wavelength, cos_theta_max;
    double energy = kPsfKernelEnergy;
};

// Kernel half-width (pixels of `pixel_pitch`) that holds psf.energy of `psf`: the
// geometric shadow's radius (span/2)(1 + f/z) plus the diffraction tail. A sharp edge sends a
// share 2 lambda f / (pi^2 D s) of the power farther than s beyond the shadow's rim (the Airy
// tail 1 - EE = J0^2 + J1^2 ~ 2 / (pi x), x = pi D r / (lambda f), Born & Wolf 8.5.2; for a
// straight edge the Fresnel integrals give half of it, one side only), stretched 1/cos^3 off
// axis; the kernel square holds more than its inscribed disc. `max_radius` is only a safety
// bound: a kernel cut there holds less.
int psf_kernel_radius(const WidestPsf& psf, double pixel_pitch, int max_radius);

}  // namespace wavecam
