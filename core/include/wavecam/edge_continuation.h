// The scene beyond the frame's edge. Without an overscan, nothing says what lies beyond the
// frame, yet a border pixel receives light from there. Every method continues the edge: a
// point outside takes the light of the nearest edge pixel. That is right for a wall, a sky or
// a texture, whose light goes on beyond the edge, but not for a lone bright pixel (a sun, a
// glint) on the edge: copied into every point beyond, it would come back thousands of times.
//
// So each edge pixel's continuation is bounded by its neighbours along the edge. Tukey's
// far-out fence q3 + 3 (q3 - q1) of the 2 K + 1 edge pixels about it (the border read as one
// closed ring, round the corners) says how bright its neighbourhood gets; a pixel whose light
// (the sum of its channels) is more than twice that is an outlier, and is continued only as
// bright as the fence, its colour kept. Smooth light lies within the fence (a linear ramp's
// extremes are 2 IQR from the quartiles) and a texture's brightest pixels within twice it, so
// a wall, a gradient or a texture is continued as before; a sun is continued as bright as its
// neighbours, and its own light only spreads. The exact answer needs the scene beyond: an
// overscan of the kernel radius.
#pragma once
#include <cstddef>
#include <vector>

namespace wavecam {

class EdgeContinuation {
public:
    // Pixels beside each edge pixel, on either side along the ring, that bound its continuation.
    static constexpr int kNeighbours = 8;

    // `values`: `channels` floats per pixel, width x height (>= 2 x 2), rows in order.
    EdgeContinuation(const float* values, int channels, int width, int height);

    // The light a point beyond the frame takes from its nearest edge pixel (i, j): `channels`
    // floats. (i, j) must lie on the frame's border.
    const float* at(int i, int j) const { return &ring_[size_t(channels_) * ring_index(i, j)]; }

    // The light at pixel (i, j) anywhere: the frame's own inside it, the edge continued beyond.
    const float* light(int i, int j) const {
        const int ci = i < 0 ? 0 : i >= width_ ? width_ - 1 : i, cj = j < 0 ? 0 : j >= height_ ? height_ - 1 : j;
        return ci == i && cj == j ? &values_[size_t(channels_) * (size_t(j) * width_ + i)] : at(ci, cj);
    }

    // Edge pixels whose continuation was bounded (what a front tells the user).
    size_t bounded() const { return bounded_; }

private:
    int ring_index(int i, int j) const;
    const float* values_;
    int channels_, width_, height_, length_;
    std::vector<float> ring_;
    size_t bounded_ = 0;
};

}  // namespace wavecam
