// --frames: OIIO's sequence syntax, counted before it is expanded (a range of a hundred million
// frames is refused in words, not allocated), and frame lists written back as ranges.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/strutil.h>

#include <cstdio>
#include <cstdlib>

#include "commands.h"

namespace wavecam::cli {
namespace {

constexpr long kMaxFrames = 100000;  // over an hour of film at 24 frames a second

// Frames one term ("7", "1-100", "1-100x2", "1-100y2": every frame but each second) stands for;
// -1 when it is not such a term (OIIO then refuses it).
long long term_count(const std::string& term) {
    long long a = 0, b = 0, step = 1;
    char kind = 'x';
    int used = 0;
    const char* s = term.c_str();
    if (std::sscanf(s, "%lld%n", &a, &used) == 1 && used == int(term.size())) return 1;
    if (std::sscanf(s, "%lld-%lld%n", &a, &b, &used) == 2 && used == int(term.size())) return std::llabs(b - a) + 1;
    if (std::sscanf(s, "%lld-%lld%c%lld%n", &a, &b, &kind, &step, &used) == 4 && used == int(term.size()) &&
        step > 0 && (kind == 'x' || kind == 'y')) {
        const long long all = std::llabs(b - a) + 1, every = std::llabs(b - a) / step + 1;
        return kind == 'x' ? every : all - every;
    }
    return -1;
}

}  // namespace

Result<std::vector<int>> frame_numbers(const std::string& text) {
    using R = Result<std::vector<int>>;
    const std::string expected = "expected a frame range such as 1-100, 1-100x2 or 3,7,10-20, got '" + text + "'";
    long long count = 0;
    for (const auto& term : OIIO::Strutil::splits(text, ",")) {
        const long long n = term_count(std::string(term));
        if (n < 0) return R::failure("--frames: " + expected);
        count += n;
        if (count > kMaxFrames)
            return R::failure("--frames: '" + text + "' is more than " + std::to_string(kMaxFrames) +
                              " frames; expected at most " + std::to_string(kMaxFrames) + " in one run");
    }
    std::vector<int> frames;
    if (!OIIO::Filesystem::enumerate_sequence(text, frames) || frames.empty()) return R::failure("--frames: " + expected);
    return R::success(std::move(frames));
}

std::string frame_ranges(const std::vector<int>& frames) {
    std::string out;
    for (size_t i = 0; i < frames.size();) {
        size_t j = i;
        while (j + 1 < frames.size() && static_cast<long long>(frames[j + 1]) == static_cast<long long>(frames[j]) + 1) ++j;
        out += (out.empty() ? "" : ",") + std::to_string(frames[i]) +
               (j > i ? "-" + std::to_string(frames[j]) : std::string());
        i = j + 1;
    }
    return out.empty() ? "none" : out;
}

}  // namespace wavecam::cli
