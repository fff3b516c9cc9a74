// Measures on a PSF image, written independently of core's propagation code: sums over
// pixels, centroids and azimuthal profiles on the film grid.
#pragma once
#include <vector>
#include "wavecam/psf.h"

namespace wavecam::test {

// Integral of relative irradiance over pixels whose centres lie within `radius` of the
// window centre (film metres^2); radius < 0 means the whole window.
double encircled_energy(const PsfImage& img, double radius = -1.0);

// Irradiance-weighted centroid, as an offset from the window centre in film coordinates (m).
void centroid_offset(const PsfImage& img, double& dx, double& dy);

// Mean irradiance in annuli of width `bin` around the window centre.
std::vector<double> azimuthal_profile(const PsfImage& img, double bin);

// Mean irradiance over pixels with centre distance in [r0, r1).
double mean_in_annulus(const PsfImage& img, double r0, double r1);

}  // namespace wavecam::test
