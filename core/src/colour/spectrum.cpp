#include <cmath>
#include <cstdio>
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

namespace {

// Jakob & Hanika's sigmoid, S(x) = 1/2 + x / (2 sqrt(1 + x^2)), and its derivative.
double sigmoid(double x) { return 0.5 + x / (2.0 * std::sqrt(1.0 + x * x)); }
double sigmoid_slope(double x) { return 0.5 / std::pow(1.0 + x * x, 1.5); }

// One primary's spectrum at the samples: exp(log_scale) S(c0 + c1 t + c2 t^2).
struct SigmoidSpectrum {
    double c[3] = {0, 0, 0}, log_scale = 0;
    double operator()(double t) const { return std::exp(log_scale) * sigmoid(c[0] + t * (c[1] + t * c[2])); }
};

double normalised(double wavelength) { return (wavelength - 550e-9) / 150e-9; }

// Fits `spectrum` so that its XYZ at the samples is `target`: Gauss-Newton on the four
// parameters with the minimum-norm step (three equations), from the current parameters, step
// halved until the residual falls. True when the relative residual is below 1e-12.
bool fit_sigmoid(const std::vector<double>& t, const std::vector<Vector3>& xyz, const Vector3& target,
                 SigmoidSpectrum& spectrum) {
    const double norm = std::hypot(target[0], target[1], target[2]);
    auto residual = [&](const SigmoidSpectrum& sp, Vector3& r) {
        r = {-target[0], -target[1], -target[2]};
        for (size_t s = 0; s < t.size(); ++s)
            for (int k = 0; k < 3; ++k) r[k] += sp(t[s]) * xyz[s][k];
        for (int k = 0; k < 3; ++k) r[k] /= norm;
        return std::hypot(r[0], r[1], r[2]);
    };
    Vector3 r;
    double err = residual(spectrum, r);
    for (int iteration = 0; iteration < 200 && err > 1e-12; ++iteration) {
        // J (3 x 4): d residual / d (c0, c1, c2, log_scale)
        double J[3][4] = {};
        for (size_t s = 0; s < t.size(); ++s) {
            const double x = spectrum.c[0] + t[s] * (spectrum.c[1] + t[s] * spectrum.c[2]);
            const double a = std::exp(spectrum.log_scale), d = a * sigmoid_slope(x), v = a * sigmoid(x);
            const double grad[4] = {d, d * t[s], d * t[s] * t[s], v};
            for (int k = 0; k < 3; ++k)
                for (int q = 0; q < 4; ++q) J[k][q] += grad[q] * xyz[s][k] / norm;
        }
        Matrix3 jjt{};  // J J^T, lightly damped
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                for (int q = 0; q < 4; ++q) jjt[i][j] += J[i][q] * J[j][q];
                if (i == j) jjt[i][j] *= 1.0 + 1e-12;
            }
        if (!(std::fabs(determinant(jjt)) > 1e-300)) return false;
        const Vector3 y = multiply(inverse(jjt), r);
        double step[4] = {};
        for (int q = 0; q < 4; ++q)
            for (int k = 0; k < 3; ++k) step[q] -= J[k][q] * y[k];
        bool improved = false;
        for (double h = 1.0; h > 1e-4 && !improved; h *= 0.5) {
            SigmoidSpectrum trial = spectrum;
            for (int q = 0; q < 3; ++q) trial.c[q] += h * step[q];
            trial.log_scale += h * step[3];
            Vector3 rt;
            const double e = residual(trial, rt);
            if (e < err) {
                spectrum = trial;
                r = rt;
                err = e;
                improved = true;
            }
        }
        if (!improved) break;
    }
    return err <= 1e-12 && std::fabs(spectrum.c[0]) + std::fabs(spectrum.c[1]) + std::fabs(spectrum.c[2]) < 1e6;
}

Vector3 column(const Matrix3& m, int p) { return {m[0][p], m[1][p], m[2][p]}; }

// Primary p's spectrum, continued from white (where a flat-ish sigmoid fits) out to the primary
// in kPrimarySteps steps, warm-started, as Jakob & Hanika fill their table from the centre.
// Returns the last step fitted (-1: none); `realised` is the working-space RGB it reached.
constexpr int kPrimarySteps = 20;
int fit_primary(int p, const std::vector<double>& t, const std::vector<Vector3>& xyz, const Matrix3& rgb_to_xyz,
                SigmoidSpectrum& sp, Vector3& realised) {
    const Vector3 white{1.0 / 3, 1.0 / 3, 1.0 / 3};
    double y_white = 0;
    for (const Vector3& s : xyz) y_white += 0.5 * s[1];
    sp.log_scale = std::log(multiply(rgb_to_xyz, white)[1] / y_white);
    int reached = -1;
    for (int k = 0; k <= kPrimarySteps; ++k) {
        const double alpha = 1.0 - double(k) / kPrimarySteps;  // share of white
        Vector3 rgb = white;
        for (int q = 0; q < 3; ++q) rgb[q] = alpha * white[q] + (1 - alpha) * (q == p ? 1.0 : 0.0);
        SigmoidSpectrum trial = sp;
        if (!fit_sigmoid(t, xyz, multiply(rgb_to_xyz, rgb), trial)) break;
        sp = trial;
        reached = k;
        realised = rgb;
    }
    return reached;
}

}  // namespace

