// Renders radiance and planar depth for every pixel.
//  radiance: mean of `samples` rays per pixel; image position, pinhole point, area-light
//            point and sky direction each jittered in a g x g grid (g = floor(sqrt(samples));
//            any remaining samples uniform); through the ideal pinhole or a finite one;
//  depth:    planar depth of the one ray through the pixel centre and the ideal pinhole
//            (not antialiased, like Blender's Z); kSkyDepth where it hits nothing.
// Rows run in parallel (OpenMP); each pixel has its own random sequence.
#pragma once
#include <vector>
#include "camera.h"
#include "finite_pinhole.h"
#include "scene.h"
#include "trace_scene.h"

namespace wavecam::trace {

// Blender's "nothing hit" depth.
constexpr float kSkyDepth = 1e10f;

struct RenderedImage {
    int width = 0, height = 0;
    std::vector<float> rgb;    // interleaved R, G, B, row 0 at the top
    std::vector<float> depth;  // metres along the view axis
};

RenderedImage render(const Scene& scene, const TraceScene& geometry, const Camera& camera,
                     const FinitePinhole& pinhole, int samples);

}  // namespace wavecam::trace
