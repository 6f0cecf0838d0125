// interval/interval.h — binary64 intervals on Boost.Interval: sound outward rounding, decoration.
//
// Contract: for every operation op and all x in X (and y in Y) where op is defined, op(x, y) lies
// in op(X, Y). Set-based IEEE 1788 semantics: functions act on the intersection of the box with
// their domain (sqrt([-5, 25]) = [0, 5]), division by a box containing 0 gives the hull of the
// quotients ([1, 2] / [0, 1] = [1, +inf]), and division by [0, 0] is empty.
// The decoration `defined` says more: the function is defined and continuous on the *whole* input
// box. A certified root finder may trust a sign change only where it holds.
//
// Rounding: Boost's `rounded_arith_opp` (everything in upward mode, lower bounds by negation),
// forced through memory by Boost so the compiler cannot reuse a round-to-nearest result.
// `Interval` saves, sets and restores the mode around every operation; inside a `RoundingScope`,
// `UpInterval` skips that and costs a few doubles (docs/theory/interval.md, docs/benchmarks.md).
// exp, log, sin, cos: glibc ignores the rounding mode, so the round-to-nearest result is widened
// outward by kTranscUlps ulps (glibc documents ≤ 1 ulp for these on x86_64), with exact values at
// the points where the function value is exactly representable.
#pragma once

#include <boost/numeric/interval.hpp>
#include <cmath>
#include <limits>

namespace certray {

namespace detail {

namespace bil = boost::numeric::interval_lib;

/// Ulps by which a glibc round-to-nearest transcendental result is widened outward.
inline constexpr int kTranscUlps = 2;

inline double step_down(double v, int n) {
    for (int i = 0; i < n; ++i) v = std::nextafter(v, -std::numeric_limits<double>::infinity());
    return v;
}

inline double step_up(double v, int n) {
    for (int i = 0; i < n; ++i) v = std::nextafter(v, std::numeric_limits<double>::infinity());
    return v;
}

/// Transcendental point bounds for Boost's rounding policy: f_down(x) <= f(x) <= f_up(x).
/// Computes in round-to-nearest and returns to upward mode, the invariant of rounded_arith_opp.
template <class Rounding>
struct WidenedTransc : Rounding {
    template <class F>
    double nearest(F f, double x) {
        this->to_nearest();
        double r = this->force_rounding(f(x));
        this->upward();
        return r;
    }
    static double exp_rn(double x) { return std::exp(x); }
    static double log_rn(double x) { return std::log(x); }
    static double sin_rn(double x) { return std::sin(x); }
    static double cos_rn(double x) { return std::cos(x); }

    // exp: exact at 0 and ±inf; below by kTranscUlps ulps, clamped at 0.
    double exp_down(double x) {
        if (x == 0) return 1.0;
        if (std::isinf(x)) return x > 0 ? x : 0.0;
        double r = step_down(nearest(exp_rn, x), kTranscUlps);
        return r < 0 ? 0.0 : r;
    }
    double exp_up(double x) {
        if (x == 0) return 1.0;
        if (std::isinf(x)) return x > 0 ? x : 0.0;
        return step_up(nearest(exp_rn, x), kTranscUlps);
    }
    // log (called by Boost only for x > 0): exact at 1 and +inf.
    double log_down(double x) {
        if (x == 1) return 0.0;
        if (std::isinf(x)) return x;
        return step_down(nearest(log_rn, x), kTranscUlps);
    }
    double log_up(double x) {
        if (x == 1) return 0.0;
        if (std::isinf(x)) return x;
        return step_up(nearest(log_rn, x), kTranscUlps);
    }
    // sin, cos: exact at 0, clamped to [-1, 1].
    double sin_down(double x) {
        if (x == 0) return x;
        double r = step_down(nearest(sin_rn, x), kTranscUlps);
        return r < -1 ? -1.0 : r;
    }
    double sin_up(double x) {
        if (x == 0) return x;
        double r = step_up(nearest(sin_rn, x), kTranscUlps);
        return r > 1 ? 1.0 : r;
    }
    double cos_down(double x) {
        if (x == 0) return 1.0;
        double r = step_down(nearest(cos_rn, x), kTranscUlps);
        return r < -1 ? -1.0 : r;
    }
    double cos_up(double x) {
        if (x == 0) return 1.0;
        double r = step_up(nearest(cos_rn, x), kTranscUlps);
        return r > 1 ? 1.0 : r;
    }
};

using IntervalArith = WidenedTransc<bil::rounded_arith_opp<double>>;
using Checking = bil::checking_base<double>;

}  // namespace detail

/// Every operation saves, sets and restores the rounding mode: safe anywhere.
struct ProtectedRounding {
    using Policies = boost::numeric::interval_lib::policies<
        boost::numeric::interval_lib::save_state<detail::IntervalArith>, detail::Checking>;
};

/// Operations assume the mode is upward: valid only inside a live `RoundingScope`.
struct UpwardRounding {
    using Policies = boost::numeric::interval_lib::policies<
        boost::numeric::interval_lib::save_state_nothing<detail::IntervalArith>, detail::Checking>;
};

/// Sets the rounding mode upward for its lifetime and restores the caller's mode at the end.
/// Hoist one scope out of a loop of `UpInterval` operations; do not call libm or code that assumes
/// round-to-nearest inside it.
using RoundingScope = boost::numeric::interval_lib::save_state<detail::IntervalArith>;

/// A closed binary64 interval [lower, upper] (possibly unbounded or empty) with a decoration.
/// `Mode` says whether its operations protect the rounding mode (see ProtectedRounding).
template <class Mode>
struct BasicInterval {
    using Boost = boost::numeric::interval<double, typename Mode::Policies>;

