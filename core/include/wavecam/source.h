// Point sources in front of the pinhole (z > 0), mutually coherent within one list.
#pragma once
#include <cmath>
#include <vector>

namespace wavecam {

// One point source. A finite source at P radiates U = a exp(i (k r + phase)) / r, r = |P - xi|
// (docs/physics.md). A source at infinity is a plane wave a exp(i (k path + phase)) arriving along
// the unit direction (ux, uy, uz) that points from the pinhole toward the source.
struct PointSource {
    double x = 0, y = 0, z = 1;  // finite: position (m); infinite: unit direction
    bool at_infinity = false;
    double amplitude = 1.0;
    double phase = 0.0;  // radians
};

// A source seen at field angle `angle` (radians, in the x-z plane) at `distance` along its ray
// from the pinhole centre; distance = +inf gives a plane wave.
inline PointSource source_at_field_angle(double distance, double angle, double amplitude = 1.0) {
    PointSource s;
    s.at_infinity = std::isinf(distance);
    const double d = s.at_infinity ? 1.0 : distance;
    s.x = d * std::sin(angle);
    s.y = 0.0;
    s.z = d * std::cos(angle);
    s.amplitude = amplitude;
    return s;
}

// Geometric image point of a source on the film plane z = -f: x0 = -f (Px/Pz, Py/Pz).
inline void geometric_image_point(const PointSource& s, double film_distance, double& x0, double& y0) {
    x0 = -film_distance * s.x / s.z;
    y0 = -film_distance * s.y / s.z;
}

// Irradiance |U|^2 the source alone would give at the film centre (0, 0, -f) with no screen:
// the unit of a relative-irradiance PSF (docs/physics.md).
inline double free_irradiance_at_film_centre(const PointSource& s, double film_distance) {
    if (s.at_infinity) return s.amplitude * s.amplitude;
    const double dz = s.z + film_distance;
    return s.amplitude * s.amplitude / (s.x * s.x + s.y * s.y + dz * dz);
}

}  // namespace wavecam
