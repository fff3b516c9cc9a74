// Colour as light: wavelength sampling, the CIE 1931 colour-matching functions, and the
// linear RGB -> spectrum basis that makes an ideal (delta) propagator return its input RGB.
#pragma once
#include <array>
#include <vector>
#include "wavecam/matrix3.h"
#include "wavecam/result.h"

namespace wavecam {

// CIE 1931 2-degree colour-matching functions x, y, z at `wavelength` (metres).
Vector3 cie1931_cmf(double wavelength);

// Wavelengths (m) and their quadrature weights (bin widths, m).
struct SpectralSampling {
    std::vector<double> wavelength, weight;
};

// `count` wavelengths evenly over 400-700 nm, at the centres of equal bins (midpoint rule).
Result<SpectralSampling> visible_sampling(int count);
// An explicit, increasing list; each weight spans halfway to its neighbours.
Result<SpectralSampling> explicit_sampling(const std::vector<double>& wavelengths);

// For each wavelength sample s and primary p, the spectral power b_p(s) per unit of that
// primary, and the XYZ that unit power at s contributes: cmf(s) x weight(s).
class SpectralBasis {
public:
    int size() const { return int(wavelength_.size()); }
    double wavelength(int s) const { return wavelength_[s]; }
    // Spectral power of linear RGB (r, g, b) at sample s; negative for some saturated colours.
    double power(int s, double r, double g, double b) const {
        return r * basis_[s][0] + g * basis_[s][1] + b * basis_[s][2];
    }
    const Vector3& xyz_per_power(int s) const { return xyz_[s]; }

    friend Result<SpectralBasis> make_spectral_basis(const SpectralSampling&, const Matrix3&);

private:
    std::vector<double> wavelength_;
    std::vector<Vector3> basis_, xyz_;
};

// Three smooth bands (Gaussians at 610, 545 and 465 nm, 40 nm wide) calibrated through the
// working space's XYZ -> RGB matrix: with M the RGB of the raw bands, the basis is
// raw x M^-1, so RGB -> spectrum -> XYZ -> RGB is the identity (needs >= 3 wavelengths).
Result<SpectralBasis> make_spectral_basis(const SpectralSampling& sampling, const Matrix3& xyz_to_rgb);

}  // namespace wavecam