    /// The enclosure itself; empty is represented by Boost as NaN bounds.
    Boost iv;
    /// True when the function that produced this interval is defined and continuous on the whole
    /// input box. False for empty intervals.
    bool defined;

    /// The point 0.
    constexpr BasicInterval() : iv(0.0), defined(true) {}
    /// The point x; NaN gives the empty interval.
    BasicInterval(double x) : iv(x), defined(!std::isnan(x)) {}  // NOLINT: implicit on purpose
    /// [lo, hi]; lo > hi or a NaN bound gives the empty interval.
    BasicInterval(double lo, double hi) : iv(lo, hi), defined(!boost::numeric::empty(iv)) {}
    BasicInterval(const Boost& b, bool def) : iv(b), defined(def && !boost::numeric::empty(b)) {}
    /// Same bounds under another rounding mode.
    template <class M2>
    explicit BasicInterval(const BasicInterval<M2>& o)
        : iv(o.lower(), o.upper()), defined(o.defined) {
        if (o.is_empty()) *this = empty();
    }

    static BasicInterval empty() { return {Boost::empty(), false}; }
    static BasicInterval entire() { return {Boost::whole(), true}; }

    double lower() const { return iv.lower(); }
    double upper() const { return iv.upper(); }
    bool is_empty() const { return boost::numeric::empty(iv); }
};

/// The safe default: every operation saves, sets and restores the rounding mode.
using Interval = BasicInterval<ProtectedRounding>;
/// The fast variant for hot loops: correct only inside a live RoundingScope.
using UpInterval = BasicInterval<UpwardRounding>;

// ---- queries ---------------------------------------------------------------------------------

template <class M>
double lower(const BasicInterval<M>& x) {
    return x.lower();
}
template <class M>
double upper(const BasicInterval<M>& x) {
    return x.upper();
}
template <class M>
bool is_defined(const BasicInterval<M>& x) {
    return x.defined;
}
template <class M>
bool is_empty(const BasicInterval<M>& x) {
    return x.is_empty();
}
/// Width rounded upward (+inf when unbounded, 0 for empty).
template <class M>
double width(const BasicInterval<M>& x) {
    return x.is_empty() ? 0.0 : boost::numeric::width(x.iv);
}
/// A point inside a non-empty interval (0 for entire, finite for half-unbounded intervals).
template <class M>
double midpoint(const BasicInterval<M>& x) {
    double l = x.lower(), u = x.upper();
    if (std::isinf(l) && std::isinf(u)) return 0.0;
    if (std::isinf(l)) return u > 0 ? 0.0 : (u == 0 ? -1.0 : 2 * u - 1.0);
    if (std::isinf(u)) return l < 0 ? 0.0 : (l == 0 ? 1.0 : 2 * l + 1.0);
    double m = 0.5 * l + 0.5 * u;
    return m < l ? l : (m > u ? u : m);
}
template <class M>
bool contains(const BasicInterval<M>& x, double v) {
    return x.lower() <= v && v <= x.upper();
}
/// True when y ⊆ x (empty y is a subset of everything).
template <class M>
bool contains(const BasicInterval<M>& x, const BasicInterval<M>& y) {
    return y.is_empty() || (x.lower() <= y.lower() && y.upper() <= x.upper());
}
template <class M>
BasicInterval<M> hull(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return {boost::numeric::hull(a.iv, b.iv), a.defined && b.defined};
}
template <class M>
BasicInterval<M> intersect(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return {boost::numeric::intersect(a.iv, b.iv), a.defined && b.defined};
}

// ---- comparisons: certainly_* holds for every pair of members, possibly_* for some pair
// ---------- Empty operands: certainly_* is vacuously true, possibly_* false.

template <class M>
bool certainly_lt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a.is_empty() || b.is_empty() || a.upper() < b.lower();
}
template <class M>
bool certainly_le(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a.is_empty() || b.is_empty() || a.upper() <= b.lower();
}
template <class M>
bool certainly_gt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return certainly_lt(b, a);
}
template <class M>
bool certainly_ge(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return certainly_le(b, a);
}
template <class M>
bool possibly_lt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return !a.is_empty() && !b.is_empty() && a.lower() < b.upper();
}
template <class M>
bool possibly_le(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return !a.is_empty() && !b.is_empty() && a.lower() <= b.upper();
}
template <class M>
bool possibly_gt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return possibly_lt(b, a);
}
template <class M>
bool possibly_ge(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return possibly_le(b, a);
}
/// 0 ∈ x.
template <class M>
bool possibly_zero(const BasicInterval<M>& x) {
    return contains(x, 0.0);
}

