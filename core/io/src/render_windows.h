// A render's data and display windows, and the frame the camera images (render_input.h's
// FrameWindows). Internal to wavecam_io.
#pragma once
#include <OpenImageIO/imageio.h>
#include <string>
#include "wavecam/render_input.h"

namespace wavecam::detail {

// Places `in` (its rgb and depth the data window's pixels, in.fov_h the display window's field
// of view) on the camera's frame: the smallest frame centred on the display window's centre that
// holds the data and display windows, at the display window's pixel pitch. The frame's pixels beyond the data
// window continue its edge (each takes the nearest data pixel's radiance and depth), as the
// diffraction continues any frame's edge. Sets in.windows, width, height, x0, y0, fov_h and
// display_fov_h. The frame holds the display window too, so that a crop is diffracted with the
// whole frame's sampling of the PSF over the field (the cost of a crop is its frame's). Refused (a message without the file name) for a data window so far from the
// display window that the frame would hold over four times the pixels of both.
Result<bool> place_on_frame(const OIIO::ImageSpec& spec, RenderInput& in);

}  // namespace wavecam::detail
