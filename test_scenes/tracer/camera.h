// The ideal pinhole camera, with POV-Ray's convention (docs/platform_notes.md): pixel (i, j) of
// W x H looks along normalize(D + x R + y U), x = (i + 0.5)/W - 0.5, y = 0.5 - (j + 0.5)/H,
// D the unit view axis, |R| = 2 tan(fov/2), |U| = |R| H / W. Row 0 is the top of the image.
// The world is right-handed: R = D x up, U = R x D.
#pragma once
#include <array>
#include "vec3.h"

namespace wavecam::trace {

struct CameraSettings {
    Vec3 position{0, 0, 0};
    Vec3 look_at{0, 0, -1};
    Vec3 up{0, 1, 0};
    double fov_deg = 60;  // horizontal field of view
    int width = 256;
    int height = 256;
};

// Continuous image coordinates: column px in [0, W), row py in [0, H); the centre of pixel
// (i, j) is (i + 0.5, j + 0.5).
struct PixelPoint {
    double px = 0, py = 0;
};

class Camera {
public:
    explicit Camera(const CameraSettings& s);

    // Unnormalised direction D + x R + y U through image point (px, py).
    Vec3 direction(PixelPoint p) const;
    // Where a world point in front of the camera lands on the image (inverse of direction).
    PixelPoint project(Vec3 point) const;
    // Distance of a world point along the view axis (Blender's Z).
    double planar_depth(Vec3 point) const { return dot(point - position_, forward_); }

    Vec3 position() const { return position_; }
    Vec3 right_unit() const { return right_; }    // unit R
    Vec3 up_unit() const { return up_; }          // unit U
    double fov_deg() const { return fov_deg_; }
    int width() const { return width_; }
    int height() const { return height_; }

    // OpenEXR's worldToCamera (Imath row-vector convention, p_cam = p_world * M): camera
    // space has x right, y up, z along the view axis (left-handed, objects in front at z > 0).
    std::array<float, 16> world_to_camera() const;

private:
    Vec3 position_, forward_, right_, up_;
    double right_length_, up_length_, fov_deg_;
    int width_, height_;
};

}  // namespace wavecam::trace
