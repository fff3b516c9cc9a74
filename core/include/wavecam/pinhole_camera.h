// The ideal pinhole camera a render was made with, and the physical camera it becomes:
// pixel rays, pixel solid angles, and the film position of each output pixel.
#pragma once
#include <algorithm>
#include <cmath>

namespace wavecam {

// How a render's depth channel measures distance: along the view axis (Blender's Z,
// POV-Ray depth passes) or along the pixel's ray.
enum class DepthMeaning { Planar, Ray };

// Depths at or beyond this (Blender writes 1e10 for "nothing hit") are sky: a plane wave.
constexpr double kInfiniteDepth = 1e9;

struct PinholeCamera {
    int width = 0, height = 0;
    double fov_h = 0;          // horizontal field of view, radians
    double film_distance = 0;  // f, metres

    // Pixel pitch in the tangent plane z = 1: 2 tan(fov/2) / width (square pixels).
    double tan_pitch() const { return 2.0 * std::tan(0.5 * fov_h) / width; }
    // Pixel pitch on the film, metres: f 2 tan(fov/2) / width. The film's size is this times
    // the pixel count; every film geometry derives from here.
    double pixel_pitch() const { return film_distance * tan_pitch(); }

    // Tangent-plane coordinates (u right, v up) of image position (x, y) in pixels, measured
    // from the top-left corner (pixel (i, j)'s centre is (i + 0.5, j + 0.5)).
    void tangent(double x, double y, double& u, double& v) const {
        const double t = tan_pitch();
        u = (x - 0.5 * width) * t;
        v = (0.5 * height - y) * t;
    }

    // Cosine of the widest field angle over the window [x0, x1] x [y0, y1] of image positions
    // (at its corners; the window may reach beyond the frame).
    double cos_widest(double x0, double y0, double x1, double y1) const {
        double widest = 0;
        for (double x : {x0, x1})
            for (double y : {y0, y1}) {
                double u, v;
                tangent(x, y, u, v);
                widest = std::max(widest, u * u + v * v);
            }
        return 1.0 / std::sqrt(1.0 + widest);
    }

    // Solid angle of pixel (i, j) seen from the pinhole: t^2 / (1 + u^2 + v^2)^(3/2)
    // (projection of a small tangent-plane patch onto the unit sphere).
    double solid_angle(int i, int j) const {
        double u, v;
        tangent(i + 0.5, j + 0.5, u, v);
        const double t = tan_pitch();
        return t * t / std::pow(1.0 + u * u + v * v, 1.5);
    }

    // Cosine of the angle at which light from the pinhole meets film pixel (i, j): the film
    // records flux through its plane, |U|^2 cos(incidence).
    double cos_incidence(int i, int j) const {
        double u, v;
        tangent(i + 0.5, j + 0.5, u, v);
        return 1.0 / std::sqrt(1.0 + u * u + v * v);
    }

    // Distance along the view axis of a point `depth` away on pixel (i, j)'s central ray.
    double planar_depth(int i, int j, double depth, DepthMeaning meaning) const {
        if (meaning == DepthMeaning::Planar) return depth;
        double u, v;
        tangent(i + 0.5, j + 0.5, u, v);
        return depth / std::sqrt(1.0 + u * u + v * v);
    }

    // cos^4 of the field angle of pixel (i, j): the pinhole camera's natural fall-off.
    double cos4(int i, int j) const {
        double u, v;
        tangent(i + 0.5, j + 0.5, u, v);
        const double c2 = 1.0 / (1.0 + u * u + v * v);
        return c2 * c2;
    }

    // Sine of the largest field angle in the frame (the corner ray).
    double sin_max_field_angle() const {
        double u, v;
        tangent(0, 0, u, v);
        const double r2 = u * u + v * v;
        return std::sqrt(r2 / (1.0 + r2));
    }
};

}  // namespace wavecam
