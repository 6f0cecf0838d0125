// interval/interval_ext.h — BasicInterval's rounding, trigonometric-inverse and selection ops
// (Fidget's opcodes floor ceil round tan asin acos atan atan2 compare mod and or not; issue 14).
//
// Contract (as interval/interval.h): for all x in X (and y in Y) where op is defined, op(x, y)
// lies in op(X, Y); set-based (asin([0, 5]) = asin([0, 1])); `defined` only where op is defined
// and continuous on the whole box (restricted to it). The piecewise-constant ops (floor, ceil,
// round, compare, not) are `defined` exactly where they do not jump on the box, i.e. where they are
// constant; mod, and, or where they keep one continuous branch. tan, asin, acos, atan, atan2:
// glibc's round-to-nearest value (≤ 1 ulp on x86_64) widened outward by kTranscUlps ulps, exact
// at 0, clamped to the function's range. Included at the end of interval/interval.h.
// Reference: IEEE Std 1788-2015 §9.3 (floor, ceil, roundTiesToAway, tan, asin, acos, atan,
// atan2 and their decorations); Fidget (mkeeter/fidget) `FloatExt` for compare, and, or, not, mod.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace certray {

namespace detail {

/// f(x) computed in round-to-nearest whatever the current mode (which is restored).
template <class F>
double nearest_of(F f, double x) {
    IntervalArith arith;
    return arith.nearest(f, x);
}
/// A lower bound of the real f(x) from glibc's round-to-nearest value (exact at x = 0 when f(0) =
/// 0), never below lo.
template <class F>
double transc_down(F f, double x, double lo) {
    if (x == 0 && f(0.0) == 0) return x;
    const double r = step_down(nearest_of(f, x), kTranscUlps);
    return r < lo ? lo : r;
}
/// An upper bound of the real f(x), never above hi.
template <class F>
double transc_up(F f, double x, double hi) {
    if (x == 0 && f(0.0) == 0) return x;
    const double r = step_up(nearest_of(f, x), kTranscUlps);
    return r > hi ? hi : r;
}

/// f ∈ {floor, ceil, round}: non-decreasing, exact on doubles, constant between its jumps.
template <class M, class F>
BasicInterval<M> integer_step(const BasicInterval<M>& x, F f) {
    if (x.is_empty()) return BasicInterval<M>::empty();
    const double lo = f(x.lower()), hi = f(x.upper());
    return from_bounds<M>(lo, hi, x.defined && lo == hi);
}

template <class M>
bool may_be_zero(const BasicInterval<M>& x) {
    return x.lower() <= 0 && 0 <= x.upper();
}
template <class M>
bool is_zero(const BasicInterval<M>& x) {
    return x.lower() == 0 && x.upper() == 0;
}
template <class M>
BasicInterval<M> with_decoration(BasicInterval<M> x, bool def) {
    x.defined = def && !x.is_empty();
    return x;
}

}  // namespace detail

/// ⌊[a, b]⌋ = [⌊a⌋, ⌊b⌋] (exact); defined iff ⌊a⌋ = ⌊b⌋ (no integer in (a, b]).
template <class M>
BasicInterval<M> floor(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    return detail::integer_step(x, [](double v) { return std::floor(v); });
}
/// ⌈[a, b]⌉ = [⌈a⌉, ⌈b⌉] (exact); defined iff ⌈a⌉ = ⌈b⌉ (no integer in [a, b)).
template <class M>
BasicInterval<M> ceil(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    return detail::integer_step(x, [](double v) { return std::ceil(v); });
}
/// round([a, b]) = [round(a), round(b)], halves away from 0 (exact); defined iff they are equal.
template <class M>
BasicInterval<M> round(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    return detail::integer_step(x, [](double v) { return std::round(v); });
}

namespace detail {
/// For finite a ≤ b, with k(t) = (t − π/2)/π (the poles of tan are the integers of k): n =
/// ⌊lower(k(a))⌋ and upper(k(b)). No pole lies in [a, b] when upper(k(b)) ≤ n + 1, at most one
/// (π/2 + nπ… the pole n + 1 of k) when it is < n + 2. A pole is irrational, never a double: k(a)
/// ≠ n and k(b) ≠ n + 1 (tan(RD(π/2)) is finite and defined). Written t/π − ½ (not (t − π/2)/π,
/// which widens twice): tight for t = ±RD(π/2). Runs in M's environment.
template <class M>
std::pair<double, double> tan_branch(double a, double b) {
    using I = BasicInterval<M>;
    const I pi(kPiLo, kPiHi), half(0.5);
    const I ka = I(a) / pi - half, kb = I(b) / pi - half;
    return {std::floor(ka.lower()), kb.upper()};
}
}  // namespace detail

