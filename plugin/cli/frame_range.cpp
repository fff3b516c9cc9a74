// --frames: OIIO's sequence syntax, counted before it is expanded (a range of a hundred million
// frames is refused in words, not allocated), frames in ascending order only, and frame lists
// written back as ranges.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/strutil.h>

#include <cstdio>
#include <limits>
#include <optional>

#include "commands.h"

namespace wavecam::cli {
namespace {

constexpr long kMaxFrames = 100000;  // over an hour of film at 24 frames a second

// One comma-separated term: "7", "1-100", "1-100x2" (every second frame), "1-100y2" (every
// frame but each second).
struct Term {
    long long first = 0, last = 0, step = 1;
    char kind = 'x';
};

// Frame numbers are ints, as OIIO's; a term beyond them is not one.
std::optional<Term> parse_term(const std::string& term) {
    Term t;
    int used = 0;
    const char* s = term.c_str();
    const auto fits = [&t] {
        for (long long v : {t.first, t.last, t.step})
            if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) return std::optional<Term>();
        return std::optional<Term>(t);
    };
    if (std::sscanf(s, "%lld%n", &t.first, &used) == 1 && used == int(term.size())) {
        t.last = t.first;
        return fits();
    }
    if (std::sscanf(s, "%lld-%lld%n", &t.first, &t.last, &used) == 2 && used == int(term.size())) return fits();
    if (std::sscanf(s, "%lld-%lld%c%lld%n", &t.first, &t.last, &t.kind, &t.step, &used) == 4 &&
        used == int(term.size()) && (t.kind == 'x' || t.kind == 'y'))
        return fits();
    return std::nullopt;
}

// Frames an ascending term with a positive step stands for: x keeps (last - first) / step + 1
// of them, y the rest.
long long term_count(const Term& t) {
    const long long all = t.last - t.first + 1, every = (t.last - t.first) / t.step + 1;
    return t.kind == 'x' ? every : all - every;
}

// Why a term cannot be run in ascending order ("" when it can). OIIO itself would enumerate
// "3-1" and "1-10x-2" downwards, and take a step of 0 as 1.
std::string descending_term(const std::string& term, const Term& t, const std::string& text) {
    const std::string where = "'" + term + "'" + (term == text ? "" : " (in '" + text + "')");
    if (t.step <= 0)
        return "--frames: " + where + " has a step of " + std::to_string(t.step) +
               "; expected FIRST-LASTxSTEP with a step of 1 or more, e.g. 1-10x2";
    if (t.first > t.last)
        return "--frames: " + where + " runs backwards; expected FIRST-LAST with FIRST <= LAST, e.g. " +
               std::to_string(t.last) + "-" + std::to_string(t.first);
    return {};
}

}  // namespace

Result<std::vector<int>> frame_numbers(const std::string& text) {
    using R = Result<std::vector<int>>;
    const std::string expected = "expected a frame range such as 1-100, 1-100x2 or 3,7,10-20, got '" + text + "'";
    long long count = 0;
    for (const auto& piece : OIIO::Strutil::splits(text, ",")) {
        const std::string term(piece);
        const auto t = parse_term(term);
        if (!t) return R::failure("--frames: " + expected);
        if (const std::string backwards = descending_term(term, *t, text); !backwards.empty())
            return R::failure(backwards);
        count += term_count(*t);
        if (count > kMaxFrames)
            return R::failure("--frames: '" + text + "' is more than " + std::to_string(kMaxFrames) +
                              " frames; expected at most " + std::to_string(kMaxFrames) + " in one run");
    }
    std::vector<int> frames;
    if (!OIIO::Filesystem::enumerate_sequence(text, frames) || frames.empty()) return R::failure("--frames: " + expected);
    for (size_t i = 1; i < frames.size(); ++i)  // each frame once, in ascending order
        if (frames[i] <= frames[i - 1])
            return R::failure("--frames: '" + text + "' lists frame " + std::to_string(frames[i]) +
                              (frames[i] == frames[i - 1] ? " twice" : " after frame " + std::to_string(frames[i - 1])) +
                              "; expected each frame once, in ascending order, e.g. 1-3,7,10-20");
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
