#include "shading.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include "sky.h"

namespace wavecam::trace {

namespace {
// Shadow rays start this far off the surface (relative to the coordinates' size) to stay
// clear of float round-off in Embree's intersections.
Vec3 lifted(const SurfaceHit& hit) {
    const double size = std::max({1.0, std::abs(hit.position.x), std::abs(hit.position.y), std::abs(hit.position.z)});
    return hit.position + hit.geometric * (1e-4 * size);
}

// Orthonormal basis around unit n: Duff et al., "Building an Orthonormal Basis, Revisited",
// JCGT 6(1), 2017.
void basis(Vec3 n, Vec3& t, Vec3& b) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), c = n.x * n.y * a;
    t = {1 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

// Malley's method: a uniform disc point lifted to the hemisphere gives pdf cos / pi.
Vec3 cosine_direction(Vec3 n, double u1, double u2) {
    const double r = std::sqrt(u1), phi = 2 * M_PI * u2;
    Vec3 t, b;
    basis(n, t, b);
    return t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1 - r * r));
}
}  // namespace

Vec3 shade(const Scene& scene, const TraceScene& geometry, const SurfaceHit& hit, const LightSamples& samples) {
    const Vec3 origin = lifted(hit);
    Vec3 irradiance;
    for (const PointLight& light : scene.point_lights) {
        const Vec3 w = light.position - hit.position;
        const double r2 = dot(w, w), cos_s = dot(hit.normal, w) / std::sqrt(r2);
        if (cos_s > 0 && !geometry.occluded(origin, light.position - origin, 1.0))
            irradiance += light.intensity * (cos_s / r2);
    }
    for (const AreaLight& light : scene.area_lights) {
        const Vec3 area_normal = cross(light.edge_u, light.edge_v);  // |.| = area
        const Vec3 point = light.corner + light.edge_u * samples.area_u + light.edge_v * samples.area_v;
        const Vec3 w = point - hit.position;
        const double r2 = dot(w, w), r = std::sqrt(r2);
        const double cos_s = dot(hit.normal, w) / r, cos_l_area = -dot(area_normal, w) / r;
        // E = L cos_s cos_l A / r^2 for one uniform sample over the area A.
        if (cos_s > 0 && cos_l_area > 0 && !geometry.occluded(origin, point - origin, 1.0))
            irradiance += light.radiance * (cos_s * cos_l_area / r2);
    }
    Vec3 radiance = hit.albedo * irradiance / M_PI;
    const Vec3 w = cosine_direction(hit.normal, samples.sky_u, samples.sky_v);
    if (dot(w, hit.geometric) > 0 && !geometry.occluded(origin, w, std::numeric_limits<double>::infinity()))
        radiance += hit.albedo * sky_radiance(scene.sky, w);
    return radiance;
}

}  // namespace wavecam::trace
