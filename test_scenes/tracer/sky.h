// Sky radiance seen along a unit direction: horizon colour at y <= 0, blending linearly in y
// to the zenith colour at y = 1.
#pragma once
#include <algorithm>
#include "scene.h"

namespace wavecam::trace {

inline Vec3 sky_radiance(const Sky& sky, Vec3 unit_direction) {
    const double w = std::clamp(unit_direction.y, 0.0, 1.0);
    return sky.horizon * (1 - w) + sky.zenith * w;
}

}  // namespace wavecam::trace
