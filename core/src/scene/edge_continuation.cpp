#include "wavecam/edge_continuation.h"

#include <algorithm>

namespace wavecam {

// The border as a ring, clockwise from (0, 0): the top row, the right column, the bottom row
// backwards, the left column upwards. A corner pixel has one index whichever side names it.
int EdgeContinuation::ring_index(int i, int j) const {
    const int w = width_ - 1, h = height_ - 1;
    if (j == 0) return i;
    if (i == w) return w + j;
    if (j == h) return w + h + (w - i);
    return (2 * w + h + (h - j)) % length_;
}

EdgeContinuation::EdgeContinuation(const float* values, int channels, int width, int height)
    : values_(values), channels_(channels), width_(width), height_(height), length_(2 * (width - 1) + 2 * (height - 1)) {
    ring_.resize(size_t(channels) * length_);
    std::vector<float> light(length_);
    auto place = [&](int i, int j) {
        const int r = ring_index(i, j);
        const float* v = &values[size_t(channels) * (size_t(j) * width + i)];
        std::copy(v, v + channels, &ring_[size_t(channels) * r]);
        float sum = 0;
        for (int c = 0; c < channels; ++c) sum += v[c];
        light[r] = sum;
    };
    for (int i = 0; i < width; ++i) {
        place(i, 0);
        place(i, height - 1);
    }
    for (int j = 0; j < height; ++j) {
        place(0, j);
        place(width - 1, j);
    }
    const int k = std::min(kNeighbours, (length_ - 1) / 2);
    std::vector<float> window(2 * k + 1);
    for (int r = 0; r < length_; ++r) {
        for (int d = -k; d <= k; ++d) window[d + k] = light[((r + d) % length_ + length_) % length_];
        // the quartiles of the window (nearest rank)
        const size_t n = window.size(), lower = (n - 1) / 4, upper = (3 * (n - 1) + 3) / 4;
        std::nth_element(window.begin(), window.begin() + lower, window.end());
        const float q1 = window[lower];
        std::nth_element(window.begin(), window.begin() + upper, window.end());
        const float q3 = window[upper];
        const float fence = q3 + 3 * (q3 - q1);
        if (!(light[r] > 2 * fence)) continue;  // a texture's brightest pixels are continued as they are
        ++bounded_;
        const float scale = fence > 0 ? fence / light[r] : 0.0f;
        for (int c = 0; c < channels; ++c) ring_[size_t(channels) * r + c] *= scale;
    }
}

}  // namespace wavecam
