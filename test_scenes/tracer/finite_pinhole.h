// Ray-optics finite pinhole: a disc of diameter d in the plane through the camera position
// normal to the view axis, film at distance f behind it. The film point of image point p
// sits at -f c (c = D + x R + y U, the chief ray); the ray from it through the pinhole point A
// has direction A - (-f c) = f c + A, i.e. c + A / f, and starts at A.
// A scene point at planar depth z images into a disc of diameter d (1 + f/z) on the film:
// d (1 + f/z) / (2 f tan(fov/2) / W) pixels.
#pragma once
#include "camera.h"

namespace wavecam::trace {

struct FinitePinhole {
    double diameter = 0;       // metres; 0 = ideal pinhole
    double film_distance = 0;  // metres
};

struct Ray {
    Vec3 origin;
    Vec3 direction;  // not necessarily unit length
};

// The ray from image point p through the pinhole point at disc sample (u1, u2) in [0,1)^2.
Ray pinhole_ray(const Camera& camera, const FinitePinhole& pinhole, PixelPoint p, double u1, double u2);

// Diameter in pixels of the blur disc of a point at planar depth z (infinite z: d / pitch).
double blur_disc_pixels(const Camera& camera, const FinitePinhole& pinhole, double z);

}  // namespace wavecam::trace
