// interval/dual.h — Dual<T, N>: forward-mode derivatives (value and N partials) over any Number.
//
// Contract: if every input Dual carries a value and partials that enclose (T an enclosure) or
// approximate (T = double) an input's value and gradient, then every operation returns a Dual
// whose value is op applied to the values and whose partials follow the chain rule written above
// each function. For T an enclosure evaluated over a box X (inputs made with `variable`), the
// partials of the result enclose ∂f/∂x_i(x) for every x in X at which f is differentiable; at
// kinks (abs at 0, min/max at a tie) they enclose both one-sided derivatives, and where the
// derivative is unbounded (sqrt at 0) they are the whole line.
// For T = double at an exact kink the derivative of one branch is taken (see detail::join).
// Reference: docs/theory/dual.md; Ceres Solver `jet.h` for the shape of a number type.
#pragma once

#include <array>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include "interval/number.h"

namespace certray {

/// A value with N first-order partial derivatives. Small, allocation-free, trivially copyable
/// when T is. Dual<Interval, N> evaluated on a box encloses the gradient over the box.
template <class T, int N>
struct Dual {
    static_assert(N >= 0, "Dual needs a non-negative number of partials");

    /// The value.
    T a;
    /// The partial derivatives ∂/∂x_0 … ∂/∂x_{N-1}.
    std::array<T, N> v;

    /// The constant 0.
    Dual() : a(0.0), v(zeros()) {}
    /// The constant c (all partials 0). Implicit, so that `Dual(2.0)` and `T(c)` work generically.
    Dual(double c) : a(c), v(zeros()) {}  // NOLINT: implicit on purpose
    /// The constant c of the underlying type (all partials 0).
    Dual(const T& c)  // NOLINT: implicit on purpose
        requires(!std::is_same_v<T, double>)
        : a(c), v(zeros()) {}
    /// A value with the given partials.
    Dual(const T& value, const std::array<T, N>& partials) : a(value), v(partials) {}

    /// The independent variable x_i with the given value: partials e_i. Requires 0 ≤ i < N.
    static Dual variable(const T& value, int i) {
        assert(0 <= i && i < N);
        Dual d(value, zeros());
        d.v[static_cast<std::size_t>(i)] = T(1.0);
        return d;
    }

