// A rendered scene in colour, as every method takes it, the checks its frame and pixels pass
// before any work, and where its film image goes: the convolution method (convolution_method.h)
// and the scene-sum methods (spectral_diffraction.h).
#pragma once
#include <cmath>
#include "wavecam/pinhole_camera.h"
#include "wavecam/result.h"

namespace wavecam {

struct SpectralScene {
    PinholeCamera camera;
    const float* rgb = nullptr;    // interleaved linear RGB in the basis's working space
    const float* depth = nullptr;  // metres
    DepthMeaning depth_meaning = DepthMeaning::Planar;
    bool checked = false;          // its pixels already checked, once for the job (load_render)
};

// At least 1x1 pixels, and an overscan that leaves some.
Result<bool> check_frame(const PinholeCamera& camera, int overscan);

// Every radiance (`channels` interleaved per pixel) within +-kMaxRadiance, and >= 0 where
// `non_negative`, and every depth > 0: the first bad pixel is named with its field and what was
// expected. The bound keeps the single-precision sums finite: a frame's worth of such sources
// (1e30 x 1e7 pixels x the spectral basis's weights) stays below float's 3.4e38.
constexpr float kMaxRadiance = 1e30f;
// One pixel's values as check_pixels (and the render reader, which names channels) accept them.
inline bool radiance_in_range(float v) { return std::fabs(v) <= kMaxRadiance; }  // NaN: false
inline bool depth_in_range(float d) { return d > 0; }                            // NaN: false; inf: sky
Result<bool> check_pixels(const PinholeCamera& camera, const float* radiance, int channels, bool non_negative,
                          const float* depth);

// Nearest planar depth in the scene (for the sampling pitch); inf if all sky.
double nearest_depth(const PinholeCamera& camera, const float* depth, DepthMeaning meaning);

// Where a frame's film image goes: XYZ interleaved, width x height, into `xyz`. `vignetting`
// keeps the natural cos^4 fall-off; false divides it out so the result compares with an ideal
// render.
struct XyzOutput {
    bool vignetting;
    float* xyz;
};

}  // namespace wavecam
