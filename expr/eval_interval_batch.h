// expr/eval_interval_batch.h — the interval tape walk over several boxes at once (lanes), in
// double bounds (the scalar walk's bits) or in binary32 bounds (enclosures, twice the lanes per
// instruction; run_interval_batch over IntervalLanesF below).
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

#include <bit>
#include <cstdint>
#include <limits>

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

/// kIntervalLanes intervals with binary32 bounds, laid out as IntervalLanes: the registers of the
/// binary32 walk (run_interval_batch over IntervalLanesF). An empty lane has NaN bounds.
struct alignas(64) IntervalLanesF {
    float lo[kIntervalLanes];
    float hi[kIntervalLanes];
    std::uint64_t defined[(kIntervalLanes + 63) / 64];
};

/// The binary32 number next to f towards −∞ (up = false) or +∞ (up = true), by its bits; f is
/// neither NaN nor the infinity it moves to.
inline float next_f32(float f, bool up) {
    if (f == 0)
        return up ? std::numeric_limits<float>::denorm_min()
                  : -std::numeric_limits<float>::denorm_min();
    const auto b = std::bit_cast<std::uint32_t>(f);
    return std::bit_cast<float>((f > 0) == up ? b + 1 : b - 1);
}
/// The largest binary32 number ≤ x (NaN: NaN), in any rounding mode.
inline float lower_f32(double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) > x ? next_f32(f, false) : f;
}
/// The smallest binary32 number ≥ x (NaN: NaN), in any rounding mode.
inline float upper_f32(double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) < x ? next_f32(f, true) : f;
}

/// lower_f32(x) and upper_f32(x), bit for bit, where the caller holds the upward mode (a
/// RoundingScope, as the walks do): without their compare and branch, the conversion of x rounds
/// up and that of −x gives, negated, the largest binary32 ≤ x. (A lane load in the branches cost
/// half a binary32 walk where its lower bounds fell either side at random.)
inline float lower_f32_upward(double x) { return -static_cast<float>(-x); }
inline float upper_f32_upward(double x) { return static_cast<float>(x); }

/// Sets lane i's bounds to [lo, hi] (not its decoration): exactly in IntervalLanes, rounded
/// outward to binary32 in IntervalLanesF (lower_f32, upper_f32).
inline void set_bounds(IntervalLanes& x, int i, double lo, double hi) {
    x.lo[i] = lo;
    x.hi[i] = hi;
}
inline void set_bounds(IntervalLanesF& x, int i, double lo, double hi) {
    x.lo[i] = lower_f32(lo);
    x.hi[i] = upper_f32(hi);
}

/// set_bounds() where the caller holds the upward mode (a RoundingScope): the same bits, in
/// binary32 by lower_f32_upward and upper_f32_upward (no branches).
inline void set_bounds_upward(IntervalLanes& x, int i, double lo, double hi) {
    set_bounds(x, i, lo, hi);
}
inline void set_bounds_upward(IntervalLanesF& x, int i, double lo, double hi) {
    x.lo[i] = lower_f32_upward(lo);
    x.hi[i] = upper_f32_upward(hi);
}

/// Whether the binary32 walk (run_interval_batch over IntervalLanesF) takes `op` with a binary32
/// kernel; it takes the others in double, widened and rounded outward, which costs their double
/// step and two conversions.
constexpr bool binary32_kernel(Op op) noexcept {
    switch (op) {
        case Op::Const:
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
        case Op::Neg:
        case Op::Abs:
        case Op::Square:
        case Op::Sqrt:
        case Op::Add:
        case Op::Sub:
        case Op::Mul:
        case Op::Div:
        case Op::Recip:
        case Op::Min:
        case Op::Max:
        case Op::Exp:
        case Op::Log:
        case Op::Sin:
        case Op::Cos:
        case Op::Pow:
            return true;
        default:
            return false;
    }
}

/// Lane i as an UpInterval: its bounds as doubles (exactly) and its decoration.
inline UpInterval lane(const IntervalLanesF& x, int i) {
    const bool def = (x.defined[i / 64] >> (i % 64)) & 1u;
    return certray::detail::from_bounds<UpwardRounding>(x.lo[i], x.hi[i], def);
}

/// Stores v in lane i rounded outward to binary32 (lower_f32 and upper_f32 of its bounds: exact
/// where they are binary32 numbers; an empty v stays empty), with its decoration.
inline void set_lane(IntervalLanesF& x, int i, const UpInterval& v) {
    set_bounds(x, i, v.lower(), v.upper());
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

/// The same walk in binary32 bounds: 8 lanes per AVX2 instruction instead of 4, for callers that
/// need enclosures, not the scalar walk's bits. Lane i of every register written holds an
/// enclosure of the instruction's value over the box (lane(p[0], i), lane(p[1], i), lane(p[2],
/// i)) in the meaning of interval/interval.h — every value the subexpression takes at a point of
/// the box lies inside, and the decoration says "defined and continuous on the whole box" only
/// where it is — with binary32 bounds, never narrower than the exact range rounded outward to
/// binary32. + − × ÷ square √ neg abs min max and 1/x apply the UpInterval kernels' formulas to
/// binary32 vectors in upward mode, exp and log the binary32 kernels of
/// interval/exp_log_kernel_f32.h where both bounds of a lane are in their range; the other lanes
/// and every other op are taken in double (the bounds widened exactly, the scalar or batched
/// UpInterval operation) and rounded outward. Same preconditions as the double walk (a
/// RoundingScope held, 1 ≤ n ≤ kIntervalLanes, an instruction may write an operand's register);
/// allocates nothing. Reference: docs/theory/interval_batch.md, "Binary32 lanes".
void run_interval_batch(const Instr* begin, const Instr* end, const IntervalLanesF* p,
                        IntervalLanesF* r, int n);

}  // namespace certray::expr
