// Core's threads: teams from one pool whose threads spin briefly and then sleep.
//
// A parallel region is a team of `threads` (the caller is rank 0, the pool's threads the rest),
// each running the same body, in the manner of an OpenMP region: loops split among the team
// (`for_blocks` as OpenMP's schedule(static), `for_strided` as schedule(static, chunk),
// `for_dynamic` as schedule(dynamic, chunk)), each ending at a barrier, and `barrier()`.
// A region started inside another runs on its caller alone (a team of one), as OpenMP's nested
// regions do by default. Teams asked for at once from several host threads each get their own
// threads, so that a team has the size asked for and a region's partition never depends on what
// else runs.
//
// Waiting threads (at a barrier, at the end of a region, idle in the pool) spin for about
// kSpinMicroseconds and then sleep on a futex: on cores that other processes share they give
// their core back to the thread being waited for, and inside a host (oiiotool, Blender) they
// neither depend on nor disturb the host's own threads.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <type_traits>

#include "wavecam/threads.h"

namespace wavecam::detail {

constexpr int kSpinMicroseconds = 100;

using wavecam::default_threads;
inline int thread_count(int nthreads) { return nthreads > 0 ? nthreads : default_threads(); }
// Whether this is the thread that started the work (not one of the pool's): the one that reports
// progress.
bool on_calling_thread();

struct TeamState;

class Team {
public:
    Team(TeamState* state, int rank, int size) : state_(state), rank_(rank), size_(size) {}
    int rank() const { return rank_; }
    int size() const { return size_; }
    // Every thread of the team waits here for the others.
    void barrier();

    // [begin, end) in `size()` contiguous blocks, the first (end - begin) % size() one longer;
    // this thread runs block rank(). Then a barrier.
    template <class F>
    void for_blocks(int64_t begin, int64_t end, F&& f) {
        const int64_t n = end - begin, q = n / size_, r = n % size_;
        const int64_t a = begin + rank_ * q + std::min<int64_t>(rank_, r), b = a + q + (rank_ < r ? 1 : 0);
        for (int64_t i = a; i < b; ++i) f(i);
        barrier();
    }
    // Chunks of `chunk` dealt in turn: chunk c to rank c % size(). Then a barrier.
    template <class F>
    void for_strided(int64_t begin, int64_t end, int64_t chunk, F&& f) {
        for (int64_t a = begin + rank_ * chunk; a < end; a += chunk * size_)
            for (int64_t i = a, b = std::min(end, a + chunk); i < b; ++i) f(i);
        barrier();
    }
    // Chunks of `chunk` taken by whichever thread comes free. Then a barrier.
    template <class F>
    void for_dynamic(int64_t begin, int64_t end, int64_t chunk, F&& f) {
        std::atomic<int64_t>& next = dynamic_counter();
        for (int64_t a; (a = begin + next.fetch_add(chunk, std::memory_order_relaxed)) < end;)
            for (int64_t i = a, b = std::min(end, a + chunk); i < b; ++i) f(i);
        finish_dynamic();
    }

private:
    std::atomic<int64_t>& dynamic_counter();
    void finish_dynamic();
    TeamState* state_;
    int rank_, size_;
    int dynamic_loops_ = 0;
};

// A callable seen through a pointer, for the pool (which runs it on other threads while the
// caller waits, so the callable outlives every call).
class TeamBody {
public:
    template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, TeamBody>>>
    explicit TeamBody(F& f) : object_(&f), call_([](void* o, Team& t) { (*static_cast<F*>(o))(t); }) {}
    void operator()(Team& t) const { call_(object_, t); }

private:
    void* object_;
    void (*call_)(void*, Team&);
};

// Runs body(team) on a team of `threads` (at least 1) and returns when every thread has. The
// first exception a body throws comes back from here once the team is done; the team's other
// threads leave their bodies at their next barrier (or loop's end) instead of waiting there.
void run_team(int threads, TeamBody body);

template <class F>
void parallel_team(int threads, F&& body) {
    run_team(threads, TeamBody(body));
}

// f(i) for i in [begin, end) over `threads` threads in contiguous blocks (schedule(static)).
template <class F>
void parallel_for(int64_t begin, int64_t end, int threads, F&& f) {
    const int64_t n = end - begin;
    if (n <= 0) return;
    const int team = int(std::min<int64_t>(std::max(threads, 1), n));
    if (team == 1) {
        for (int64_t i = begin; i < end; ++i) f(i);
        return;
    }
    parallel_team(team, [&](Team& t) { t.for_blocks(begin, end, f); });
}

// f(i) for i in [begin, end), chunks of `chunk` taken as threads come free (schedule(dynamic)).
template <class F>
void parallel_for_dynamic(int64_t begin, int64_t end, int64_t chunk, int threads, F&& f) {
    const int64_t n = end - begin;
    if (n <= 0) return;
    const int team = int(std::min<int64_t>(std::max(threads, 1), (n + chunk - 1) / chunk));
    if (team == 1) {
        for (int64_t i = begin; i < end; ++i) f(i);
        return;
    }
    parallel_team(team, [&](Team& t) { t.for_dynamic(begin, end, chunk, f); });
}

}  // namespace wavecam::detail
