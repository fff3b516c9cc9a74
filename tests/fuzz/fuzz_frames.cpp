// Fuzzes --frames (plugin/cli/frame_range.cpp): any text is a list of at most 100000 frames,
// each once in ascending order, or an error naming --frames, counted before it is expanded (a
// range of 10^9 frames must not be allocated), never a crash; the list written back as ranges
// reads back as the same frames.
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
    for (size_t i = 1; i < r.value.size(); ++i)
        if (r.value[i] <= r.value[i - 1]) std::abort();
    auto again = wavecam::cli::frame_numbers(wavecam::cli::frame_ranges(r.value));
    if (!again.ok() || again.value != r.value) std::abort();
    return 0;
}
