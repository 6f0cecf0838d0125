// expr/tangent.h — a list that computes f and its derivative along a direction, for the lanes.
//
// Contract: tangent_list(list) turns an SSA list of f(x, y, z) into one that computes, beside
// every value of the list, its derivative along a direction u = (u_x, u_y, u_z) (forward mode by
// source transformation: the chain rule of each op written as plain instructions). Run over a box
// X with the seed slots holding u (any enclosures of it), its value slots are those of the list
// and its `derivative` slot holds an enclosure of ∇f(x)·u for every x in X and u in the seeds —
// wherever f is differentiable on X, which its value's decoration says: every op it accepts is
// C¹ where it is defined (+ − × /, square, neg, recip, exp, log, sin, cos, integer powers, and √
// where the operand is > 0; at √0 the derivative is unbounded, its bound infinite). So over a
// segment {o + t·u : t ∈ T} on which f is proven defined and continuous with a finite derivative
// enclosure G′, the mean value theorem gives g(T) ⊆ g(c) + G′·(T − c) for g(t) = f(o + t·u).
// Ops with kinks or jumps (abs, min, max, floor, …) have no rule here: tangent_list returns
// nothing for a list that holds one (the scalar Dual walk, with Clarke's hulls, serves those).
// The list runs in any interval walk of SSA lists (expr/eval.h's run<UpInterval>,
// expr/eval_interval_batch.h's lanes) once the caller has written the seeds into their slots,
// which no instruction writes. Reference: docs/theory/coherent.md ("Mean value forms in lanes").
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "expr/tape.h"

namespace certray::expr {

struct TangentList {
    std::vector<Instr> list;            ///< the instructions (SSA: each slot written once)
    std::uint32_t value = 0;            ///< slot of f
    std::uint32_t derivative = 0;       ///< slot of ∇f·u
    std::uint32_t seed[3] = {0, 0, 0};  ///< slots of u_x, u_y, u_z: the caller writes them
    std::uint32_t slots = 0;            ///< one past the largest slot used
};

/// The tangent list of an SSA list (slots in any order, each written once, the last instruction
/// f), or nothing when the list holds an op without a rule here.
std::optional<TangentList> tangent_list(const std::vector<Instr>& list);

}  // namespace certray::expr
