#include "wavecam/pinhole_design.h"

#include <cmath>

namespace wavecam {
namespace {
// sqrt(d^2 + a^2) - d without cancellation; 0 for d = inf.
double sagitta(double d, double a) { return std::isinf(d) ? 0.0 : a * a / (std::sqrt(d * d + a * a) + d); }
}  // namespace

double fresnel_number(double radius, double film_distance, double source_distance, double wavelength) {
    return 2.0 * (sagitta(film_distance, radius) + sagitta(source_distance, radius)) / wavelength;
}

double rayleigh_optimal_diameter(double film_distance, double wavelength) {
    return 1.9 * std::sqrt(film_distance * wavelength);
}

double nyquist_optimal_diameter(double film_width, double wavelength) {
    return std::sqrt(film_width * wavelength / 2.0);
}

}  // namespace wavecam
