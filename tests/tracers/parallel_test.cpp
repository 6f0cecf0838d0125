// tests/tracers/parallel_test.cpp — run_workers and its pool of threads (tracers/parallel.h): each
// index once, worker 0 on the calling thread, exceptions, nesting, concurrent callers, polling,
// the floating-point environment, a child process after fork, and no thread to be had.
#include "tracers/parallel.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cfenv>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace certray::tracers {
namespace {

/// Runs run_workers(workers) and returns how often each index ran.
std::vector<int> counts_of(unsigned workers) {
    std::vector<std::atomic<int>> seen(workers);
    run_workers(workers, [&](unsigned k) { seen.at(k).fetch_add(1); });
    std::vector<int> out;
    for (auto& s : seen) out.push_back(s.load());
    return out;
}

TEST(RunWorkers, EachIndexOnceOverManyRuns) {
    prestart_workers(4);
    for (int run = 0; run < 300; ++run) {
        const unsigned workers = 1 + static_cast<unsigned>(run % 6);  // the pool grows and shrinks
        EXPECT_EQ(counts_of(workers), std::vector<int>(workers, 1)) << "run " << run;
    }
}

TEST(RunWorkers, WorkerZeroRunsOnTheCaller) {
    const std::thread::id me = std::this_thread::get_id();
    std::vector<std::thread::id> ids(3);
    run_workers(3, [&](unsigned k) { ids[k] = std::this_thread::get_id(); });
    EXPECT_EQ(ids[0], me);
    EXPECT_NE(ids[1], me);
    EXPECT_NE(ids[2], me);
}

TEST(RunWorkers, TheWorkersRunTogether) {
    // Two workers that each wait (bounded) for the other to have started: they must overlap.
    std::atomic<int> started{0};
    std::atomic<int> met{0};
    run_workers(2, [&](unsigned) {
        started.fetch_add(1);
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (started.load() < 2 && std::chrono::steady_clock::now() < until) {
            std::this_thread::yield();
        }
        if (started.load() == 2) met.fetch_add(1);
    });
    EXPECT_EQ(met.load(), 2);
}

TEST(RunWorkers, TheFirstExceptionAfterAllHaveReturned) {
    std::atomic<int> finished{0};
    EXPECT_THROW(run_workers(4,
                             [&](unsigned k) {
                                 if (k == 2) throw std::runtime_error("worker 2");
                                 std::this_thread::sleep_for(std::chrono::milliseconds(20));
                                 finished.fetch_add(1);
                             }),
                 std::runtime_error);
    EXPECT_EQ(finished.load(), 3);
    EXPECT_EQ(counts_of(4), std::vector<int>(4, 1));  // the pool serves the next run
}

TEST(RunWorkers, NestedRunsComplete) {
    std::atomic<int> inner{0};
    run_workers(3, [&](unsigned) { run_workers(3, [&](unsigned) { inner.fetch_add(1); }); });
    EXPECT_EQ(inner.load(), 9);
}

TEST(RunWorkers, ConcurrentCallersEachGetTheirRun) {
    std::vector<std::thread> callers;
    std::atomic<int> wrong{0};
    for (int c = 0; c < 4; ++c) {
        callers.emplace_back([&] {
            for (int run = 0; run < 50; ++run) {
                if (counts_of(3) != std::vector<int>(3, 1)) wrong.fetch_add(1);
            }
        });
    }
    for (std::thread& t : callers) t.join();
    EXPECT_EQ(wrong.load(), 0);
}

TEST(RunWorkers, PollingCallerRunsNoWorker) {
    const std::thread::id me = std::this_thread::get_id();
    std::atomic<int> on_caller{0};
    std::atomic<int> ran{0};
    int polls = 0;
    run_workers(
        2,
        [&](unsigned) {
            if (std::this_thread::get_id() == me) on_caller.fetch_add(1);
            std::this_thread::sleep_for(std::chrono::milliseconds(30));
            ran.fetch_add(1);
        },
        [&] { ++polls; }, std::chrono::milliseconds(1));
    EXPECT_EQ(ran.load(), 2);
    EXPECT_EQ(on_caller.load(), 0);
    EXPECT_GE(polls, 1);
}

TEST(RunWorkers, APollThatThrowsWaitsForTheWorkers) {
    // The workers refer to the caller's frame: the poll's exception reaches the caller only after
    // they have all returned, and the pool serves the next run.
    std::atomic<int> ran{0};
    EXPECT_THROW(run_workers(
                     3,
                     [&](unsigned) {
                         std::this_thread::sleep_for(std::chrono::milliseconds(30));
                         ran.fetch_add(1);
                     },
                     [] { throw std::runtime_error("progress"); }, std::chrono::milliseconds(1)),
                 std::runtime_error);
    EXPECT_EQ(ran.load(), 3);
    EXPECT_EQ(counts_of(3), std::vector<int>(3, 1));
    // The same where the pool is busy (nested in a worker): the run's own threads.
    std::atomic<int> inner{0};
    std::atomic<int> caught{0};
    run_workers(2, [&](unsigned) {
        try {
            run_workers(
                2,
                [&](unsigned) {
                    std::this_thread::sleep_for(std::chrono::milliseconds(10));
                    inner.fetch_add(1);
                },
                [] { throw std::runtime_error("progress"); }, std::chrono::milliseconds(1));
        } catch (const std::runtime_error&) {
            caught.fetch_add(1);
        }
    });
    EXPECT_EQ(inner.load(), 4);
    EXPECT_EQ(caught.load(), 2);
}

TEST(RunWorkers, WorkersRoundToNearestWhateverTheCaller) {
    // 1 + 2^-60 is 1 rounded to nearest and the next double rounded upward: each worker, on the
    // caller's thread or the pool's, computes in the library's environment (NearestScope).
    const int saved = std::fegetround();
    ASSERT_EQ(std::fesetround(FE_UPWARD), 0);
    std::vector<double> sums(3, 0.0);
    volatile double one = 1.0, tiny = 0x1p-60;
    run_workers(3, [&](unsigned k) { sums[k] = one + tiny; });
    std::fesetround(saved);
    for (double s : sums) EXPECT_EQ(s, 1.0);
}

TEST(RunWorkers, AChildProcessAfterForkHasItsOwnThreads) {
    EXPECT_EQ(counts_of(3), std::vector<int>(3, 1));  // the parent's pool exists
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // The parent's pool threads do not exist here: a run must not wait for them (were it to,
        // the alarm ends the child and the test fails instead of hanging).
        alarm(20);
        const bool ok = counts_of(3) == std::vector<int>(3, 1);
        _exit(ok ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

// Where no thread can be started (an address space too small for a thread's stack), each index
// still runs once, on the calling thread, with or without polling; nothing throws or terminates.
// In a child process, whose pool is its own (the sanitizers' shadow memory needs more room).
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
TEST(RunWorkers, WithoutThreadsEachIndexRunsOnTheCaller) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        alarm(20);
        long pages = 0;  // the address space in use now
        if (FILE* f = std::fopen("/proc/self/statm", "r")) {
            if (std::fscanf(f, "%ld", &pages) != 1) pages = 0;
            std::fclose(f);
        }
        const rlim_t used = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE));
        const rlimit limit{used + (4u << 20), used + (4u << 20)};  // less than a thread's stack
        if (pages == 0 || setrlimit(RLIMIT_AS, &limit) != 0) _exit(3);
        // Threads that never end, until none can be started: the stacks of exited threads that
        // the C library keeps for reuse are taken too.
        bool threads_fail = false;
        for (int k = 0; k < 1000 && !threads_fail; ++k) {
            try {
                std::thread([] {
                    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
                }).detach();
            } catch (const std::system_error&) {
                threads_fail = true;
            }
        }
        if (!threads_fail) _exit(4);  // the limit did not bite: nothing tested
        prestart_workers(4);
        bool ok = counts_of(4) == std::vector<int>(4, 1);
        std::vector<std::atomic<int>> seen(3);
        int polls = 0;
        run_workers(
            3, [&](unsigned k) { seen.at(k).fetch_add(1); }, [&] { ++polls; },
            std::chrono::milliseconds(1));
        for (auto& s : seen) ok = ok && s.load() == 1;
        _exit(ok ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "3: no limit set, 4: threads still start, 1: an index "
                                         "not run once";
}
#endif

TEST(ParallelFor, CoversEveryIndexOnce) {
    std::vector<std::atomic<int>> seen(1000);
    ParallelOptions po;
    po.threads = 3;
    po.chunk = 7;
    EXPECT_TRUE(parallel_for(seen.size(), po, [&](std::size_t b, std::size_t e, unsigned) {
        for (std::size_t i = b; i < e; ++i) seen[i].fetch_add(1);
    }));
    for (auto& s : seen) EXPECT_EQ(s.load(), 1);
}

}  // namespace
}  // namespace certray::tracers
