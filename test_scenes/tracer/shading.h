// Radiance a diffuse (Lambertian) surface sends back along the ray that hit it:
//   L = albedo / pi * (sum of shadowed irradiance from point and area lights)
//     + albedo * sky radiance along one shadowed cosine-weighted direction,
// the last an unbiased one-sample estimate of albedo / pi * integral of L_sky cos over the
// hemisphere (pdf cos / pi). Each call takes one point on every area light and one sky
// direction from the given unit-square samples (the caller stratifies them).
#pragma once
#include "scene.h"
#include "trace_scene.h"

namespace wavecam::trace {

struct LightSamples {
    double area_u, area_v;  // position on each area light, uniform over its area
    double sky_u, sky_v;    // cosine-weighted sky direction
};

Vec3 shade(const Scene& scene, const TraceScene& geometry, const SurfaceHit& hit, const LightSamples& samples);

}  // namespace wavecam::trace
