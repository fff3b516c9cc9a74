// The scene beyond the frame's edge. Without an overscan, nothing says what lies beyond the
// frame, yet a border pixel receives light from there. Every method continues the edge: a
// point outside takes the light of the nearest edge pixel. That is right for a wall, a sky or
// a texture, whose light goes on beyond the edge, but not for a lone bright pixel (a sun, a
// glint) on the edge: copied into every point beyond, it would come back thousands of times.
//
// So each edge pixel's continuation is bounded by its neighbours along the edge: its light
// (the sum of its channels) at most Tukey's far-out fence q3 + 3 (q3 - q1) of the 2 K + 1 edge
// pixels about it (the border read as one closed ring, round the corners), its colour kept.
// Smooth light lies within the fence (a linear ramp's extremes are 2 IQR from the quartiles),
// so a wall, a gradient or a texture is continued as before; a pixel far brighter than most of
// its neighbours is continued as bright as they are, and its own light only spreads. The exact
// answer needs the scene beyond: an overscan of the kernel radius.
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

    // Edge pixels whose continuation was bounded, and those among them more than twice as
    // bright as their bound (what a front tells the user).
    size_t bounded() const { return bounded_; }
    size_t bright() const { return bright_; }

private:
    int ring_index(int i, int j) const;
    int channels_, width_, height_, length_;
    std::vector<float> ring_;
    size_t bounded_ = 0, bright_ = 0;
};

}  // namespace wavecam