std::string SpectralBasis::description() const {
    if (monochrome_) return "monochrome (every channel diffracted with the same light)";
    if (desaturation_[0] == 0 && desaturation_[1] == 0 && desaturation_[2] == 0)
        return "colour, non-negative spectra over the working space's whole gamut";
    char line[160];
    std::snprintf(line, sizeof line,
                  "colour, non-negative spectra inside a gamut whose primaries are pulled toward white by "
                  "R %.2f G %.2f B %.2f",
                  desaturation_[0], desaturation_[1], desaturation_[2]);
    return line;
}

Result<SpectralBasis> make_spectral_basis(const SpectralSampling& sampling, const Matrix3& xyz_to_rgb,
                                          bool monochrome) {
    const int n = int(sampling.wavelength.size());
    if (sampling.weight.size() != sampling.wavelength.size())
        return Result<SpectralBasis>::failure("wavelengths: expected one weight per wavelength, got " +
                                              std::to_string(sampling.weight.size()) + " weights for " +
                                              std::to_string(n) + " wavelengths");
    if (n < 1) return Result<SpectralBasis>::failure("wavelengths: expected at least 1 wavelength");
    if (!(std::fabs(determinant(xyz_to_rgb)) > 0))
        return Result<SpectralBasis>::failure("colorspace: the working space's XYZ -> RGB matrix is singular");
    const Matrix3 rgb_to_xyz = inverse(xyz_to_rgb);
    std::vector<Vector3> xyz(n);
    std::vector<double> t(n);
    for (int s = 0; s < n; ++s) {
        const Vector3 cmf = cie1931_cmf(sampling.wavelength[s]);
        for (int k = 0; k < 3; ++k) xyz[s][k] = cmf[k] * sampling.weight[s];
        t[s] = normalised(sampling.wavelength[s]);
    }

    SpectralBasis b;
    Matrix3 realised{};  // column p: working-space RGB of the realised primary p
    std::vector<SigmoidSpectrum> primaries(3);
    bool colour = !monochrome && n >= 3;
    for (int p = 0; p < 3 && colour; ++p) {
        Vector3 rgb{};
        const int reached = fit_primary(p, t, xyz, rgb_to_xyz, primaries[p], rgb);
        // Colour needs each primary at least half way from white; otherwise the wavelengths are
        // too close together to carry it (e.g. 549, 550, 551 nm): monochrome.
        if (reached < kPrimarySteps / 2) colour = false;
        for (int q = 0; q < 3; ++q) realised[q][p] = rgb[q];
        b.desaturation_[p] = 1.0 - double(reached) / kPrimarySteps;
    }
    if (colour && !(std::fabs(determinant(realised)) > 1e-6)) colour = false;

    if (colour) {
        // power(s, rgb) = sum_p spectrum_p(s) q_p, q = realised^-1 rgb (the colour in realised
        // primaries): exact round trip; q >= 0 inside the realised gamut.
        const Matrix3 to_realised = inverse(realised);
        b.wavelength_ = sampling.wavelength;
        b.xyz_ = xyz;
        for (int s = 0; s < n; ++s) {
            Vector3 row{0, 0, 0};
            for (int q = 0; q < 3; ++q)
                for (int p = 0; p < 3; ++p) row[q] += primaries[p](t[s]) * to_realised[p][q];
            b.basis_.push_back(row);
        }
        return Result<SpectralBasis>::success(std::move(b));
    }
    // Monochrome: sample (k, channel c) at wavelength k carries channel c's value x the
    // wavelength's share of the total weight, and contributes channel c's primary XYZ.
    double total = 0;
    for (double w : sampling.weight) total += w;
    b = SpectralBasis{};
    b.monochrome_ = true;
    for (int s = 0; s < n; ++s)
        for (int c = 0; c < 3; ++c) {
            b.wavelength_.push_back(sampling.wavelength[s]);
            Vector3 row{0, 0, 0};
            row[c] = sampling.weight[s] / total;
            b.basis_.push_back(row);
            b.xyz_.push_back(column(rgb_to_xyz, c));
        }
    return Result<SpectralBasis>::success(std::move(b));
}

}  // namespace wavecam
