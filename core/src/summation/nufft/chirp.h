// The path's chirp, the part of the path length the lattice's Fourier kernel leaves (the nufft
// evaluator, docs/summation.md). Internal to core.
//
// Path from a point at distance R along the unit direction u (in-plane components u) to a pinhole
// point xi (z = 0), exactly, with rho = 1/R and g = r / R:
//   g^2 = 1 - 2 rho u.xi + rho^2 |xi|^2,
//   r - R = (rho |xi|^2 - 2 u.xi) / (1 + g)                    (no cancellation),
//   psi = r - R + u.xi = rho (|xi|^2 + u.xi (rho |xi|^2 - 2 u.xi) / (1 + g)) / (1 + g),
// psi ~ rho (|xi|^2 - (u.xi)^2) / 2: the chirp, smooth in (u, rho). Sources: U(xi) = sum_s
// (c_s / R_s) exp(-i k u_s.xi) [exp(i k psi) / g]; film: U(t) = (f / R_t^2) sum_xi w(xi)
// exp(-i k n_t.xi) [exp(i k psi) / g^2], n_t = t / R_t, 1 / R_t = sqrt(1 - |n_t|^2) / f.
#pragma once
#include <algorithm>
#include <cmath>
#include <complex>

#include "base/sincos_turns.h"

namespace wavecam::detail {

using cfloat = std::complex<float>;

// The chirp at (x, y) for direction (ux, uy), inverse distance rho: psi and g = r / R.
struct Chirp {
    double psi, g;
};
inline Chirp chirp(double ux, double uy, double rho, double x, double y) {
    const double q2 = x * x + y * y, p = ux * x + uy * y;
    const double g = std::sqrt(std::max(1e-300, 1.0 - 2.0 * rho * p + rho * rho * q2));
    return {rho * (q2 + p * (rho * q2 - 2.0 * p) / (1.0 + g)) / (1.0 + g), g};
}

// The chirp's expansion about a sub-aperture's centre c: psi(xi) = psi(c) + grad psi(c).(xi - c)
// + psi2(xi), grad psi = (rho xi + (g - 1) u) / g (from d r / d xi = (xi - R u) / r). The first
// two terms are exact per point (a phase and a shift of its frequency); psi2, quadratic in
// xi - c, is what the nodes interpolate: over a sub-aperture of 1/B the width it varies B^2 less.
struct ChirpAtCentre {
    double psi, gx, gy, cx, cy, rho, ux, uy;
    ChirpAtCentre(double ux_, double uy_, double rho_, double cx_, double cy_)
        : cx(cx_), cy(cy_), rho(rho_), ux(ux_), uy(uy_) {
        const Chirp c = chirp(ux, uy, rho, cx, cy);
        const double q2 = cx * cx + cy * cy, p = ux * cx + uy * cy;
        const double gm1 = rho * (rho * q2 - 2.0 * p) / (1.0 + c.g);  // g - 1 without cancellation
        psi = c.psi;
        gx = (rho * cx + gm1 * ux) / c.g;
        gy = (rho * cy + gm1 * uy) / c.g;
    }
    // exp(i k psi2(x, y)) / g^power: the interpolated remainder (k psi2 a few radians at most:
    // its sine and cosine in float, sincos_turns.h, to about 1e-6).
    cfloat remainder(double x, double y, double inv_lambda, int power) const {
        const Chirp c = chirp(ux, uy, rho, x, y);
        const double psi2 = c.psi - psi - gx * (x - cx) - gy * (y - cy);
        float sn, cs;
        sincos_turns(float(psi2 * inv_lambda), sn, cs);
        const float a = float(power == 1 ? 1.0 / c.g : 1.0 / (c.g * c.g));
        return {a * cs, a * sn};
    }
};

// A film point's inverse distance from its direction components: 1 / R_t = sqrt(1 - |n|^2) / f.
inline double film_rho(double nx, double ny, double f) { return std::sqrt(std::max(0.0, 1.0 - nx * nx - ny * ny)) / f; }

}  // namespace wavecam::detail
