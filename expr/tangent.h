// expr/tangent.h — a list that computes f and its derivative along a direction, for the lanes.
//
// Contract: tangent_list(list) turns an SSA list of f(x, y, z) into one that computes, beside
// every value of the list, its derivative along a direction u = (u_x, u_y, u_z) (forward mode by
// source transformation: the chain rule of each op written as plain instructions). Run over a box
// X with the seed slots holding u (any enclosures of it), its value slots are those of the list
// and its `derivative` slot holds an enclosure of ∇f(x)·u for every x in X and u in the seeds —
// wherever f is differentiable on X, which its value's decoration says: the smooth ops are C¹
// where they are defined (+ − × /, square, neg, recip, exp, log, sin, cos, integer powers, and √
// where the operand is > 0; at √0 the derivative is unbounded, its bound infinite). min, max and
// abs have kinks: their rule encloses Clarke's generalized derivative, one branch's where the
// branch is certain on X and g·a′ + (1 − g)·b′ with g ∈ [0, 1] (sign·a′, sign ∈ [−1, 1] for abs)
// where it is not, which holds the convex hull of the two. So over a segment {o + t·u : t ∈ T} on
// which f is proven defined and continuous with a finite derivative enclosure G′, the mean value
// theorem (Lebourg's, for the kinks: f is then Lipschitz on the segment) gives g(T) ⊆ g(c) +
// G′·(T − c) for g(t) = f(o + t·u). Ops with jumps and the rest (floor, compare, atan2, …) have no
// rule here: tangent_list returns nothing for a list that holds one.
// The list runs in any interval walk of SSA lists (expr/eval.h's run<UpInterval>,
// expr/eval_interval_batch.h's lanes) once the caller has written the seeds into their slots,
// which no instruction writes. An operand slot that no instruction of `list` writes is an input
// the caller fills too (as for a list folded to a region, tracers/coherent_lanes.cpp): its value is
// read from the slot, and its derivative taken as 0, so that the derivative is the partial one with
// those inputs held fixed. Reference: docs/theory/coherent.md ("Mean value forms in lanes").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "expr/tape.h"

namespace certray::expr {

struct TangentList {
    std::vector<Instr> list;            ///< the instructions (SSA: each slot written once)
    std::uint32_t value = 0;            ///< slot of f
    std::uint32_t derivative = 0;       ///< slot of ∇f·u
    std::uint32_t seed[3] = {0, 0, 0};  ///< slots of u_x, u_y, u_z: the caller writes them
    std::uint32_t slots = 0;            ///< one past the largest slot used
    bool smooth = true;                 ///< the list holds no kink (min, max, abs)
};

/// The tangent list of an SSA list (slots in any order, each written once, the last instruction
/// f), or nothing when the list holds an op without a rule here.
std::optional<TangentList> tangent_list(const std::vector<Instr>& list);

/// What tangent_list(list) gives, without making it: none, a list without kinks (smooth) or one
/// with kinks.
enum class TangentKind : std::uint8_t { None, Smooth, Kinked };
TangentKind tangent_kind(const std::vector<Instr>& list);

/// An SSA list made shorter for the slots `keep` (the slots read after a walk): first every
/// operand read from a slot `same[k].first` reads `same[k].second` instead (two inputs the caller
/// fills with the same values, such as the seeds of a tangent list taken twice); then an
/// instruction that repeats an earlier one (the same op on the same operand slots, with the same
/// immediate or exponent) is dropped, its readers reading the earlier one's slot, unless it writes
/// a slot of `keep`; last, every instruction that no slot of `keep` depends on is dropped. Walked
/// over the same inputs, every slot of `keep` holds bit for bit what it held before, in any walk
/// (an instruction's result is a function of its op and its operands' values). Returns how many
/// instructions were dropped.
std::size_t share_instructions(std::vector<Instr>& list,
                               std::span<const std::pair<std::uint32_t, std::uint32_t>> same,
                               std::span<const std::uint32_t> keep);

}  // namespace certray::expr
