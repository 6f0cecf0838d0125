// tracers/progress.h — tracers::WorkProgress: how much of an image computation is done, for a
// caller to poll from another thread (apps/progress.h draws it); the library itself prints nothing.
//
// Contract: the computation sets `total` before its first unit is done and then adds one to `done`
// per unit finished (a tile), so that done <= total and done == total at the end of a run that did
// not throw. Both are relaxed atomics: a reader sees a count that is at most briefly behind.
#pragma once

#include <atomic>
#include <cstdint>

namespace certray::tracers {

/// Units (tiles) done out of a total; see the file contract.
struct WorkProgress {
    std::atomic<std::uint64_t> done{0};   ///< units finished so far
    std::atomic<std::uint64_t> total{0};  ///< units in the whole computation
};

}  // namespace certray::tracers
