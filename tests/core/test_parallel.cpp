// Core's thread pool (core/src/base/parallel.h): every loop covers its range once and splits it
// as its schedule says, barriers hold, nested regions run alone, concurrent teams get the size
// they ask for, a body's exception comes back to the caller, and waiting threads sleep.
#include <gtest/gtest.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "base/parallel.h"

namespace wavecam::detail {
namespace {

TEST(Parallel, BlocksSplitTheRangeAsOpenMpsStaticSchedule) {
    for (const int threads : {1, 2, 3, 5}) {
        for (const int64_t n : {0, 1, 4, 7, 100, 1001}) {
            std::vector<int> rank_of(size_t(n), -1);
            parallel_team(threads, [&](Team& team) {
                team.for_blocks(10, 10 + n, [&](int64_t i) { rank_of[size_t(i - 10)] = team.rank(); });
            });
            // the first n % threads ranks hold one more: rank r holds [r q + min(r, n % T), ...)
            const int64_t q = n / threads, r = n % threads;
            for (int64_t i = 0; i < n; ++i) {
                int expected = 0;
                while ((expected + 1) * q + std::min<int64_t>(expected + 1, r) <= i) ++expected;
                ASSERT_EQ(rank_of[size_t(i)], expected) << threads << " threads, " << n << " items, item " << i;
            }
        }
    }
}

TEST(Parallel, StridedChunksGoToTheRanksInTurn) {
    const int threads = 3;
    const int64_t n = 50, chunk = 4;
    std::vector<int> rank_of(n, -1);
    parallel_team(threads, [&](Team& team) {
        team.for_strided(0, n, chunk, [&](int64_t i) { rank_of[size_t(i)] = team.rank(); });
    });
    for (int64_t i = 0; i < n; ++i) EXPECT_EQ(rank_of[size_t(i)], int((i / chunk) % threads)) << i;
}

TEST(Parallel, DynamicLoopsInARowEachCoverTheirRangeOnce) {
    const int threads = 4, loops = 7;
    std::vector<std::atomic<int>> count(size_t(loops) * 1000);
    parallel_team(threads, [&](Team& team) {
        for (int l = 0; l < loops; ++l)
            team.for_dynamic(0, 997, 1 + l, [&](int64_t i) { count[size_t(l) * 1000 + i].fetch_add(1); });
    });
    for (int l = 0; l < loops; ++l)
        for (int i = 0; i < 1000; ++i) ASSERT_EQ(count[size_t(l) * 1000 + i].load(), i < 997 ? 1 : 0) << l << " " << i;
    std::vector<std::atomic<int>> once(5000);
    parallel_for_dynamic(0, 5000, 3, threads, [&](int64_t i) { once[size_t(i)].fetch_add(1); });
    parallel_for(0, 5000, threads, [&](int64_t i) { once[size_t(i)].fetch_add(1); });
    for (const auto& c : once) ASSERT_EQ(c.load(), 2);
}

TEST(Parallel, NoThreadPassesABarrierBeforeEveryThreadReachesIt) {
    const int threads = 4, rounds = 200;
    std::vector<int> written(threads, -1);
    std::atomic<int> wrong{0};
    parallel_team(threads, [&](Team& team) {
        for (int round = 0; round < rounds; ++round) {
            written[size_t(team.rank())] = round;
            team.barrier();
            for (int other = 0; other < threads; ++other)
                if (written[size_t(other)] != round) wrong.fetch_add(1);
            team.barrier();
        }
    });
    EXPECT_EQ(wrong.load(), 0);
}

TEST(Parallel, ARegionInsideAnotherRunsOnItsCallerAlone) {
    std::mutex m;
    std::set<std::pair<std::thread::id, int>> inner;  // (thread, inner team size)
    parallel_team(3, [&](Team&) {
        parallel_team(4, [&](Team& nested) {
            std::lock_guard<std::mutex> lock(m);
            inner.insert({std::this_thread::get_id(), nested.size()});
            EXPECT_EQ(nested.rank(), 0);
        });
    });
    ASSERT_EQ(inner.size(), 3u);  // one nested team per outer thread, each of one thread
    for (const auto& [id, size] : inner) EXPECT_EQ(size, 1);
}

TEST(Parallel, TeamsAskedForAtOnceEachGetTheirSize) {
    const int hosts = 4, threads = 3;
    std::vector<std::set<std::thread::id>> seen(hosts);
    std::vector<std::thread> callers;
    for (int h = 0; h < hosts; ++h)
        callers.emplace_back([&, h] {
            for (int repeat = 0; repeat < 20; ++repeat) {
                std::mutex m;
                std::set<std::thread::id> ids;
                parallel_team(threads, [&](Team& team) {
                    EXPECT_EQ(team.size(), threads);
                    std::lock_guard<std::mutex> lock(m);
                    ids.insert(std::this_thread::get_id());
                });
                EXPECT_EQ(int(ids.size()), threads);
                seen[size_t(h)].insert(ids.begin(), ids.end());
            }
        });
    for (std::thread& t : callers) t.join();
    for (int h = 0; h < hosts; ++h) EXPECT_GE(int(seen[size_t(h)].size()), threads);
}

TEST(Parallel, AnExceptionInAnyThreadReachesTheCaller) {
    EXPECT_THROW(parallel_for(0, 100, 4, [&](int64_t i) {
                     if (i == 99) throw std::runtime_error("last block");
                 }),
                 std::runtime_error);
    EXPECT_THROW(parallel_team(1, [&](Team&) { throw std::runtime_error("alone"); }), std::runtime_error);
    // a thread that throws before a barrier leaves none of the others waiting there
    for (const int thrower : {0, 2})
        EXPECT_THROW(parallel_team(3,
                                   [&](Team& team) {
                                       if (team.rank() == thrower) throw std::runtime_error("before the barrier");
                                       team.barrier();
                                       team.for_dynamic(0, 10, 1, [](int64_t) {});
                                   }),
                     std::runtime_error);
    // and the pool still works after it
    std::atomic<int> sum{0};
    parallel_for(0, 100, 4, [&](int64_t i) { sum += int(i); });
    EXPECT_EQ(sum.load(), 4950);
}

double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Threads that wait (at a barrier, or at the end of a region for a slow rank 0) sleep after a
// short spin: three threads waiting 300 ms use a few milliseconds of CPU between them, where
// spinning would use 900 ms.
TEST(Parallel, WaitingThreadsSleepAfterAShortSpin) {
    parallel_for(0, 4, 4, [](int64_t) {});  // the pool's threads started
    const double cpu0 = process_cpu_seconds();
    const auto wall0 = std::chrono::steady_clock::now();
    parallel_team(4, [&](Team& team) {
        if (team.rank() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(150));
        team.barrier();
        if (team.rank() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(150));
    });
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const double cpu = process_cpu_seconds() - cpu0;
    EXPECT_GE(wall, 0.3);
    EXPECT_LT(cpu, 0.1) << "CPU seconds while three threads waited " << wall << " s";
}

TEST(Parallel, TheCallingThreadReportsProgress) {
    std::atomic<int> reports{0};
    parallel_for(0, 64, 4, [&](int64_t) {
        if (on_calling_thread()) ++reports;
    });
    EXPECT_EQ(reports.load(), 16);  // rank 0's block
    EXPECT_TRUE(on_calling_thread());
    std::atomic<int> workers{0};
    parallel_team(4, [&](Team& team) {
        if (team.rank() > 0 && !on_calling_thread()) ++workers;
    });
    EXPECT_EQ(workers.load(), 3);
}

}  // namespace
}  // namespace wavecam::detail
