// The output file's layout: the input's own channel names and header, less what described the
// ideal pinhole camera it was rendered with, so a renderer reads wavecam's image back as its
// own (a Blender multilayer file stays one layer: ViewLayer.Combined.R/G/B/A, ViewLayer.Depth.Z).
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <string>
#include <vector>
#include "wavecam/render_input.h"
#include "wavecam/result.h"

namespace wavecam {

// Whether an input header attribute describes the ideal camera or an earlier wavecam run, and
// so would be stale in the diffracted image: lens and focal length (Blender's `Lens`, EXIF and
// OpenEXR lens fields), camera matrices (`worldToCamera`, `worldToNDC`), the renderer's
// statistics (`cycles.*`), a texture's MIP and lookup description and its pixels' statistics
// (`textureformat`, `wrapmodes`, `oiio:AverageColor`, `oiio:SHA-1`...), and `wavecam.*`
// (rewritten for this run; `wavecam.scene` and `wavecam.scene-unit` are kept).
bool is_stale_camera_attribute(const std::string& name);

// The output header's list of the channels wavecam diffracted ("R,G,B,A"); every other channel
// the output holds is the input's, unchanged.
constexpr const char* kDiffractedChannelsAttribute = "wavecam.diffracted-channels";

// The output's header: the input's (its data and display windows too), stale attributes
// dropped; the radiance layer's R, G, B (and A) diffracted, every other channel (depth, AOVs,
// Cryptomatte, IDs) in its own name and place; with `other_channels` false, only the radiance
// layer and depth (and Cryptomatte's metadata dropped with its channels). Float in memory, one
// level, as scanlines (a MIP-mapped or tiled input's level 0).
OIIO::ImageSpec output_header(const OIIO::ImageSpec& input, const RenderChannels& channels, bool other_channels);

// The file's type of each output channel: the input's type of the channel of that name;
// `diffracted_type` for the diffracted ones unless TypeUnknown (the input's then too).
std::vector<OIIO::TypeDesc> file_channel_formats(const OIIO::ImageSpec& input, const OIIO::ImageSpec& output,
                                                 OIIO::TypeDesc diffracted_type);

// Fills `dst` (already reset to output_header's spec, its data window `src`'s, or cropped by
// `margin` pixels of overscan on every side): R, G, B from `rgb` (interleaved), alpha from
// `alpha`, every other channel copied unchanged from the same pixels of `src`.
Result<bool> fill_output(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const RenderChannels& channels, int margin,
                         const float* rgb, const float* alpha);

// Where a diffracted channel is written as half and holds values beyond half's range (65504,
// a sun after diffraction, a bright patch after a colour conversion), which half would write as
// inf: the half-overflow setting. Float writes the diffracted channels as float instead; Clamp
// sets such values to +-65504; Refuse writes nothing. Each says how many values and the largest.
enum class HalfOverflow { Float, Clamp, Refuse };

// The largest finite value a half holds.
constexpr float kHalfMax = 65504.0f;

// Writes the diffracted `dst` as `path` (atomic_write.h) with the rest of `src`'s file: each
// channel in its file type (file_channel_formats), and every other part of a multi-part input
// read again and written as it was, in its place. Never writes inf for a finite value: half
// channels beyond half's range go as `overflow` says, and the value is what was done ("" when
// every value fits; the file's header records it as wavecam.half-overflow-written).
Result<std::string> write_plate(const OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& path,
                                OIIO::TypeDesc diffracted_type, HalfOverflow overflow, double max_bytes);

}  // namespace wavecam