// ---- arithmetic ------------------------------------------------------------------------------
// Every result is defined where both operands are, and the operation is defined on the whole box.

namespace detail {
/// Boost yields NaN bounds (read as empty) for inf − inf and 0 · inf on non-empty operands at
/// infinite bounds; the sound answer for a non-empty input is then the whole line.
template <class M>
BasicInterval<M> repair(const BasicInterval<M>& r, const BasicInterval<M>& a,
                        const BasicInterval<M>& b) {
    if (r.is_empty() && !a.is_empty() && !b.is_empty()) {
        return {BasicInterval<M>::Boost::whole(), a.defined && b.defined};
    }
    return r;
}
}  // namespace detail

/// [a, b] + [c, d] = [a + c rounded down, b + d rounded up].
template <class M>
BasicInterval<M> operator+(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return detail::repair(BasicInterval<M>{a.iv + b.iv, a.defined && b.defined}, a, b);
}
/// [a, b] − [c, d] = [a − d rounded down, b − c rounded up].
template <class M>
BasicInterval<M> operator-(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return detail::repair(BasicInterval<M>{a.iv - b.iv, a.defined && b.defined}, a, b);
}
/// −[a, b] = [−b, −a] (exact).
template <class M>
BasicInterval<M> operator-(const BasicInterval<M>& a) {
    return {-a.iv, a.defined};
}
/// Product by Boost's sign-case table (9 cases), each bound rounded outward; 0 · ∞ counts as 0.
template <class M>
BasicInterval<M> operator*(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return detail::repair(BasicInterval<M>{a.iv * b.iv, a.defined && b.defined}, a, b);
}

/// Set-based quotient {x / y : x ∈ a, y ∈ b, y ≠ 0}:
///   0 ∉ b            → Boost's quotient, rounded outward
///   b = [0, 0]       → empty
///   b = [0, d], d>0  → a = [0,0]: [0,0]; a ≤ 0 with a.hi<0: [−∞, a.hi/d]; a.hi = 0: [−∞, 0];
///                      a ≥ 0 with a.lo>0: [a.lo/d, +∞]; a.lo = 0: [0, +∞]; else entire
///   b = [c, 0], c<0  → the mirror image
///   c < 0 < d        → a = [0,0]: [0,0]; else entire
/// The result is never `defined` when 0 ∈ b.
template <class M>
BasicInterval<M> operator/(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    using I = BasicInterval<M>;
    if (a.is_empty() || b.is_empty()) return I::empty();
    const double c = b.lower(), d = b.upper();
    if (c > 0 || d < 0) return detail::repair(I{a.iv / b.iv, a.defined && b.defined}, a, b);
    const double lo = a.lower(), hi = a.upper();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if (c == 0 && d == 0) return I::empty();
    if (lo == 0 && hi == 0) return I{typename I::Boost(0.0), false};
    typename M::Policies::rounding rnd;
    if (c == 0) {  // b = [0, d]: quotients with y → 0⁺
        if (hi < 0) return I{typename I::Boost(-kInf, rnd.div_up(hi, d)), false};
        if (hi == 0) return I{typename I::Boost(-kInf, 0.0), false};
        if (lo > 0) return I{typename I::Boost(rnd.div_down(lo, d), kInf), false};
        if (lo == 0) return I{typename I::Boost(0.0, kInf), false};
        return I{I::Boost::whole(), false};
    }
    if (d == 0) {  // b = [c, 0]: quotients with y → 0⁻
        if (hi < 0) return I{typename I::Boost(rnd.div_down(hi, c), kInf), false};
        if (hi == 0) return I{typename I::Boost(0.0, kInf), false};
        if (lo > 0) return I{typename I::Boost(-kInf, rnd.div_up(lo, c)), false};
        if (lo == 0) return I{typename I::Boost(-kInf, 0.0), false};
        return I{I::Boost::whole(), false};
    }
    return I{I::Boost::whole(), false};
}

