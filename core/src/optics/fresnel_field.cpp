#include "optics/fresnel_field.h"

#include <cmath>

namespace wavecam::detail {

FieldGeometry geometry_of(const FieldPsfRequest& q) {
    FieldGeometry g;
    const double tan2 = q.u * q.u + q.v * q.v;
    g.c = 1.0 / std::sqrt(1.0 + tan2);
    g.alpha = (std::isinf(q.depth) ? 0.0 : 1.0 / q.depth) + 1.0 / q.film_distance;
    g.ar = g.c * g.c * g.c * g.alpha;
    g.at = g.c * g.alpha;
    const double rn = std::sqrt(tan2);  // any axis on axis
    if (rn > 0) {
        g.er_x = q.u / rn;
        g.er_y = -q.v / rn;
    }
    g.span = 2 * q.aperture.bounding_radius();
    g.area = q.aperture.area();
    return g;
}

double psf_radius(const Aperture& aperture, double film_distance, double depth, double wavelength, double cos_theta,
                  double energy) {
    const double span = 2 * aperture.bounding_radius();
    const double shadow = 0.5 * span * (1.0 + film_distance / depth);
    const double tail = 2 * wavelength * film_distance / (M_PI * M_PI * aperture.diameter * (1 - energy));
    return shadow + tail / std::pow(cos_theta, 3);
}

bool mirror_symmetric(const Aperture& a) {
    return a.shape == ApertureShape::Circle || a.shape == ApertureShape::ZonePlate;
}

bool point_symmetric(const Aperture& a) {
    return mirror_symmetric(a) || a.shape == ApertureShape::Square ||
           (a.shape == ApertureShape::Polygon && a.sides % 2 == 0);
}

}  // namespace wavecam::detail
