#include "finite_pinhole.h"

#include "wavecam/pinhole_camera.h"

namespace wavecam::trace {

namespace {
// Shirley & Chiu's concentric map, unit square to unit disc (keeps strata compact):
// P. Shirley, K. Chiu, "A Low Distortion Map Between Disk and Square", JGT 2(3), 1997.
void concentric_disc(double u1, double u2, double& dx, double& dy) {
    const double a = 2 * u1 - 1, b = 2 * u2 - 1;
    if (a == 0 && b == 0) {
        dx = dy = 0;
        return;
    }
    double r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = M_PI / 4 * (b / a);
    } else {
        r = b;
        phi = M_PI / 2 - M_PI / 4 * (a / b);
    }
    dx = r * std::cos(phi);
    dy = r * std::sin(phi);
}
}  // namespace

Ray pinhole_ray(const Camera& camera, const FinitePinhole& pinhole, PixelPoint p, double u1, double u2) {
    const Vec3 chief = camera.direction(p);
    if (pinhole.diameter <= 0) return {camera.position(), chief};
    double dx, dy;
    concentric_disc(u1, u2, dx, dy);
    const double radius = pinhole.diameter / 2;
    const Vec3 a = camera.right_unit() * (dx * radius) + camera.up_unit() * (dy * radius);
    return {camera.position() + a, chief + a / pinhole.film_distance};
}

double blur_disc_pixels(const Camera& camera, const FinitePinhole& pinhole, double z) {
    const PinholeCamera film{camera.width(), camera.height(), camera.fov_deg() * M_PI / 180, pinhole.film_distance};
    return pinhole.diameter * (1 + pinhole.film_distance / z) / film.pixel_pitch();
}

}  // namespace wavecam::trace
