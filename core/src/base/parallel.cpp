#include "base/parallel.h"

#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace wavecam::detail {

struct TeamState {
    TeamState(int size, TeamBody body) : size(size), body(body) {}
    int size;
    TeamBody body;
    std::atomic<int> arrived{0};
    std::atomic<uint32_t> generation{0};
    std::atomic<int> sleepers{0};
    std::atomic<int64_t> next[2]{{0}, {0}};
    std::atomic<bool> broken{false};  // a body threw: every barrier throws TeamAborted
    std::mutex error_mutex;
    std::exception_ptr error;
};

namespace {

thread_local bool t_in_team = false;      // inside a region: a nested one runs alone
thread_local bool t_pool_thread = false;  // one of the pool's threads

void relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

// Returns once `word` differs from `value`: a spin of about kSpinMicroseconds, then a futex
// sleep. `sleepers` counts the sleepers so that a waker with none makes no system call; the
// word and the count are both seq_cst, so that a waker either sees the sleeper or the sleeper
// sees the new word.
void wait_while(std::atomic<uint32_t>& word, uint32_t value, std::atomic<int>& sleepers) {
    const auto start = std::chrono::steady_clock::now();
    for (int k = 1;; ++k) {
        if (word.load(std::memory_order_acquire) != value) return;
        relax();
        if (k % 64 == 0 && std::chrono::steady_clock::now() - start > std::chrono::microseconds(kSpinMicroseconds))
            break;
    }
    sleepers.fetch_add(1);
    while (word.load() == value)
        syscall(SYS_futex, reinterpret_cast<uint32_t*>(&word), FUTEX_WAIT_PRIVATE, value, nullptr, nullptr, 0);
    sleepers.fetch_sub(1);
}

// After `word` changed: wakes whoever sleeps on it.
void wake(std::atomic<uint32_t>& word, std::atomic<int>& sleepers) {
    if (sleepers.load() > 0)
        syscall(SYS_futex, reinterpret_cast<uint32_t*>(&word), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0);
}

// What a barrier throws in a team whose body threw elsewhere, so that no thread waits for one
// that will not come.
struct TeamAborted {};

// Records the first exception of a team's bodies and releases every thread at a barrier.
void record_failure(TeamState& s, std::exception_ptr e) {
    {
        std::lock_guard<std::mutex> lock(s.error_mutex);
        if (!s.error) s.error = e;
    }
    s.broken.store(true);
    s.generation.fetch_add(1);
    wake(s.generation, s.sleepers);
}

// body(team), its exception recorded.
void run_rank(TeamState& s, Team& team) {
    try {
        s.body(team);
    } catch (const TeamAborted&) {
    } catch (...) {
        record_failure(s, std::current_exception());
    }
}

// One of the pool's threads: it runs one rank of one team at a time. It lives as long as the
// process (the pool is never destroyed, so that no thread outlives what it waits on at exit).
struct Worker {
    std::atomic<uint32_t> ticket{0};    // raised by the caller: a team to join
    std::atomic<uint32_t> finished{0};  // raised by the worker: its rank is done
    std::atomic<int> ticket_sleepers{0}, finished_sleepers{0};
    TeamState* state = nullptr;
    int rank = 0;

    void start(TeamState* s, int r) {
        state = s;
        rank = r;
        ticket.fetch_add(1);
        wake(ticket, ticket_sleepers);
    }
    void join() { wait_while(finished, ticket.load(std::memory_order_relaxed) - 1, finished_sleepers); }

    void loop() {
        t_in_team = t_pool_thread = true;
        for (uint32_t seen = 0;; ++seen) {
            wait_while(ticket, seen, ticket_sleepers);
            TeamState& s = *state;
            Team team(&s, rank, s.size);
            run_rank(s, team);
            // the team's state is the caller's: not touched once it may return
            finished.fetch_add(1);
            wake(finished, finished_sleepers);
        }
    }
};

class Pool {
public:
    // n idle workers, started where there are fewer.
    std::vector<Worker*> take(int n) {
        std::vector<Worker*> taken;
        std::lock_guard<std::mutex> lock(mutex_);
        while (int(taken.size()) < n && !idle_.empty()) {
            taken.push_back(idle_.back());
            idle_.pop_back();
        }
        while (int(taken.size()) < n) {
            auto* w = new Worker;  // lives as long as the process
            std::thread([w] { w->loop(); }).detach();
            taken.push_back(w);
        }
        return taken;
    }
    void give_back(const std::vector<Worker*>& workers) {
        std::lock_guard<std::mutex> lock(mutex_);
        idle_.insert(idle_.end(), workers.begin(), workers.end());
    }

private:
    std::mutex mutex_;
    std::vector<Worker*> idle_;
};

Pool* g_pool = nullptr;
std::once_flag g_pool_once;

Pool& pool() {
    std::call_once(g_pool_once, [] {
        g_pool = new Pool;
        // a forked child has none of the parent's threads: it starts a pool of its own
        pthread_atfork(nullptr, nullptr, [] { g_pool = new Pool; });
    });
    return *g_pool;
}

int threads_from_environment() {
    if (const char* v = std::getenv("OMP_NUM_THREADS")) {
        const int n = std::atoi(v);  // the first of a list: the outermost level's
        if (n > 0) return n;
    }
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
    return int(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace

}  // namespace wavecam::detail

namespace wavecam {

int default_threads() {
    static const int n = detail::threads_from_environment();
    return n;
}

void parallel_for(int64_t begin, int64_t end, int threads, const std::function<void(int64_t)>& f) {
    detail::parallel_for(begin, end, detail::thread_count(threads), f);
}

}  // namespace wavecam

namespace wavecam::detail {

bool on_calling_thread() { return !t_pool_thread; }

void Team::barrier() {
    if (size_ == 1) return;
    TeamState& s = *state_;
    // (the generation read before `broken`: a failure recorded after this read raises it)
    const uint32_t generation = s.generation.load();
    if (s.broken.load()) throw TeamAborted{};
    if (s.arrived.fetch_add(1, std::memory_order_acq_rel) == size_ - 1) {
        s.arrived.store(0, std::memory_order_relaxed);
        s.generation.fetch_add(1);
        wake(s.generation, s.sleepers);
    } else {
        wait_while(s.generation, generation, s.sleepers);
    }
    if (s.broken.load()) throw TeamAborted{};
}

// Dynamic loops alternate between two counters: loop k's is reset by rank 0 after the barrier
// that ends it, and loop k + 2 (the next to use it) starts only after loop k + 1's barrier.
std::atomic<int64_t>& Team::dynamic_counter() { return state_->next[dynamic_loops_ & 1]; }

void Team::finish_dynamic() {
    barrier();
    if (rank_ == 0) state_->next[dynamic_loops_ & 1].store(0, std::memory_order_relaxed);
    ++dynamic_loops_;
}

void run_team(int threads, TeamBody body) {
    if (threads <= 1 || t_in_team) {
        TeamState alone(1, body);
        Team team(&alone, 0, 1);
        body(team);
        return;
    }
    TeamState s(threads, body);
    const std::vector<Worker*> workers = pool().take(threads - 1);
    for (int k = 0; k < threads - 1; ++k) workers[size_t(k)]->start(&s, k + 1);
    t_in_team = true;
    Team team(&s, 0, threads);
    run_rank(s, team);
    t_in_team = false;
    for (Worker* w : workers) w->join();
    pool().give_back(workers);
    if (s.error) std::rethrow_exception(s.error);
}

}  // namespace wavecam::detail
