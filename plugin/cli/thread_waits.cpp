#include "thread_waits.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace wavecam::cli {

namespace {

const char* const kSpinRounds = "GOMP_SPINCOUNT=10000";

bool named(const char* entry, const char* name) {
    const size_t n = std::strlen(name);
    return std::strncmp(entry, name, n) == 0 && entry[n] == '=';
}

// The executable's pre-initialiser: the dynamic loader calls it once the libraries are loaded and
// before any of them initialises, libgomp (which reads the environment then) and libc (which
// sets `environ` only after this) included. Where neither OMP_WAIT_POLICY nor GOMP_SPINCOUNT is
// set, it executes the command again with GOMP_SPINCOUNT added: the one way to hand libgomp a
// setting before it reads them. The first start then costs the loading alone (no library has
// initialised), a few milliseconds. If the execution fails, the command goes on as it is.
void wait_briefly_at_barriers(int, char** argv, char** envp) {
    size_t count = 0;
    for (; envp && envp[count]; ++count)
        if (named(envp[count], "OMP_WAIT_POLICY") || named(envp[count], "GOMP_SPINCOUNT")) return;
    char** with = static_cast<char**>(__builtin_alloca((count + 2) * sizeof(char*)));
    for (size_t k = 0; k < count; ++k) with[k] = envp[k];
    with[count] = const_cast<char*>(kSpinRounds);
    with[count + 1] = nullptr;
    ::execve("/proc/self/exe", argv, with);
}

[[gnu::used, gnu::section(".preinit_array")]] void (*const kWaitBrieflyAtBarriers)(int, char**, char**) =
    &wait_briefly_at_barriers;

}  // namespace

std::string barrier_waits() {
    std::string s = "threads wait at barriers:";
    for (const char* name : {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT"})
        if (const char* value = std::getenv(name)) s += std::string(" ") + name + "=" + value;
    return s + (s.back() == ':' ? " libgomp's default" : "");
}

}  // namespace wavecam::cli
