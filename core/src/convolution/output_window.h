// The pixels a convolution writes. Internal to core.
#pragma once

namespace wavecam::detail {

// width x height pixels whose pixel (0, 0) is the convolution domain's pixel (x0, y0).
struct OutputWindow {
    int x0, y0, width, height;
};

}  // namespace wavecam::detail
