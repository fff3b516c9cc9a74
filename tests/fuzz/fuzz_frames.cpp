// Fuzzes --frames (plugin/cli/frame_range.cpp): any text is a list of at most 100000 frames or
// an error naming --frames, counted before it is expanded (a range of 10^9 frames must not be
// allocated), never a crash; the list written back as ranges reads back as the same frames.
#include <cstdlib>
#include <string>

#include "cli/commands.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    auto r = wavecam::cli::frame_numbers(text);
    if (!r.ok()) {
        if (r.error.rfind("--frames: ", 0) != 0) std::abort();
        return 0;
    }
    if (r.value.empty() || r.value.size() > 100000) std::abort();
    const std::string ranges = wavecam::cli::frame_ranges(r.value);
    auto again = wavecam::cli::frame_numbers(ranges);
    if (!again.ok() || again.value != r.value) {
        // ranges of a sorted list read back the same; an unsorted list keeps its frames
        if (!again.ok() || again.value.size() != r.value.size()) std::abort();
    }
    return 0;
}
