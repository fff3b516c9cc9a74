#include "estimate_line.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace wavecam::front {

std::string format_duration(double seconds) {
    char s[32];
    const long t = std::lround(std::max(0.0, seconds));
    if (t >= 3600) std::snprintf(s, sizeof s, "%ldh%02ldm", t / 3600, t / 60 % 60);
    else if (t >= 60) std::snprintf(s, sizeof s, "%ldm%02lds", t / 60, t % 60);
    else std::snprintf(s, sizeof s, "%lds", t);
    return s;
}

std::string estimate_line(const JobEstimate& e) {
    char tail[160];
    std::snprintf(tail, sizeof tail, " = %.3g terms, about %s on %d thread%s at %.3g terms/s measured here", e.terms,
                  format_duration(e.seconds).c_str(), e.threads, e.threads == 1 ? "" : "s", e.rate);
    return e.job + tail;
}

}  // namespace wavecam::front
