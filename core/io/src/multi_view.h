// Multi-view (stereo) OpenEXR: one file, several views of the scene (`multiView`: "left",
// "right"), each with its own radiance and depth. Every view is diffracted with its own depth,
// its channels read under their names without the view, then put back under their own.
//
// Which view a channel belongs to is OpenEXR's rule: a name without a dot is the default view's
// (the first in multiView); else the name's next-to-last part, where it names a view
// ("right.R", "ViewLayer.Combined.left.R"); any other channel ("diffuse.R") belongs to no view
// and passes through once. Internal to wavecam_io.
#pragma once
#include <OpenImageIO/imagebuf.h>

#include <functional>
#include <string>
#include <vector>
#include "wavecam/result.h"

namespace wavecam::detail {

// The file's views, in multiView's order; empty for a file of fewer than two.
std::vector<std::string> view_names(const OIIO::ImageSpec& spec);

// Diffracts each view of `src` (view_names has two or more) through `one` (the single-view
// diffraction, its errors naming "NAME (view V)"), and writes into `dst` every view's result
// under the input's channel names, in the input's order, the header the default view's with
// multiView kept and wavecam.views saying what was done.
using DiffractOneView = std::function<Result<bool>(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name)>;
Result<bool> diffract_each_view(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name,
                                const DiffractOneView& one);

}  // namespace wavecam::detail
