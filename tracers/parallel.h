// tracers/parallel.h — the one way certray spreads work over threads.
//
// Contract: run_workers(workers, fn) calls fn(k) once for each k in [0, workers) and returns when
// all have returned: the calling thread runs k = 0 unless it polls, the others run on threads kept
// between calls (a pool; one thread may run two k one after the other where another wakes late,
// so fn must not wait for another k), or on threads of the call's own where the pool is busy (a
// call on another thread, or one nested in a worker); a k that no thread can be started for runs
// on the calling thread, before its own part. Each worker runs in the library's
// floating-point environment (NearestScope). The first exception a worker throws is rethrown to
// the caller after all have returned. An idle pool thread spins for a few milliseconds before it
// sleeps (a sleeping core can be slow to wake); prestart_workers(threads) starts them early, as the
// command line does while it reads the scene.
// parallel_for(n, options, body) calls body(begin, end, worker) on disjoint ranges covering
// [0, n) exactly once, in chunks taken in increasing order by `worker_count(threads)` workers;
// the first exception stops the others at their next chunk; a set cancel flag stops them the same
// way and parallel_for returns false. `progress(done, n)` is called from the calling thread only,
// about every `progress_period`, and once at the end of a run that was not stopped.
// Used by certray::query, the 3D and 2D renders and the bench: one implementation of threads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>

namespace certray::tracers {

struct ParallelOptions {
    unsigned threads = 0;    ///< workers; 0: one per hardware thread
    std::size_t chunk = 64;  ///< indices a worker takes at a time
    /// Called on the calling thread with (done, total) while the work runs; may be empty.
    std::function<void(std::size_t, std::size_t)> progress;
    std::chrono::milliseconds progress_period{200};
    /// Set (by any thread) to stop early; may be null.
    const std::atomic<bool>* cancel = nullptr;
};

/// The number of workers `threads` means: itself if > 0, else the hardware threads (at least 1).
unsigned worker_count(unsigned threads);

/// Starts the pool's threads for runs of `threads` workers (0: one per hardware thread) now, so
/// that they are awake when the first run comes (see the file contract).
void prestart_workers(unsigned threads);

/// Runs fn(0) … fn(workers − 1) (see the file contract). With `poll`, the
/// calling thread runs no worker and calls poll() about every `period` until all have returned.
void run_workers(unsigned workers, const std::function<void(unsigned)>& fn,
                 const std::function<void()>& poll = {},
                 std::chrono::milliseconds period = std::chrono::milliseconds(200));

/// Runs body over [0, n) (see the file contract). Returns false when cancelled.
bool parallel_for(
    std::size_t n, const ParallelOptions& options,
    const std::function<void(std::size_t begin, std::size_t end, unsigned worker)>& body);

}  // namespace certray::tracers
