#include <cmath>

#include "wavecam/spectrum.h"

namespace wavecam {
namespace {
// Piecewise Gaussian: sigma1 below the mean, sigma2 above.
double lobe(double nm, double mean, double sigma1, double sigma2) {
    const double t = (nm - mean) / (nm < mean ? sigma1 : sigma2);
    return std::exp(-0.5 * t * t);
}
}  // namespace

// CIE 1931 2-degree colour-matching functions, multi-lobe fit of Wyman, Sloan & Shirley,
// "Simple Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2), 2013:
// x, y, z are sums of piecewise Gaussians (mean, sigma below, sigma above, in nm), within a
// few percent of each function's peak of the CIE table (checked in tests/core/test_spectrum.cpp).
Vector3 cie1931_cmf(double wavelength) {
    const double nm = wavelength * 1e9;
    const double x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
                     0.065 * lobe(nm, 501.1, 20.4, 26.2);
    const double y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    const double z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
    return {x, y, z};
}

}  // namespace wavecam
