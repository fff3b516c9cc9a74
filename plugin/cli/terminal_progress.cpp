#include "terminal_progress.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>

namespace wavecam::cli {
namespace {
std::atomic<bool> g_interrupted{false};
bool g_drawn = false;
extern "C" void on_signal(int) { g_interrupted.store(true); }
}  // namespace

void install_interrupt_handlers() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
}

bool interrupted() { return g_interrupted.load(); }

ProgressFn terminal_progress(const std::string& label) {
    const bool tty = ::isatty(STDERR_FILENO);
    return [label, tty](double fraction) {
        if (tty) {
            const int width = 30, full = static_cast<int>(fraction * width + 0.5);
            std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label.c_str(), full, "##############################",
                         width - full, "", static_cast<int>(fraction * 100 + 0.5));
            std::fflush(stderr);
            g_drawn = true;
        }
        return !g_interrupted.load();
    };
}

void finish_progress() {
    if (g_drawn) std::fputc('\n', stderr);
    g_drawn = false;
}

}  // namespace wavecam::cli
