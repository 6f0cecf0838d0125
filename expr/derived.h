// expr/derived.h — queries derived from one tape: gradients and local Lipschitz bounds.
//
// Contract: gradient() is ∇f at a point in double (forward mode). interval_gradient() encloses
// f and every generalised gradient of f over a box (Clarke's: at kinks of abs/min/max the hull of
// the one-sided derivatives). lipschitz_bound(box) is a sound upper bound on sup ‖∇f‖₂ over the
// box — so |f(p) − f(q)| ≤ λ‖p − q‖ for p, q in the box and |f(p)| / λ is a proven lower bound on
// the distance from p to the surface inside the box — or +inf when f is not proven defined and
// continuous on the whole box. Reference: docs/theory/lipschitz.md.
#pragma once

#include <array>

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

/// Sound upper bound on the Lipschitz constant of f over the box (see the file contract).
double lipschitz_bound(const Tape& tape, const std::array<Interval, 3>& box);

/// The same over the bounding box of the segment [p, q].
double lipschitz_bound_segment(const Tape& tape, const std::array<double, 3>& p,
                               const std::array<double, 3>& q);

}  // namespace certray::expr
