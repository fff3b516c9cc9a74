// Kaiser-windowed sinc interpolation on the lattice (band_limited_stencil.h).
#include "summation/nufft/band_limited_stencil.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <initializer_list>
#include <map>
#include <mutex>
#include <utility>

namespace wavecam::detail {
namespace {

// Modified Bessel function I0 by its power series (terms fall fast for the beta used, < 40).
double bessel_i0(double x) {
    double term = 1, sum = 1;
    for (int k = 1; k < 200 && term > 1e-17 * sum; ++k) {
        term *= (x / (2 * k)) * (x / (2 * k));
        sum += term;
    }
    return sum;
}

constexpr int kMaxHalfWidth = 24;  // 48 points: bands to 0.95 pi at 1e-2

}  // namespace

double BandLimitedStencil::kernel(double t) const {
    const double r = t / half_width_;
    if (std::fabs(r) >= 1) return 0;
    const double sinc = t == 0 ? 1.0 : std::sin(M_PI * t) / (M_PI * t);
    return sinc * bessel_i0(beta_ * std::sqrt(1 - r * r)) / bessel_i0(beta_);
}

long BandLimitedStencil::weights(double x, double* w) const {
    const long first = long(std::floor(x)) - half_width_ + 1;
    for (int i = 0; i < width(); ++i) w[i] = kernel(x - double(first + i));
    return first;
}

// The largest |sum_m kappa(x - m) exp(i nu m) - exp(i nu x)| over 16 positions in a cell and
// 16 W + 1 frequencies across the band (the error ripples about W times across it; the weights
// once per position, the exponentials by recurrence).
double BandLimitedStencil::error_of(double nu_max) const {
    double worst = 0, w[2 * kMaxHalfWidth];
    for (int b = 0; b < 16; ++b) {
        const double x = (b + 0.5) / 16;
        const long first = weights(x, w);
        const int steps = 16 * half_width_;
        for (int a = 0; a <= steps; ++a) {
            const double nu = nu_max * (2.0 * a / steps - 1.0);
            const std::complex<double> step = std::polar(1.0, nu);
            std::complex<double> e = std::polar(1.0, nu * double(first)), s = 0;
            for (int i = 0; i < width(); ++i, e *= step) s += w[i] * e;
            worst = std::max(worst, std::abs(s - std::polar(1.0, nu * x)));
        }
    }
    return worst;
}

void BandLimitedStencil::design(double nu_max, double tolerance) {
    for (int W = 2; W <= kMaxHalfWidth; ++W) {
        half_width_ = W;
        // the window's smear against the room left above the band: a few ratios tried
        double best = INFINITY, best_beta = 0;
        for (double c : {0.6, 0.7, 0.8, 0.9, 1.0}) {
            beta_ = c * W * (M_PI - nu_max);
            const double e = error_of(nu_max);
            if (e < best) best = e, best_beta = beta_;
        }
        beta_ = best_beta;
        error_ = best;
        if (best <= tolerance) return;
    }
    half_width_ = 0;
}

BandLimitedStencil::BandLimitedStencil(double nu_max, double tolerance) {
    nu_max = std::fabs(nu_max);
    if (!(nu_max < M_PI) || !(tolerance > 0)) return;
    // Every sum's plan asks for a stencil (the kernel summation's kernels: two plans per anchor and
    // layer), and each design checks its error over the band, milliseconds each. A stencil serves
    // any band within its own at any tolerance above its own, so designs are kept for bands
    // rounded up to pi / 256 and tolerances rounded down to powers of 2^(1/4), and shared.
    const double band = std::ceil(nu_max * 256 / M_PI) * M_PI / 256;
    const double tol = std::exp2(std::floor(4 * std::log2(tolerance)) / 4);
    if (band < M_PI) {
        static std::mutex guard;
        static std::map<std::pair<double, double>, BandLimitedStencil> designed;
        bool known = false;
        {
            std::lock_guard<std::mutex> lock(guard);
            if (auto it = designed.find({band, tol}); it != designed.end()) *this = it->second, known = true;
        }
        if (!known) {
            design(band, tol);
            std::lock_guard<std::mutex> lock(guard);
            designed.emplace(std::pair{band, tol}, *this);
        }
        if (usable()) return;
    }
    design(nu_max, tolerance);  // (the rounded band reached no stencil; the band itself may)
}

}  // namespace wavecam::detail
