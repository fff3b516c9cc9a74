// A render in a file of several parts (OpenEXR multi-part, OIIO subimages): which part is read,
// and what the other parts hold when the chosen one lacks a channel. Internal to wavecam_io.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <string>
#include "wavecam/result.h"

namespace wavecam::detail {

// The index of the part named `name` in the file at `path` (its oiio:subimagename, OpenEXR's
// part name); with no name, 0 when the file has one part, else the one part holding R, G, B
// and Z. Otherwise refused, naming each part and its channels, and saying how to choose one.
Result<int> choose_part(const std::string& path, const std::string& name);

// For a channel the read part lacks: "; channel 'Z' is in part "depth" of this file, ..."
// naming how to join the parts; "" when no other part has it (or the file has one part).
std::string other_part_note(const OIIO::ImageBuf& image, const std::string& channel);

}  // namespace wavecam::detail
