#include <cmath>
#include <string>

#include "wavecam/spectrum.h"

namespace wavecam {

namespace {
// The visible range sampled by default (m).
constexpr double kVisibleLow = 400e-9, kVisibleHigh = 700e-9;
}  // namespace

Result<SpectralSampling> visible_sampling(int count) {
    if (count < 1)
        return Result<SpectralSampling>::failure("wavelengths: expected at least 1 wavelength, got " +
                                                 std::to_string(count));
    SpectralSampling s;
    const double w = (kVisibleHigh - kVisibleLow) / count;
    for (int k = 0; k < count; ++k) {
        s.wavelength.push_back(kVisibleLow + (k + 0.5) * w);
        s.weight.push_back(w);
    }
    return Result<SpectralSampling>::success(s);
}

Result<SpectralSampling> explicit_sampling(const std::vector<double>& wavelengths) {
    const size_t n = wavelengths.size();
    if (n == 0) return Result<SpectralSampling>::failure("wavelengths: expected at least 1 wavelength");
    for (size_t k = 0; k < n; ++k) {
        if (!(wavelengths[k] > 0) || !std::isfinite(wavelengths[k]))
            return Result<SpectralSampling>::failure("wavelengths: expected positive finite wavelengths");
        if (k > 0 && !(wavelengths[k] > wavelengths[k - 1]))
            return Result<SpectralSampling>::failure("wavelengths: expected an increasing list");
    }
    SpectralSampling s;
    s.wavelength = wavelengths;
    for (size_t k = 0; k < n; ++k) {
        // The end samples mirror their one neighbour; a lone wavelength stands for the visible range.
        const double left = k > 0     ? wavelengths[k] - wavelengths[k - 1]
                            : n > 1   ? wavelengths[1] - wavelengths[0]
                                      : kVisibleHigh - kVisibleLow;
        const double right = k + 1 < n ? wavelengths[k + 1] - wavelengths[k] : left;
        s.weight.push_back(0.5 * (left + right));
    }
    return Result<SpectralSampling>::success(s);
}

Result<SpectralBasis> make_spectral_basis(const SpectralSampling& sampling, const Matrix3& xyz_to_rgb) {
    const int n = int(sampling.wavelength.size());
    if (sampling.weight.size() != sampling.wavelength.size())
        return Result<SpectralBasis>::failure("wavelengths: expected one weight per wavelength, got " +
                                              std::to_string(sampling.weight.size()) + " weights for " +
                                              std::to_string(n) + " wavelengths");
    if (n < 3)
        return Result<SpectralBasis>::failure("wavelengths: expected at least 3 wavelengths to carry RGB colour, got " +
                                              std::to_string(n));
    // Raw band p: exp(-(lambda - centre_p)^2 / (2 width^2)), one per primary R, G, B.
    constexpr double kCentre[3] = {610e-9, 545e-9, 465e-9}, kWidth = 40e-9;
    SpectralBasis b;
    b.wavelength_ = sampling.wavelength;
    std::vector<Vector3> raw(n);
    Matrix3 m{};  // column p: RGB of raw band p
    for (int s = 0; s < n; ++s) {
        const Vector3 cmf = cie1931_cmf(sampling.wavelength[s]);
        b.xyz_.push_back({cmf[0] * sampling.weight[s], cmf[1] * sampling.weight[s], cmf[2] * sampling.weight[s]});
        for (int p = 0; p < 3; ++p) {
            const double t = (sampling.wavelength[s] - kCentre[p]) / kWidth;
            raw[s][p] = std::exp(-0.5 * t * t);
        }
    }
    for (int p = 0; p < 3; ++p) {  // XYZ = sum_s raw_p(s) cmf(s) weight(s)
        Vector3 xyz{0, 0, 0};
        for (int s = 0; s < n; ++s)
            for (int k = 0; k < 3; ++k) xyz[k] += raw[s][p] * b.xyz_[s][k];
        const Vector3 rgb = multiply(xyz_to_rgb, xyz);
        for (int k = 0; k < 3; ++k) m[k][p] = rgb[k];
    }
    // Independence, scale-free: |det M| against its bound, the product of the column lengths.
    double column_lengths = 1;
    for (int p = 0; p < 3; ++p) column_lengths *= std::hypot(m[0][p], m[1][p], m[2][p]);
    if (!(std::fabs(determinant(m)) > 1e-9 * column_lengths))
        return Result<SpectralBasis>::failure("wavelengths: these " + std::to_string(n) +
                                              " wavelengths cannot carry RGB colour (the three bands' colours "
                                              "are not independent)");
    // Calibrated basis: b(s) = raw(s) . M^-1, so the RGB of the spectrum of (r, g, b) is M M^-1 (r, g, b).
    const Matrix3 mi = inverse(m);
    for (int s = 0; s < n; ++s) {
        Vector3 row{0, 0, 0};
        for (int q = 0; q < 3; ++q)
            for (int p = 0; p < 3; ++p) row[q] += raw[s][p] * mi[p][q];
        b.basis_.push_back(row);
    }
    return Result<SpectralBasis>::success(std::move(b));
}

}  // namespace wavecam
