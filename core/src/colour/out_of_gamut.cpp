#include "wavecam/out_of_gamut.h"

#include <algorithm>

namespace wavecam {

size_t desaturate_into_gamut(float* rgb, size_t count, const Vector3& y) {
    const double white_luminance = y[0] + y[1] + y[2];
    size_t changed = 0;
    for (size_t p = 0; p < count; ++p) {
        float* c = rgb + 3 * p;
        const double lowest = std::min({c[0], c[1], c[2]});
        if (!(lowest < 0)) continue;
        ++changed;
        const double luminance = y[0] * c[0] + y[1] * c[1] + y[2] * c[2];
        if (!(luminance > 0)) {
            c[0] = c[1] = c[2] = 0.0f;
            continue;
        }
        const double grey = luminance / white_luminance, t = grey / (grey - lowest);
        for (int k = 0; k < 3; ++k) c[k] = static_cast<float>(std::max(0.0, grey + t * (c[k] - grey)));
    }
    return changed;
}

}  // namespace wavecam
