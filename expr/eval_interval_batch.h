// expr/eval_interval_batch.h — the interval tape walk over several boxes at once (lanes).
//
// Contract: run_interval_batch runs a tape's instructions (or an SSA list) over n ≤
// kIntervalLanes boxes, and lane i of every register it writes is bit for bit what
// detail::run<UpInterval> (expr/eval.h) computes for box i: both bounds (a signed zero included),
// the decoration, and the empty interval (NaN bounds, not defined). Each op applies the formulas
// of the scalar UpInterval kernels (interval/interval.h) to a vector of lanes — + − × square
// neg abs min max sqrt, and exp and log with one switch to round-to-nearest for all lanes of the
// instruction — and the lanes those kernels send to Boost's case tables (infinities, 0 · ∞,
// empty operands), as well as every other op, call the scalar UpInterval operation lane by lane.
// Like run<UpInterval>, it assumes the caller holds a RoundingScope. One copy of the walk per
// instruction set (baseline SSE2, AVX2, AVX-512), the one Evaluator<Batch> uses (set_batch_isa,
// expr/eval_batch.h, chooses both). Reference: docs/theory/interval_batch.md.
#pragma once

#include <cstdint>

#include "expr/tape.h"
#include "interval/interval.h"

namespace certray::expr {

/// The capacity of IntervalLanes: how many boxes one walk can evaluate. 64 lanes are 1 KiB of
/// bounds, as a Batch is; 128 would save 3–15 % more per box (docs/benchmarks.md, "Interval batch
/// walk").
inline constexpr int kIntervalLanes = 64;

/// kIntervalLanes intervals, structure of arrays, aligned to a cache line: lane i is
/// [lo[i], hi[i]] with the decoration bit i of `defined` (bit i % 64 of word i / 64). Read and
/// write lanes with lane() and set_lane(); the bits of an empty lane are those of
/// UpInterval::empty().
struct alignas(64) IntervalLanes {
    double lo[kIntervalLanes];
    double hi[kIntervalLanes];
    std::uint64_t defined[(kIntervalLanes + 63) / 64];
};

/// Lane i as an UpInterval, exactly as stored (bounds and decoration).
inline UpInterval lane(const IntervalLanes& x, int i) {
    const bool def = (x.defined[i / 64] >> (i % 64)) & 1u;
    return certray::detail::from_bounds<UpwardRounding>(x.lo[i], x.hi[i], def);
}

/// Stores v in lane i, exactly (bounds and decoration).
inline void set_lane(IntervalLanes& x, int i, const UpInterval& v) {
    x.lo[i] = v.lower();
    x.hi[i] = v.upper();
    const std::uint64_t bit = std::uint64_t{1} << (i % 64);
    x.defined[i / 64] = v.defined ? x.defined[i / 64] | bit : x.defined[i / 64] & ~bit;
}

/// Runs the instructions [begin, end) — a tape's instrs() or an SSA list (the out register of
/// each instruction is where its result goes: r[in.out]) — over lanes 0 … n − 1 of the boxes p[0],
/// p[1], p[2] (x, y, z), 1 ≤ n ≤ kIntervalLanes. Lane i of every register written is what
/// detail::run<UpInterval> computes for the box (lane(p[0], i), lane(p[1], i), lane(p[2], i)), bit
/// for bit; lanes from n on may be overwritten with meaningless values. An instruction may write
/// one of its operands' registers (as a tape's allocator has it). The caller holds a RoundingScope
/// (interval/interval.h). Allocates nothing.
void run_interval_batch(const Instr* begin, const Instr* end, const IntervalLanes* p,
                        IntervalLanes* r, int n);

}  // namespace certray::expr