/// tan on [a, b]:
///   empty              → empty
///   a or b infinite    → entire, not defined
///   a pole π/2 + nπ may lie in [a, b] (decided with interval π; huge |a| cannot tell)
///                      → entire, not defined
///   otherwise          → [tan a ↓, tan b ↑] (increasing on the branch), defined as x
template <class M>
BasicInterval<M> tan(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    using I = BasicInterval<M>;
    if (x.is_empty()) return I::empty();
    const double a = x.lower(), b = x.upper();
    if (!std::isfinite(a) || !std::isfinite(b)) return I{I::Boost::whole(), false};
    const auto [n, kb] = detail::tan_branch<M>(a, b);
    if (!(std::isfinite(n) && kb <= n + 1)) {
        I r = I::entire();
        r.defined = false;
        return r;
    }
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const auto f = [](double v) { return std::tan(v); };
    return detail::from_bounds<M>(detail::transc_down(f, a, -kInf), detail::transc_up(f, b, kInf),
                                  x.defined);
}

/// tan on [a, b] across one pole: when [a, b] (finite) holds at most one pole p = π/2 + nπ and
/// may hold one, tan takes its values in [tan a ↓, +∞] (on [a, p)) ∪ [−∞, tan b ↑] (on (p, b]),
/// each piece not defined; otherwise nothing (tan(x) is then the enclosure: [tan a, tan b] or
/// entire). What the two-piece enclosures of interval/interval_pair.h see past a pole with.
template <class M>
std::optional<std::array<BasicInterval<M>, 2>> tan_branches(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    using I = BasicInterval<M>;
    if (x.is_empty() || !std::isfinite(x.lower()) || !std::isfinite(x.upper())) return {};
    const double a = x.lower(), b = x.upper();
    const auto [n, kb] = detail::tan_branch<M>(a, b);
    if (!(std::isfinite(n) && n + 1 < kb && kb < n + 2)) return {};
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const auto f = [](double v) { return std::tan(v); };
    I left = detail::from_bounds<M>(detail::transc_down(f, a, -kInf), kInf, false);
    I right = detail::from_bounds<M>(-kInf, detail::transc_up(f, b, kInf), false);
    return std::array<I, 2>{left, right};
}

/// asin on [a, b] ∩ [−1, 1] (empty if disjoint): [asin a ↓, asin b ↑] within [−π/2, π/2];
/// defined iff [a, b] ⊆ [−1, 1].
template <class M>
BasicInterval<M> asin(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    if (x.is_empty() || x.lower() > 1 || x.upper() < -1) return BasicInterval<M>::empty();
    const double a = x.lower() < -1 ? -1.0 : x.lower(), b = x.upper() > 1 ? 1.0 : x.upper();
    const auto f = [](double v) { return std::asin(v); };
    return detail::from_bounds<M>(detail::transc_down(f, a, -detail::kHalfPiHi),
                                  detail::transc_up(f, b, detail::kHalfPiHi),
                                  x.defined && x.lower() >= -1 && x.upper() <= 1);
}
/// acos on [a, b] ∩ [−1, 1] (empty if disjoint): decreasing, [acos b ↓, acos a ↑] within [0, π]
/// (acos 1 = 0 exactly); defined iff [a, b] ⊆ [−1, 1].
template <class M>
BasicInterval<M> acos(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    if (x.is_empty() || x.lower() > 1 || x.upper() < -1) return BasicInterval<M>::empty();
    const double a = x.lower() < -1 ? -1.0 : x.lower(), b = x.upper() > 1 ? 1.0 : x.upper();
    const auto f = [](double v) { return std::acos(v); };
    const double lo = b == 1 ? 0.0 : detail::transc_down(f, b, 0.0);
    const double hi = a == 1 ? 0.0 : detail::transc_up(f, a, detail::kPiHi);
    return detail::from_bounds<M>(lo, hi, x.defined && x.lower() >= -1 && x.upper() <= 1);
}
/// atan on [a, b]: increasing, [atan a ↓, atan b ↑] within [−π/2, π/2] (atan ±∞ = ±π/2).
template <class M>
BasicInterval<M> atan(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    if (x.is_empty()) return BasicInterval<M>::empty();
    const auto f = [](double v) { return std::atan(v); };
    return detail::from_bounds<M>(detail::transc_down(f, x.lower(), -detail::kHalfPiHi),
                                  detail::transc_up(f, x.upper(), detail::kHalfPiHi), x.defined);
}

