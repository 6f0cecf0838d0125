// expr/derived.h — queries derived from one tape: gradients and local Lipschitz bounds.
//
// Contract: gradient() is ∇f at a point in double (forward mode). interval_gradient() encloses
// f and every generalised gradient of f over a box (Clarke's: at kinks of abs/min/max the hull of
// the one-sided derivatives). lipschitz_bound(box) is a sound upper bound on sup ‖∇f‖₂ over the
// box — so |f(p) − f(q)| ≤ λ‖p − q‖ for p, q in the box and |f(p)| / λ is a proven lower bound on
// the distance from p to the surface inside the box — or +inf when f is not proven defined and
// continuous on the whole box. Reference: docs/theory/lipschitz.md.
//
// Smooth blends: the quadratic smooth union min(a, b) − max(k − |a − b|, 0)² / (4k) and the smooth
// intersection max(a, b) + max(k − |a − b|, 0)² / (4k), k > 0 (Lipschitz-Pruning's blends, as
// expr/csg_shapes.cpp writes them; difference is intersection with −b), are C¹ functions φ(a, b)
// whose gradient is (w, 1 − w) with w ∈ [0, 1]. So such a node is Lipschitz with max(λ_a, λ_b) and
// every generalised gradient of it lies, component by component, in the hull of its operands'
// (docs/theory/lipschitz.md, "Smooth blends"). The interval rules of its parts cannot see that the
// weights sum to 1: through a chain of n blends their bound grows as 2ⁿ (10¹⁷⁶ on the molecule).
// lipschitz_bound recognises the blends in the tape's SSA form (smooth_blends) and gives each
// the operands' hull and max(λ_a, λ_b) after its parts are evaluated (the value is its own).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "expr/eval.h"
#include "expr/tape.h"
#include "interval/dual.h"
#include "interval/interval.h"

namespace certray::expr {

/// Dual numbers over Interval are evaluated as duals over UpInterval in one rounding scope.
template <int N>
struct Fast<Dual<Interval, N>> {
    using type = Dual<UpInterval, N>;
    using Scope = RoundingScope;
    static type in(const Dual<Interval, N>& x) {
        type r(UpInterval(x.a));
        for (int i = 0; i < N; ++i) r.v[i] = UpInterval(x.v[i]);
        return r;
    }
    static Dual<Interval, N> out(const type& x) {
        Dual<Interval, N> r(Interval(x.a));
        for (int i = 0; i < N; ++i) r.v[i] = Interval(x.v[i]);
        return r;
    }
};

/// f(p) and ∇f(p) in double.
Dual<double, 3> gradient(const Tape& tape, const std::array<double, 3>& p);

/// An enclosure of f and of its generalised gradients over the box.
Dual<Interval, 3> interval_gradient(const Tape& tape, const std::array<Interval, 3>& box);

/// Sound bound on ‖g‖₂ for every g in the interval vector `grad` (+inf if any part is unbounded,
/// empty or undefined).
double norm_bound(const std::array<Interval, 3>& grad);

/// One smooth blend of an SSA list (see the file contract): the slot of its result and the slots
/// of its two operands a and b (b already negated for a difference).
struct SmoothBlend {
    std::uint32_t root, a, b;
};

/// The smooth blends of an SSA list (Tape::ssa(), or a pruned list: each instruction writes its
/// own slot), in list order: each node that is exactly min(a, b) − K or K + max(a, b) (either
/// operand order of the sum) with K = S / c, S = square(max(k − |d|, 0)) (either order of the max,
/// 0 a constant), d = a − b or b − a, k and c constants with k > 0 and c = 4k.
std::vector<SmoothBlend> smooth_blends(const std::vector<Instr>& ssa);
/// The same into `out` (replaced; no allocation once it has grown).
void smooth_blends(const std::vector<Instr>& ssa, std::vector<SmoothBlend>& out);

/// Sound upper bound on the Lipschitz constant of f over the box (see the file contract).
double lipschitz_bound(const Tape& tape, const std::array<Interval, 3>& box);

/// The same over the bounding box of the segment [p, q].
double lipschitz_bound_segment(const Tape& tape, const std::array<double, 3>& p,
                               const std::array<double, 3>& q);

}  // namespace certray::expr
