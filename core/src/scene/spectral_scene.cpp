// What every method reads of a scene before its work (spectral_scene.h): its frame's and pixels'
// checks, its nearest depth.
#include "wavecam/spectral_scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace wavecam {

Result<bool> check_frame(const PinholeCamera& c, int overscan) {
    if (c.width < 1 || c.height < 1) return Result<bool>::failure("image: expected at least 1x1 pixels");
    if (overscan >= 0 && 2 * overscan < std::min(c.width, c.height)) return Result<bool>::success(true);
    std::ostringstream m;
    m << "overscan: expected 0 to " << (std::min(c.width, c.height) - 1) / 2 << " pixels for a " << c.width << "x"
      << c.height << " image, got " << overscan;
    return Result<bool>::failure(m.str());
}

Result<bool> check_pixels(const PinholeCamera& c, const float* radiance, int channels, bool non_negative,
                          const float* depth) {
    if (!radiance || !depth) return Result<bool>::failure("image: radiance and depth are required");
    auto bad = [&c](const char* field, size_t p, float value, const char* expected) {
        std::ostringstream m;
        m << field << ": pixel (" << p % c.width << ", " << p / c.width << ") is " << value << ", expected "
          << expected;
        return Result<bool>::failure(m.str());
    };
    const size_t n = size_t(c.width) * c.height;
    for (size_t p = 0; p < n; ++p) {
        for (int k = 0; k < channels; ++k) {
            const float v = radiance[channels * p + k];
            if (!radiance_in_range(v) || (non_negative && v < 0))
                return bad("radiance", p, v,
                           non_negative ? "a finite value from 0 to 1e30" : "a finite value within +-1e30");
        }
        if (!depth_in_range(depth[p]))
            return bad("depth", p, depth[p], "a distance > 0 (inf or >= 1e9 for sky)");
    }
    return Result<bool>::success(true);
}

double nearest_depth(const PinholeCamera& camera, const float* depth, DepthMeaning meaning) {
    double z = INFINITY;
    for (int j = 0; j < camera.height; ++j)
        for (int i = 0; i < camera.width; ++i) {
            const double d = depth[size_t(j) * camera.width + i];
            if (d < kInfiniteDepth) z = std::min(z, camera.planar_depth(i, j, d, meaning));
        }
    return z;
}

}  // namespace wavecam
