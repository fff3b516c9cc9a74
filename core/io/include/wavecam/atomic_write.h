// Writing a file so that nothing is lost or half-written: write a temporary beside the
// target, then rename it over the target (atomic on one filesystem). Every writer of wavecam's
// outputs (images, CSV tables, job records, scripts) goes through here.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <string>
#include <vector>
#include "wavecam/result.h"

namespace wavecam {

// Writes `image` to `path` (format from the extension, as OIIO decides), its pixels as `format`,
// else channel by channel as `channel_formats` where the file format allows (OpenEXR), else as
// the buffer holds them. Every step is
// checked: the writer's open, pixels and close, an fsync, and the temporary read back whole (a
// full disk that a writer does not report); on failure the target is untouched and the
// temporary removed; the error names the file.
Result<bool> write_image_atomically(const OIIO::ImageBuf& image, const std::string& path,
                                    OIIO::TypeDesc format = OIIO::TypeUnknown,
                                    const std::vector<OIIO::TypeDesc>& channel_formats = {});

// One part (OIIO subimage) of a file of several, and its file types channel by channel.
struct PartToWrite {
    const OIIO::ImageBuf* image;
    std::vector<OIIO::TypeDesc> channel_formats;
};

// Writes the parts, in order, as one file (OpenEXR multi-part) the same way; refused for a format
// that holds one image.
Result<bool> write_parts_atomically(const std::vector<PartToWrite>& parts, const std::string& path,
                                    OIIO::TypeDesc format = OIIO::TypeUnknown);

// Writes `text` to `path` the same way (every write, the fsync and the close checked).
Result<bool> write_text_atomically(const std::string& text, const std::string& path);

// "" when `path` can be written as an output name; else why not, naming it: a component beyond
// NAME_MAX, or a path too long (PATH_MAX) for its temporary. Fronts check it before any work.
std::string output_name_problem(const std::string& path);

// A check asked before each rename: when it says the process is stopping (a signal), the
// temporary is removed and the target left as it was ("PATH: interrupted; not written").
void set_write_cancel_check(bool (*cancelled)());

// The temporary being written now (nullptr when none): what a signal handler that ends the
// process at once must remove. Async-signal-safe.
const char* temporary_being_written();

}  // namespace wavecam
