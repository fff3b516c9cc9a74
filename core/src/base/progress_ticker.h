// Shared progress accounting for the parallel loops: workers count finished items, the thread
// that started the work (a team's rank 0, on_calling_thread in base/parallel.h) reports at most
// ~10 times a second and records a cancel.
#pragma once
#include <atomic>
#include <chrono>
#include "wavecam/progress.h"

namespace wavecam::detail {

class ProgressTicker {
public:
    ProgressTicker(const ProgressFn& fn, double total) : fn_(fn), total_(total) {}

    // Called by any worker after finishing `n` items; only the reporting thread invokes the callback.
    void advance(long n, bool reporter) {
        done_.fetch_add(n, std::memory_order_relaxed);
        if (!fn_ || !reporter) return;
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        if (!fn_(double(done_.load(std::memory_order_relaxed)) / total_))
            cancelled_.store(true, std::memory_order_relaxed);
    }
    bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

private:
    const ProgressFn& fn_;
    double total_;
    std::atomic<long> done_{0};
    std::atomic<bool> cancelled_{false};
    std::chrono::steady_clock::time_point last_{};
};

}  // namespace wavecam::detail