/// atan2(y, x), the angle of the point (x, y) in (−π, π], over the box Y × X:
///   an empty operand, or Y × X = {(0, 0)}      → empty (undefined at the origin)
///   the origin in the box                      → [−π, π], not defined
///   the box meets y = 0, x < 0 and has y < 0   → [−π, π], not defined (the branch cut: π on
///                                                the axis, → −π from below)
///   otherwise the angle is continuous on the box and its extremes are at the corners (the
///   box is convex and misses the origin): hull of the corner values, widened outward, within
///   [−π, π]; y bounds ±0 read as +0 (the real atan2(0, x < 0) is π); defined as Y and X.
template <class M>
BasicInterval<M> atan2(const BasicInterval<M>& y, const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    using I = BasicInterval<M>;
    if (y.is_empty() || x.is_empty()) return I::empty();
    const I full = detail::from_bounds<M>(-detail::kPiHi, detail::kPiHi, false);
    if (detail::may_be_zero(y) && detail::may_be_zero(x)) {
        return detail::is_zero(y) && detail::is_zero(x) ? I::empty() : full;
    }
    const double ylo = y.lower() == 0 ? 0.0 : y.lower(), yhi = y.upper() == 0 ? 0.0 : y.upper();
    if (x.lower() < 0 && ylo < 0 && 0 <= yhi) return full;
    double lo = detail::kPiHi, hi = -detail::kPiHi;
    for (const double yc : {ylo, yhi}) {
        for (const double xc : {x.lower(), x.upper()}) {
            const auto f = [yc](double v) { return std::atan2(yc, v); };
            double l, h;
            if (yc == 0 && xc > 0) {
                l = h = 0.0;  // exact
            } else {
                const double v = detail::nearest_of(f, xc);
                l = detail::step_down(v, detail::kTranscUlps);
                h = detail::step_up(v, detail::kTranscUlps);
            }
            lo = l < lo ? l : lo;
            hi = h > hi ? h : hi;
        }
    }
    lo = lo < -detail::kPiHi ? -detail::kPiHi : lo;
    hi = hi > detail::kPiHi ? detail::kPiHi : hi;
    return detail::from_bounds<M>(lo, hi, y.defined && x.defined);
}

/// compare(a, b) ∈ {−1, 0, 1}: the hull of −1 if some a < b, 0 if the boxes meet, 1 if some
/// a > b; empty operand → empty; defined iff only one value is possible (constant).
template <class M>
BasicInterval<M> compare(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    if (a.is_empty() || b.is_empty()) return BasicInterval<M>::empty();
    const bool lt = a.lower()<b.upper(), gt = a.upper()> b.lower();
    const bool eq = a.lower() <= b.upper() && b.lower() <= a.upper();
    const double lo = lt ? -1.0 : (eq ? 0.0 : 1.0), hi = gt ? 1.0 : (eq ? 0.0 : -1.0);
    return detail::from_bounds<M>(lo, hi, a.defined && b.defined && lo == hi);
}

/// mod(a, b) = a − |b|·⌊a/|b|⌋ ∈ [0, |b|), with |B| = [m, M]:
///   an empty operand or M = 0          → empty
///   m = 0 (b may be 0), a unbounded,
///   or ⌊a/|b|⌋ not constant on the box → [0, M], not defined (it jumps, or b = 0)
///   ⌊a/|b|⌋ = n on the box             → (A − |B|·n) ∩ [0, M], defined as A and B
template <class M>
BasicInterval<M> mod(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    using I = BasicInterval<M>;
    if (a.is_empty() || b.is_empty()) return I::empty();
    const I m = abs(b);
    if (m.upper() == 0) return I::empty();
    const I range = detail::from_bounds<M>(0.0, m.upper(), false);
    if (m.lower() == 0 || !std::isfinite(a.lower()) || !std::isfinite(a.upper())) return range;
    const I q = a / m;
    const double n = std::floor(q.lower());
    if (!std::isfinite(n) || std::floor(q.upper()) != n) return range;
    const I r = intersect(I(a - m * I(n)), range);
    return detail::with_decoration(r, a.defined && b.defined);
}

/// and(a, b) = a if a = 0, else b:
///   a empty → empty;  0 ∉ A → B (defined as A and B);  A = [0, 0] → A;
///   otherwise         → hull(0, B), not defined (it may jump where a reaches 0)
template <class M>
BasicInterval<M> logic_and(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    using I = BasicInterval<M>;
    if (a.is_empty()) return I::empty();
    if (!detail::may_be_zero(a)) return detail::with_decoration(b, a.defined && b.defined);
    if (detail::is_zero(a)) return a;
    const I zero(0.0);
    return detail::with_decoration(b.is_empty() ? zero : hull(zero, b), false);
}
/// or(a, b) = a if a ≠ 0, else b:
///   a empty → empty;  0 ∉ A → A;  A = [0, 0] → B (defined as A and B);
///   otherwise         → hull(A, B), not defined
template <class M>
BasicInterval<M> logic_or(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    if (a.is_empty()) return BasicInterval<M>::empty();
    if (!detail::may_be_zero(a)) return a;
    if (detail::is_zero(a)) return detail::with_decoration(b, a.defined && b.defined);
    return detail::with_decoration(b.is_empty() ? a : hull(a, b), false);
}
/// not(a) = 1 if a = 0, else 0:  empty → empty;  A = [0, 0] → [1, 1];  0 ∉ A → [0, 0];
/// otherwise → [0, 1], not defined.
template <class M>
BasicInterval<M> logic_not(const BasicInterval<M>& a) {
    [[maybe_unused]] typename M::Guard guard;  // the library's environment (interval.h)
    if (a.is_empty()) return BasicInterval<M>::empty();
    if (detail::is_zero(a)) return detail::from_bounds<M>(1.0, 1.0, a.defined);
    if (!detail::may_be_zero(a)) return detail::from_bounds<M>(0.0, 0.0, a.defined);
    return detail::from_bounds<M>(0.0, 1.0, false);
}

}  // namespace certray
