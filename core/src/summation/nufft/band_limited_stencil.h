// Values of a band-limited function off the pinhole lattice from its values on it: for every
// frequency |nu| <= nu_max (radians per lattice step, nu_max < pi: the lattice oversamples),
//   exp(i nu x) ~= sum_m kappa(x - m) exp(i nu m),  kappa(t) = sinc(t) I0(beta sqrt(1 - (t/W)^2)) / I0(beta),
// |t| < W: a sinc cut to 2W lattice points by a Kaiser window, which smears the sinc's flat band
// by about beta / W, so beta = W (pi - nu_max) keeps |nu| <= nu_max flat (Kaiser, "Nonrecursive
// digital filter design using the I0-sinh window function", IEEE ISCAS 1974; the oversampling
// argument of docs/summation.md). W is the least (up to 24) whose error, checked here over
// the band and the cell, is within the tolerance. The nufft evaluator's use: rim samples (a cell's
// open part's centroid) spread onto, or read from, the lattice around them. Internal to core.
#pragma once

namespace wavecam::detail {

class BandLimitedStencil {
public:
    BandLimitedStencil(double nu_max, double tolerance);
    bool usable() const { return half_width_ > 0; }  // false: no W up to 24 reaches the tolerance
    int width() const { return 2 * half_width_; }
    double error() const { return error_; }
    // The width() weights for a point at lattice coordinate x; returns the first lattice index.
    long weights(double x, double* w) const;

private:
    BandLimitedStencil() = default;
    void design(double nu_max, double tolerance);
    double kernel(double t) const;
    double error_of(double nu_max) const;
    int half_width_ = 0;
    double beta_ = 0, error_ = 0;
};

}  // namespace wavecam::detail
