#include "terminal_progress.h"

#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sstream>

#include "wavecam/atomic_write.h"
#include "wavecam/term_rate.h"
#include "../front/estimate_line.h"

namespace wavecam::cli {
namespace {
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};
bool g_drawn = false;
char g_stop_message[512] = "\nwavecam: interrupted\n";
std::atomic<size_t> g_stop_length{sizeof "\nwavecam: interrupted\n" - 1};
constexpr long kGraceMicroseconds = 1500000;  // the work's own stop, before the watchdog's

// The watchdog: work that has not stopped within the grace time after a signal (a loop
// that does not ask, a read that blocks), or a second signal, ends the process here: the
// temporary being written is removed, the target never touched. Async-signal-safe only.
extern "C" void stop_now(int) {
    if (const char* temp = temporary_being_written()) ::unlink(temp);
    [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, g_stop_message, g_stop_length.load());
    const int sig = g_signal.load();
    ::_exit(128 + (sig > 0 ? sig : SIGINT));
}

extern "C" void on_signal(int sig) {
    if (g_interrupted.load()) stop_now(sig);  // a second signal: now
    g_signal.store(sig);  // (before the flag: whoever sees the flag finds its signal)
    g_interrupted.store(true);
    itimerval grace{};
    grace.it_value.tv_sec = kGraceMicroseconds / 1000000;
    grace.it_value.tv_usec = kGraceMicroseconds % 1000000;
    ::setitimer(ITIMER_REAL, &grace, nullptr);
}
using Clock = std::chrono::steady_clock;
}  // namespace

void install_interrupt_handlers() {
    set_write_cancel_check([] { return g_interrupted.load(); });
    std::signal(SIGALRM, stop_now);
    // every signal that ends a process by default and can be caught: the run stops as at SIGINT,
    // its temporary removed, the old output kept, exit 128 + N
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXCPU, SIGXFSZ, SIGUSR1, SIGUSR2})
        std::signal(sig, on_signal);
}

bool interrupted() { return g_interrupted.load(); }

void set_interrupt_message(const std::string& message) {
    const std::string line = "\n" + message.substr(0, sizeof g_stop_message - 3) + "\n";
    g_stop_length.store(0);
    std::memcpy(g_stop_message, line.data(), line.size());
    g_stop_length.store(line.size());
}

int interrupted_status() {
    const int sig = g_signal.load();
    return 128 + (sig > 0 ? sig : SIGINT);
}

void print_estimate(const std::string& label, const JobEstimate& e) {
    std::fprintf(stderr, "%s: %s\n", label.c_str(), front::estimate_line(e).c_str());
    std::fflush(stderr);
}

std::string aperture_work(const Aperture& aperture, double samples) {
    std::ostringstream s;
    s.precision(3);
    s << "aperture " << aperture.name();
    if (aperture.shape == ApertureShape::PhotonSieve) {
        long holes = 1;  // the central disc
        for (const SieveRing& ring : sieve_rings(aperture.sieve())) holes += ring.holes;
        s << " (" << holes << " holes)";
    } else if (aperture.shape == ApertureShape::ZonePlate) {
        s << " (" << aperture.zones << " zones)";
    }
    s << ": about " << samples << " pinhole samples per PSF";
    return s.str();
}

ProgressFn terminal_progress(const std::string& label) {
    struct State {
        bool tty = ::isatty(STDERR_FILENO);
        Clock::time_point start = Clock::now(), last_line = start;
        double last_fraction = 0;
    };
    auto st = std::make_shared<State>();
    return [label, st](double fraction) {
        const auto now = Clock::now();
        const double elapsed = std::chrono::duration<double>(now - st->start).count();
        const double since = std::chrono::duration<double>(now - st->last_line).count();
        const bool known = fraction > 0.001 && elapsed > 1;  // enough done to extrapolate
        const std::string left = known ? front::format_duration(elapsed / fraction * (1 - fraction)) + " left" : "estimating";
        if (st->tty) {
            const int width = 30, full = static_cast<int>(fraction * width + 0.5);
            std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%  %-16s", label.c_str(), full, "##############################",
                         width - full, "", static_cast<int>(fraction * 100 + 0.5), left.c_str());
            g_drawn = true;
        } else if (since >= 10 || (fraction - st->last_fraction >= 0.05 && since >= 1)) {
            std::fprintf(stderr, "%s: %d%% after %s, %s\n", label.c_str(), static_cast<int>(fraction * 100),
                         front::format_duration(elapsed).c_str(), (known ? "about " + left : left).c_str());
            st->last_line = now;
            st->last_fraction = fraction;
        }
        std::fflush(stderr);
        return !g_interrupted.load();
    };
}

void finish_progress() {
    if (g_drawn) std::fputc('\n', stderr);
    g_drawn = false;
}

}  // namespace wavecam::cli
