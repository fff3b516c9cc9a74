// Pinhole design formulas (docs/physics.md, result 5, and the seed paper section 3).
#pragma once

namespace wavecam {

// Number of half-period Fresnel zones the aperture of radius a spans for an on-axis source
// at distance z (inf allowed) and film distance f:
// N = 2 (sqrt(f^2 + a^2) - f + sqrt(z^2 + a^2) - z) / lambda, each difference in a
// cancellation-free form a^2 / (sqrt(d^2 + a^2) + d).
double fresnel_number(double radius, double film_distance, double source_distance, double wavelength);

// Rayleigh's classic optimum d = 1.9 sqrt(f lambda).
double rayleigh_optimal_diameter(double film_distance, double wavelength);

// The seed paper's Nyquist argument: d = sqrt(D lambda / 2) for a film of width D.
double nyquist_optimal_diameter(double film_width, double wavelength);

}  // namespace wavecam
