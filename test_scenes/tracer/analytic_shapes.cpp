#include "analytic_shapes.h"
#include <utility>

namespace wavecam::trace {

double intersect_sphere(Vec3 o, Vec3 d, Vec3 centre, double radius, double t_min, double t_max) {
    const Vec3 oc = o - centre;
    const double a = dot(d, d), b = dot(d, oc), k = dot(oc, oc) - radius * radius;
    const double disc = b * b - a * k;
    if (disc < 0) return -1;
    const double q = -b - std::copysign(std::sqrt(disc), b);
    double t0 = q / a, t1 = q != 0 ? k / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_min && t0 < t_max) return t0;
    if (t1 > t_min && t1 < t_max) return t1;
    return -1;
}

double intersect_plane(Vec3 o, Vec3 d, Vec3 point, Vec3 normal, double t_min, double t_max) {
    const double dn = dot(d, normal);
    if (dn == 0) return -1;
    const double t = dot(point - o, normal) / dn;
    return t > t_min && t < t_max ? t : -1;
}

}  // namespace wavecam::trace
