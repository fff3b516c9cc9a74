#include "camera.h"

namespace wavecam::trace {

Camera::Camera(const CameraSettings& s)
    : position_(s.position),
      forward_(normalize(s.look_at - s.position)),
      right_(normalize(cross(forward_, s.up))),
      up_(cross(right_, forward_)),
      right_length_(2 * std::tan(s.fov_deg * M_PI / 360)),
      up_length_(right_length_ * s.height / s.width),
      fov_deg_(s.fov_deg),
      width_(s.width),
      height_(s.height) {}

Vec3 Camera::direction(PixelPoint p) const {
    const double x = p.px / width_ - 0.5;
    const double y = 0.5 - p.py / height_;
    return forward_ + right_ * (x * right_length_) + up_ * (y * up_length_);
}

PixelPoint Camera::project(Vec3 point) const {
    const Vec3 v = point - position_;
    const double z = dot(v, forward_);
    const double x = dot(v, right_) / (z * right_length_);
    const double y = dot(v, up_) / (z * up_length_);
    return {(x + 0.5) * width_, (0.5 - y) * height_};
}

std::array<float, 16> Camera::world_to_camera() const {
    const Vec3 axes[3] = {right_, up_, forward_};
    std::array<float, 16> m{};
    for (int c = 0; c < 3; ++c) {
        m[0 * 4 + c] = static_cast<float>(axes[c].x);
        m[1 * 4 + c] = static_cast<float>(axes[c].y);
        m[2 * 4 + c] = static_cast<float>(axes[c].z);
        m[3 * 4 + c] = static_cast<float>(-dot(axes[c], position_));
    }
    m[15] = 1;
    return m;
}

}  // namespace wavecam::trace
