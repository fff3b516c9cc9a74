#include "thread_waits.h"

#include <unistd.h>

#include <cstdlib>

namespace wavecam::cli {

namespace {
const char* const kSpinRounds = "10000";
}

void wait_briefly_at_barriers(char** argv) {
    if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
    if (::setenv("GOMP_SPINCOUNT", kSpinRounds, 1) != 0) return;
    ::execv("/proc/self/exe", argv);
    ::unsetenv("GOMP_SPINCOUNT");  // not executed again: as before
}

std::string barrier_waits() {
    std::string s = "threads wait at barriers:";
    for (const char* name : {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT"})
        if (const char* value = std::getenv(name)) s += std::string(" ") + name + "=" + value;
    return s + (s.back() == ':' ? " libgomp's default" : "");
}

}  // namespace wavecam::cli
