// Exact ray intersections with spheres and infinite planes, in double precision, for rays
// o + t d with d of any length. Returns the smallest t in (t_min, t_max), or a negative value.
#pragma once
#include "vec3.h"

namespace wavecam::trace {

// |o + t d - c|^2 = r^2: a t^2 + 2 b t + k = 0 with a = d.d, b = d.(o - c), k = |o - c|^2 - r^2.
// The two roots as k / q and q / a with q = -b - sign(b) sqrt(b^2 - a k) avoid cancellation
// (Numerical Recipes 5.6).
double intersect_sphere(Vec3 o, Vec3 d, Vec3 centre, double radius, double t_min, double t_max);

// (o + t d - p).n = 0: t = (p - o).n / d.n.
double intersect_plane(Vec3 o, Vec3 d, Vec3 point, Vec3 normal, double t_min, double t_max);

}  // namespace wavecam::trace
