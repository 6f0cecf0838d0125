// tracers/parallel.h — the one way certray spreads work over threads.
//
// Contract: parallel_for(n, options, body) calls body(begin, end) on disjoint ranges covering
// [0, n) exactly once, from `threads` workers (the calling thread is one of them), in chunks
// taken in increasing order. Each worker runs in the library's floating-point environment
// (NearestScope). The first exception a body throws stops the others at their next chunk and is
// rethrown to the caller; a set cancel flag stops them the same way and parallel_for returns
// false. `progress(done, n)` is called from the calling thread only, about every
// `progress_period`, and once at the end of a run that was not stopped.
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

/// Runs body over [0, n) (see the file contract). Returns false when cancelled.
bool parallel_for(std::size_t n, const ParallelOptions& options,
                  const std::function<void(std::size_t begin, std::size_t end)>& body);

}  // namespace certray::tracers