    /// N copies of T(0).
    static std::array<T, N> zeros() {
        std::array<T, N> z;
        z.fill(T(0.0));
        return z;
    }
};

// ---- per-type helpers for kinks
// ------------------------------------------------------------------ One overload set per question,
// so that the Dual rules below stay one template: doubles compare plainly, enclosures (Interval,
// MpfrInterval, Affine) through their bounds, nested Duals through their value.

namespace detail {

/// The value is < 0 (doubles: plainly; enclosures: for every member).
inline bool certainly_negative(double x) { return x < 0; }
/// The value is > 0 (doubles: plainly; enclosures: for every member).
inline bool certainly_positive(double x) { return x > 0; }
/// a < b (doubles: plainly; enclosures: for every pair of members).
inline bool certainly_less(double a, double b) { return a < b; }
/// A value holding both one-sided derivatives p and q. For doubles no such value exists: it
/// returns p, and callers pass the branch to take at an exact kink first.
inline double join(double p, double /*q*/) { return p; }
/// The derivative where none is finite (sqrt at 0): for doubles NaN.
inline double unbounded(double) { return std::numeric_limits<double>::quiet_NaN(); }

/// The value is 0 (doubles: plainly; enclosures: the point 0).
inline bool certainly_zero(double x) { return x == 0; }
/// The value is not 0 (doubles: plainly, NaN included; enclosures: 0 outside).
inline bool certainly_nonzero(double x) { return !(x == 0); }

template <Enclosure T>
bool certainly_zero(const T& x) {
    return lower(x) == 0 && upper(x) == 0;
}
template <Enclosure T>
bool certainly_nonzero(const T& x) {
    return lower(x) > 0 || upper(x) < 0;
}
template <Enclosure T>
bool certainly_negative(const T& x) {
    return upper(x) < 0;
}
template <Enclosure T>
bool certainly_positive(const T& x) {
    return lower(x) > 0;
}
template <Enclosure T>
bool certainly_less(const T& a, const T& b) {
    return upper(a) < lower(b);
}
/// The hull of the two one-sided derivatives.
template <Enclosure T>
T join(const T& p, const T& q) {
    return hull(p, q);
}
/// The whole line (needs T::entire()).
template <Enclosure T>
T unbounded(const T&) {
    return T::entire();
}

template <class T, int N>
bool certainly_negative(const Dual<T, N>& x) {
    return certainly_negative(x.a);
}
template <class T, int N>
bool certainly_positive(const Dual<T, N>& x) {
    return certainly_positive(x.a);
}
template <class T, int N>
bool certainly_zero(const Dual<T, N>& x) {
    return certainly_zero(x.a);
}
template <class T, int N>
bool certainly_nonzero(const Dual<T, N>& x) {
    return certainly_nonzero(x.a);
}
template <class T, int N>
bool certainly_less(const Dual<T, N>& a, const Dual<T, N>& b) {
    return certainly_less(a.a, b.a);
}
template <class T, int N>
Dual<T, N> join(const Dual<T, N>& p, const Dual<T, N>& q) {
    Dual<T, N> r(join(p.a, q.a), Dual<T, N>::zeros());
    for (int i = 0; i < N; ++i) r.v[i] = join(p.v[i], q.v[i]);
    return r;
}
template <class T, int N>
Dual<T, N> unbounded(const Dual<T, N>& x) {
    Dual<T, N> r(unbounded(x.a), Dual<T, N>::zeros());
    for (int i = 0; i < N; ++i) r.v[i] = unbounded(x.v[i]);
    return r;
}

/// (value, d · x.v): the chain rule for a unary function with derivative d at x.a.
template <class T, int N>
Dual<T, N> chain(const T& value, const T& d, const Dual<T, N>& x) {
    Dual<T, N> r(value, Dual<T, N>::zeros());
    for (int i = 0; i < N; ++i) r.v[i] = d * x.v[i];
    return r;
}

/// Component-wise join of two partial vectors.
template <class T, std::size_t N>
std::array<T, N> join_partials(const std::array<T, N>& p, const std::array<T, N>& q) {
    std::array<T, N> r = p;
    for (std::size_t i = 0; i < N; ++i) r[i] = join(p[i], q[i]);
    return r;
}

}  // namespace detail

// ---- arithmetic --------------------------------------------------------------------------------

/// (f + g)' = f' + g'
template <class T, int N>
Dual<T, N> operator+(const Dual<T, N>& f, const Dual<T, N>& g) {
    Dual<T, N> r(f.a + g.a, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = f.v[i] + g.v[i];
    return r;
}
/// (f − g)' = f' − g'
template <class T, int N>
Dual<T, N> operator-(const Dual<T, N>& f, const Dual<T, N>& g) {
    Dual<T, N> r(f.a - g.a, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = f.v[i] - g.v[i];
    return r;
}
/// (−f)' = −f'
template <class T, int N>
Dual<T, N> operator-(const Dual<T, N>& f) {
    Dual<T, N> r(-f.a, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = -f.v[i];
    return r;
}
/// (f·g)' = f'·g + f·g'
template <class T, int N>
Dual<T, N> operator*(const Dual<T, N>& f, const Dual<T, N>& g) {
    Dual<T, N> r(f.a * g.a, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = f.v[i] * g.a + f.a * g.v[i];
    return r;
}
/// (f/g)' = (f' − (f/g)·g')/g  (the quotient q = f/g is reused; g containing 0 follows T's /)
template <class T, int N>
Dual<T, N> operator/(const Dual<T, N>& f, const Dual<T, N>& g) {
    const T q = f.a / g.a;
    Dual<T, N> r(q, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = (f.v[i] - q * g.v[i]) / g.a;
    return r;
}

/// (f + c)' = f'
template <class T, int N>
Dual<T, N> operator+(const Dual<T, N>& f, double c) {
    return {f.a + T(c), f.v};
}
/// (c + f)' = f'
template <class T, int N>
Dual<T, N> operator+(double c, const Dual<T, N>& f) {
    return {T(c) + f.a, f.v};
}
/// (f − c)' = f'
template <class T, int N>
Dual<T, N> operator-(const Dual<T, N>& f, double c) {
    return {f.a - T(c), f.v};
}
/// (c − f)' = −f'
template <class T, int N>
Dual<T, N> operator-(double c, const Dual<T, N>& f) {
    Dual<T, N> r(T(c) - f.a, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = -f.v[i];
    return r;
}
/// (c·f)' = c·f'
template <class T, int N>
Dual<T, N> operator*(double c, const Dual<T, N>& f) {
    const T k(c);
    return detail::chain(k * f.a, k, f);
}
/// (f·c)' = f'·c
template <class T, int N>
Dual<T, N> operator*(const Dual<T, N>& f, double c) {
    const T k(c);
    Dual<T, N> r(f.a * k, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = f.v[i] * k;
    return r;
}
/// (f/c)' = f'/c
template <class T, int N>
Dual<T, N> operator/(const Dual<T, N>& f, double c) {
    const T k(c);
    Dual<T, N> r(f.a / k, f.v);
    for (int i = 0; i < N; ++i) r.v[i] = f.v[i] / k;
    return r;
}
/// (c/g)' = −(c/g)·g'/g
template <class T, int N>
Dual<T, N> operator/(double c, const Dual<T, N>& g) {
    const T q = T(c) / g.a;
    Dual<T, N> r(q, g.v);
    for (int i = 0; i < N; ++i) r.v[i] = -(q * g.v[i]) / g.a;
    return r;
}

template <class T, int N>
Dual<T, N>& operator+=(Dual<T, N>& f, const Dual<T, N>& g) {
    return f = f + g;
}
template <class T, int N>
Dual<T, N>& operator-=(Dual<T, N>& f, const Dual<T, N>& g) {
    return f = f - g;
}
template <class T, int N>
Dual<T, N>& operator*=(Dual<T, N>& f, const Dual<T, N>& g) {
    return f = f * g;
}
template <class T, int N>
Dual<T, N>& operator/=(Dual<T, N>& f, const Dual<T, N>& g) {
    return f = f / g;
}

// ---- elementary functions
// ------------------------------------------------------------------------

/// |f|' = f' where f > 0, −f' where f < 0; where the sign of f is not certain, join(f', −f')
/// (enclosures: the hull; doubles at f = 0: f', the right-hand branch).
template <class T, int N>
Dual<T, N> abs(const Dual<T, N>& f) {
    Dual<T, N> r(abs(f.a), f.v);
    if (detail::certainly_negative(f.a)) {
        for (int i = 0; i < N; ++i) r.v[i] = -f.v[i];
    } else if (!detail::certainly_positive(f.a)) {
        for (int i = 0; i < N; ++i) r.v[i] = detail::join(f.v[i], T(-f.v[i]));
    }
    return r;
}
/// (f²)' = 2·f·f'
template <class T, int N>
Dual<T, N> square(const Dual<T, N>& f) {
    return detail::chain(square(f.a), T(T(2.0) * f.a), f);
}
/// (fⁿ)' = n·fⁿ⁻¹·f'  (f⁰ = 1 with derivative 0)
template <class T, int N>
Dual<T, N> pow(const Dual<T, N>& f, unsigned n) {
    if (n == 0) return Dual<T, N>(pow(f.a, 0u), Dual<T, N>::zeros());
    return detail::chain(pow(f.a, n), T(T(static_cast<double>(n)) * pow(f.a, n - 1)), f);
}
/// (√f)' = f'/(2√f); where f is not certainly > 0 the derivative is unbounded (enclosures: the
/// whole line; doubles: NaN). The value's own decoration says only whether √ is defined and
/// continuous there, not whether it is differentiable.
template <class T, int N>
Dual<T, N> sqrt(const Dual<T, N>& f) {
    const T s = sqrt(f.a);
    if (!detail::certainly_positive(f.a)) {
        Dual<T, N> r(s, f.v);
        for (int i = 0; i < N; ++i) r.v[i] = detail::unbounded(f.a);
        return r;
    }
    return detail::chain(s, T(T(0.5) / s), f);
}
/// (eᶠ)' = eᶠ·f'
template <class T, int N>
Dual<T, N> exp(const Dual<T, N>& f) {
    const T e = exp(f.a);
    return detail::chain(e, e, f);
}
/// (log f)' = f'/f  (f containing 0 follows T's division)
template <class T, int N>
Dual<T, N> log(const Dual<T, N>& f) {
    Dual<T, N> r(log(f.a), f.v);
    for (int i = 0; i < N; ++i) r.v[i] = f.v[i] / f.a;
    return r;
}
/// (sin f)' = cos f · f'
template <class T, int N>
Dual<T, N> sin(const Dual<T, N>& f) {
    return detail::chain(sin(f.a), cos(f.a), f);
}
/// (cos f)' = −sin f · f'
template <class T, int N>
Dual<T, N> cos(const Dual<T, N>& f) {
    return detail::chain(cos(f.a), T(-sin(f.a)), f);
}
/// min(f, g)' = f' where f < g, g' where g < f; where they are not certainly ordered,
/// join(f', g') (enclosures: the hull; doubles at f = g: f').
template <class T, int N>
Dual<T, N> min(const Dual<T, N>& f, const Dual<T, N>& g) {
    const T m = min(f.a, g.a);
    if (detail::certainly_less(f.a, g.a)) return {m, f.v};
    if (detail::certainly_less(g.a, f.a)) return {m, g.v};
    return {m, detail::join_partials(f.v, g.v)};
}
/// max(f, g)' = f' where f > g, g' where g > f; where they are not certainly ordered,
/// join(f', g') (enclosures: the hull; doubles at f = g: f').
template <class T, int N>
Dual<T, N> max(const Dual<T, N>& f, const Dual<T, N>& g) {
    const T m = max(f.a, g.a);
    if (detail::certainly_less(g.a, f.a)) return {m, f.v};
    if (detail::certainly_less(f.a, g.a)) return {m, g.v};
    return {m, detail::join_partials(f.v, g.v)};
}

// ---- Fidget's further ops (issue 14). The piecewise-constant ones have derivative 0 wherever
// they are differentiable; where they jump, the value's decoration (not the partials) says so.

/// ⌊f⌋' = 0 (off the jumps)
template <class T, int N>
Dual<T, N> floor(const Dual<T, N>& f) {
    return {floor(f.a), Dual<T, N>::zeros()};
}
/// ⌈f⌉' = 0 (off the jumps)
template <class T, int N>
Dual<T, N> ceil(const Dual<T, N>& f) {
    return {ceil(f.a), Dual<T, N>::zeros()};
}
/// round(f)' = 0 (off the jumps)
template <class T, int N>
Dual<T, N> round(const Dual<T, N>& f) {
    return {round(f.a), Dual<T, N>::zeros()};
}
/// (tan f)' = (1 + tan² f)·f'
template <class T, int N>
Dual<T, N> tan(const Dual<T, N>& f) {
    const T t = tan(f.a);
    return detail::chain(t, T(T(1.0) + square(t)), f);
}
/// (asin f)' = f'/√(1 − f²)  (unbounded at f = ±1, following T's division)
template <class T, int N>
Dual<T, N> asin(const Dual<T, N>& f) {
    return detail::chain(asin(f.a), T(T(1.0) / sqrt(T(T(1.0) - square(f.a)))), f);
}
/// (acos f)' = −f'/√(1 − f²)
template <class T, int N>
Dual<T, N> acos(const Dual<T, N>& f) {
    return detail::chain(acos(f.a), T(T(-1.0) / sqrt(T(T(1.0) - square(f.a)))), f);
}
/// (atan f)' = f'/(1 + f²)
template <class T, int N>
Dual<T, N> atan(const Dual<T, N>& f) {
    return detail::chain(atan(f.a), T(T(1.0) / T(T(1.0) + square(f.a))), f);
}
/// atan2(f, g)' = (g·f' − f·g')/(f² + g²)
template <class T, int N>
Dual<T, N> atan2(const Dual<T, N>& f, const Dual<T, N>& g) {
    const T r2 = square(f.a) + square(g.a);
    Dual<T, N> r(atan2(f.a, g.a), f.v);
    for (int i = 0; i < N; ++i) r.v[i] = (g.a * f.v[i] - f.a * g.v[i]) / r2;
    return r;
}
/// compare(f, g)' = 0 (off the jumps)
template <class T, int N>
Dual<T, N> compare(const Dual<T, N>& f, const Dual<T, N>& g) {
    return {compare(f.a, g.a), Dual<T, N>::zeros()};
}
/// not(f)' = 0 (off the jumps)
template <class T, int N>
Dual<T, N> logic_not(const Dual<T, N>& f) {
    return {logic_not(f.a), Dual<T, N>::zeros()};
}
/// mod(f, g) = f − |g|·k with k = ⌊f/|g|⌋ locally constant: mod' = f' − sgn(g)·k·g' (where g's
/// sign is not certain, the join of both signs)
template <class T, int N>
Dual<T, N> mod(const Dual<T, N>& f, const Dual<T, N>& g) {
    const T k = floor(T(f.a / abs(g.a)));
    const T s = detail::certainly_positive(g.a)   ? T(1.0)
                : detail::certainly_negative(g.a) ? T(-1.0)
                                                  : detail::join(T(1.0), T(-1.0));
    const T sk = s * k;
    Dual<T, N> r(mod(f.a, g.a), f.v);
    for (int i = 0; i < N; ++i) r.v[i] = f.v[i] - sk * g.v[i];
    return r;
}
/// and(f, g)' = f' where f = 0, g' where f ≠ 0; undecided: join(f', g')
template <class T, int N>
Dual<T, N> logic_and(const Dual<T, N>& f, const Dual<T, N>& g) {
    const T v = logic_and(f.a, g.a);
    if (detail::certainly_zero(f.a)) return {v, f.v};
    if (detail::certainly_nonzero(f.a)) return {v, g.v};
    return {v, detail::join_partials(f.v, g.v)};
}
/// or(f, g)' = f' where f ≠ 0, g' where f = 0; undecided: join(f', g')
template <class T, int N>
Dual<T, N> logic_or(const Dual<T, N>& f, const Dual<T, N>& g) {
    const T v = logic_or(f.a, g.a);
    if (detail::certainly_nonzero(f.a)) return {v, f.v};
    if (detail::certainly_zero(f.a)) return {v, g.v};
    return {v, detail::join_partials(f.v, g.v)};
}

}  // namespace certray
