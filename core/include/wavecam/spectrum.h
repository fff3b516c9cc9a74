// Colour as light: wavelength sampling, the CIE 1931 colour-matching functions, and the
// linear RGB -> spectrum basis that makes an ideal (delta) propagator return its input RGB.
#pragma once
#include <algorithm>
#include <array>
#include <string>
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
//
// Colour (the default): three smooth, non-negative spectra, one per primary of the working
// space, each of the Jakob-Hanika form a S(c0 + c1 t + c2 t^2), S(x) = 1/2 + x / (2 sqrt(1 + x^2)),
// t = (lambda - 550 nm) / 150 nm (Jakob & Hanika 2019, "A Low-Dimensional Function Space for
// Efficient Spectral Upsampling"; pbrt-v4 and Mitsuba 3 use it per colour). We fit it once per
// PRIMARY, not per pixel, so the basis stays linear in RGB - the convolution method folds the wavelength
// sum into RGB -> XYZ kernels through power(s, r, g, b) with unit primaries - and every
// non-negative RGB is a non-negative spectrum. Linear also means emitted values above 1 need no
// rescaling (a per-colour fit bounds S by 1 and must scale by the maximum; a sum of fixed
// spectra does not). The fit matches each primary's XYZ exactly at the sampled wavelengths, so
// RGB -> spectrum -> XYZ -> RGB is the identity.
// Out of gamut: a primary that no non-negative spectrum at these wavelengths can reach (a wide
// working space such as ACEScg, or few wavelengths) is pulled toward white until one can; the
// basis is then calibrated by the inverse of the realised primaries, so the round trip stays
// exact, colours inside the realised gamut stay non-negative and colours beyond it carry a
// negative share of a primary (the scene-sum methods diffract that share separately and subtract).
// Monochrome: every channel is diffracted with the same light - the sampled wavelengths'
// weighted mean PSF - as three virtual samples per wavelength, one per channel: power(s, rgb)
// is one channel's value, xyz_per_power(s) that channel's primary's XYZ. Grey in, grey out.
class SpectralBasis {
public:
    int size() const { return int(wavelength_.size()); }
    double wavelength(int s) const { return wavelength_[s]; }
    double shortest_wavelength() const { return *std::min_element(wavelength_.begin(), wavelength_.end()); }
    double longest_wavelength() const { return *std::max_element(wavelength_.begin(), wavelength_.end()); }
    // Spectral power of linear RGB (r, g, b) at sample s: non-negative for non-negative RGB inside
    // the realised gamut (the working space's own whenever desaturation() is all zero).
    double power(int s, double r, double g, double b) const {
        return r * basis_[s][0] + g * basis_[s][1] + b * basis_[s][2];
    }
    const Vector3& xyz_per_power(int s) const { return xyz_[s]; }
    bool monochrome() const { return monochrome_; }
    // How far each primary (R, G, B) was pulled toward white to be made of non-negative light:
    // 0 = the working space's primary itself.
    const Vector3& desaturation() const { return desaturation_; }
    // One line for headers: "colour, full gamut", "colour, primaries desaturated R 0 G 0.15 B 0",
    // "monochrome".
    std::string description() const;

    friend Result<SpectralBasis> make_spectral_basis(const SpectralSampling&, const Matrix3&, bool);

private:
    std::vector<double> wavelength_;
    std::vector<Vector3> basis_, xyz_;
    bool monochrome_ = false;
    Vector3 desaturation_{0, 0, 0};
};

// The basis for these wavelengths and working space (its XYZ -> RGB matrix). Monochrome when
// asked, or when fewer than 3 wavelengths are given, or when they cannot carry colour (all
// within a few nm: no primary can be reached even half way from white).
Result<SpectralBasis> make_spectral_basis(const SpectralSampling& sampling, const Matrix3& xyz_to_rgb,
                                          bool monochrome = false);

}  // namespace wavecam
