// Anamorphic frames: pixels wider than tall (OpenEXR's pixelAspectRatio, OIIO's
// PixelAspectRatio). Field angles and PSFs belong to the real pixel shape, so a frame of
// non-square pixels is diffracted on square ones: each row stretched to W x aspect pixels of the
// frame's height (every pixel's light spread evenly over the square pixels its footprint covers),
// diffracted, and squeezed back (each pixel the average of what its footprint covers). Internal
// to wavecam_io.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include "wavecam/render_input.h"
#include "wavecam/result.h"

namespace wavecam::detail {

// The file's pixel aspect ratio, width over height (1 when it says none).
double pixel_aspect(const OIIO::ImageSpec& spec);

// `src` on square pixels: the radiance layer's R, G, B and A spread by area, every other channel
// (depth, IDs) taken from the pixel under each new pixel's centre. Refused for a file whose data
// window differs from its display window.
Result<OIIO::ImageBuf> to_square_pixels(const OIIO::ImageBuf& src, const RenderChannels& channels, double aspect);

// `square` (the diffracted image on square pixels) back on the pixels of `src`: the diffracted
// channels (wavecam.diffracted-channels) averaged over each pixel's footprint, every other
// channel copied from `src` unchanged; the header says the input's aspect.
Result<OIIO::ImageBuf> to_file_pixels(const OIIO::ImageBuf& square, const OIIO::ImageBuf& src, double aspect);

}  // namespace wavecam::detail
