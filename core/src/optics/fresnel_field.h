// The geometry of one field-PSF request that both evaluations of the Fresnel integral share
// (the matrix Fourier transform, fresnel_mft.cpp, and the transfer function,
// fresnel_transfer.cpp; the derivation is in wavecam/fresnel_psf.h). Internal to core.
#pragma once
#include "wavecam/fresnel_psf.h"

namespace wavecam::detail {

// The request's geometry, shared by both evaluations (see wavecam/fresnel_psf.h for the derivation).
struct FieldGeometry {
    double c = 1;              // cos theta
    double alpha = 0;          // 1/z + 1/f
    double ar = 0, at = 0;     // chirp rates c^3 alpha (radial), c alpha (tangential)
    double er_x = 1, er_y = 0;  // radial unit vector in image (column, row) axes
    double span = 0;           // the aperture's largest width
    double area = 0;           // the aperture's area: the transmitted power, per unit irradiance
};

FieldGeometry geometry_of(const FieldPsfRequest& q);

// Film radius (m) holding `energy` of the PSF: the shadow's radius plus the sharp edge's tail,
// light beyond the rim by s being at most 2 lambda f / (pi^2 D s) of the power, stretched
// 1/cos^3 off axis (see psf_kernel_radius in wavecam/fresnel_psf.h).
double psf_radius(const Aperture& aperture, double film_distance, double depth, double wavelength, double cos_theta,
                  double energy = kPsfKernelEnergy);

// Rotationally symmetric (circle, zone plate): the same in the (r, t) axes of every field
// azimuth and even in each.
bool mirror_symmetric(const Aperture& a);

// t(-x, -y) = t(x, y): a regular polygon of even N, a square, or any mirror-symmetric pupil.
bool point_symmetric(const Aperture& a);

}  // namespace wavecam::detail