template <class M>
BasicInterval<M> operator+(const BasicInterval<M>& a, double b) {
    return a + BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator+(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) + b;
}
template <class M>
BasicInterval<M> operator-(const BasicInterval<M>& a, double b) {
    return a - BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator-(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) - b;
}
template <class M>
BasicInterval<M> operator*(const BasicInterval<M>& a, double b) {
    return a * BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator*(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) * b;
}
template <class M>
BasicInterval<M> operator/(const BasicInterval<M>& a, double b) {
    return a / BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator/(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) / b;
}

template <class M>
BasicInterval<M>& operator+=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a + b;
}
template <class M>
BasicInterval<M>& operator-=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a - b;
}
template <class M>
BasicInterval<M>& operator*=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a * b;
}
template <class M>
BasicInterval<M>& operator/=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a / b;
}

// ---- elementary functions ----------------------------------------------------------------------

/// |[a, b]|: [a, b] if a ≥ 0; [−b, −a] if b ≤ 0; [0, max(−a, b)] otherwise. Exact.
template <class M>
BasicInterval<M> abs(const BasicInterval<M>& x) {
    return {boost::numeric::abs(x.iv), x.defined};
}
/// [a, b]²: [a², b²] if a ≥ 0; [b², a²] if b ≤ 0; [0, max(a², b²)] otherwise; rounded outward.
template <class M>
BasicInterval<M> square(const BasicInterval<M>& x) {
    return {boost::numeric::square(x.iv), x.defined};
}
/// xⁿ for a non-negative integer n: x⁰ = [1, 1]; even n as square, odd n monotone.
template <class M>
BasicInterval<M> pow(const BasicInterval<M>& x, unsigned n) {
    if (x.is_empty()) return BasicInterval<M>::empty();
    if (n == 0) return {typename BasicInterval<M>::Boost(1.0), x.defined};
    return detail::repair(
        BasicInterval<M>{boost::numeric::pow(x.iv, static_cast<int>(n)), x.defined}, x, x);
}
/// √ on [a, b] ∩ [0, ∞): [√max(a,0) down, √b up]; empty if b < 0; defined only if a ≥ 0.
template <class M>
BasicInterval<M> sqrt(const BasicInterval<M>& x) {
    return {boost::numeric::sqrt(x.iv), x.defined && x.lower() >= 0};
}
/// exp is increasing: [exp_down(a), exp_up(b)].
template <class M>
BasicInterval<M> exp(const BasicInterval<M>& x) {
    return {boost::numeric::exp(x.iv), x.defined};
}
/// log on [a, b] ∩ (0, ∞): [log_down(a) or −∞ if a ≤ 0, log_up(b)]; empty if b ≤ 0;
/// defined only if a > 0.
template <class M>
BasicInterval<M> log(const BasicInterval<M>& x) {
    return {boost::numeric::log(x.iv), x.defined && x.lower() > 0};
}
/// cos: the box is reduced modulo 2π with interval π bounds; a box of width ≥ 2π, an unbounded
/// box or a reduction too coarse to tell gives [−1, 1]; otherwise monotone pieces.
template <class M>
BasicInterval<M> cos(const BasicInterval<M>& x) {
    if (x.is_empty()) return BasicInterval<M>::empty();
    if (!std::isfinite(x.lower()) || !std::isfinite(x.upper()))
        return {BasicInterval<M>(-1.0, 1.0).iv, x.defined};
    return {boost::numeric::cos(x.iv), x.defined};
}
/// sin(x) = cos(x − π/2) with π/2 as an interval.
template <class M>
BasicInterval<M> sin(const BasicInterval<M>& x) {
    if (x.is_empty()) return BasicInterval<M>::empty();
    if (!std::isfinite(x.lower()) || !std::isfinite(x.upper()))
        return {BasicInterval<M>(-1.0, 1.0).iv, x.defined};
    return {boost::numeric::sin(x.iv), x.defined};
}
/// min([a, b], [c, d]) = [min(a, c), min(b, d)]. Exact.
template <class M>
BasicInterval<M> min(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return {boost::numeric::min(a.iv, b.iv), a.defined && b.defined};
}
/// max([a, b], [c, d]) = [max(a, c), max(b, d)]. Exact.
template <class M>
BasicInterval<M> max(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return {boost::numeric::max(a.iv, b.iv), a.defined && b.defined};
}

}  // namespace certray
