// interval/poly.h — Poly<T>: a polynomial in the ray parameter t with enclosed coefficients.
//
// Evaluating a tape over Poly<T> with the inputs x = ray_coordinate(o_x, d_x, dom) (and y, z)
// yields the coefficients of g(t) = f(o + t·d), when f restricted to the ray is a polynomial of
// degree ≤ kMaxPolyDegree on dom.
//
// Contract (the meaning of `valid`): if p.valid, there are real numbers a_0 … a_degree with
// a_k ∈ p.c[k] for every k (and a_k = 0 above degree) such that for every t in p.dom (every real t
// when !p.has_dom) the exact function value equals Σ a_k t^k. Every coefficient is computed with
// T's outward-rounded arithmetic, so the exact coefficients (of the exact ray inputs, not of a
// rounded o + t·d) lie in the enclosures. `degree` is an upper bound of the exact degree (the
// enclosure of the leading coefficient may contain 0). If !p.valid nothing is claimed, and every
// operation with an invalid operand is invalid.
//
// Operations: + − × and square / pow (degrees add; above kMaxPolyDegree → invalid); unary −;
// ÷ only by a degree-0 divisor whose enclosure excludes 0; sqrt, exp, log, sin, cos only of a
// degree-0 argument (applied to the constant); abs, min, max of non-constants only when the sign
// of range(a) or range(a − b) on dom decides the branch; a constant whose enclosure is not
// defined (sqrt(−1), a NaN constant, log of a possibly non-positive constant) is invalid.
//
// Reference: docs/theory/closed_form.md (the polynomial pipeline); the centred form of range() is
// the Taylor (mean-value) form, R. E. Moore, "Methods and Applications of Interval Analysis",
// SIAM 1979, ch. 6; Ratschek & Rokne, "Computer Methods for the Range of Functions", 1984.
#pragma once

#include <array>
#include <cmath>

#include "interval/number.h"

namespace certray {

/// The largest degree a Poly may have; a product of higher degree is invalid.
inline constexpr int kMaxPolyDegree = 16;

/// A polynomial in t with coefficient enclosures of type T (Interval or MpfrInterval), valid on
/// the parameter interval `dom` (see the file contract).
template <class T>
struct Poly {
    /// c[k] encloses the exact coefficient of t^k; 0 above degree.
    std::array<T, kMaxPolyDegree + 1> c{};
    /// An upper bound of the exact degree.
    int degree = 0;
    /// False: not (proven) a polynomial on dom; nothing is claimed.
    bool valid = true;
    /// Whether dom is set: the t-range on which min/max/abs were decided. Constants have none.
    bool has_dom = false;
    /// The t-range on which the polynomial is valid (meaningful only when has_dom).
    T dom{};

    /// The constant 0, valid everywhere.
    Poly() = default;
    /// The constant v (implicit, so that the evaluator's T(c) works); a NaN or infinite v is
    /// invalid.
    Poly(double v) : valid(std::isfinite(v)) { c[0] = T(v); }  // NOLINT: implicit on purpose

    /// An invalid polynomial.
    static Poly invalid() {
        Poly p;
        p.valid = false;
        return p;
    }
};

namespace detail {

/// The constant with enclosure x (invalid if x is not defined).
template <class T>
Poly<T> poly_constant(const T& x) {
    Poly<T> p;
    p.c[0] = x;
    p.valid = is_defined(x);
    return p;
}

/// Combines the domains of a and b into r: the intersection when both have one (invalid when it
/// is empty). Returns r.valid.
template <class T>
bool merge_dom(Poly<T>& r, const Poly<T>& a, const Poly<T>& b) {
    if (a.has_dom && b.has_dom) {
        r.has_dom = true;
        r.dom = intersect(a.dom, b.dom);
        if (is_empty(r.dom)) r.valid = false;
    } else if (a.has_dom || b.has_dom) {
        r.has_dom = true;
        r.dom = a.has_dom ? a.dom : b.dom;
    }
    return r.valid;
}

/// A result with the validity and domain of the operands a and b, degree and coefficients 0.
template <class T>
Poly<T> poly_from(const Poly<T>& a, const Poly<T>& b) {
    Poly<T> r;
    r.valid = a.valid && b.valid;
    merge_dom(r, a, b);
    return r;
}

/// Applies f to the constant of a degree-0 argument; anything else is invalid.
template <class T, class F>
Poly<T> poly_unary_constant(const Poly<T>& a, F f) {
    if (!a.valid || a.degree != 0) return Poly<T>::invalid();
    Poly<T> r = poly_constant<T>(f(a.c[0]));
    r.has_dom = a.has_dom;
    r.dom = a.dom;
    return r;
}

/// Sign of p on its domain: +1 if certainly ≥ 0, −1 if certainly ≤ 0, 0 when undecided.
template <class T>
int certain_sign(const Poly<T>& p);

}  // namespace detail

/// o + t·d on dom (degree 1, or 0 when d == 0), both exact.
template <class T>
Poly<T> ray_coordinate(double o, double d, const T& dom) {
    Poly<T> p(o);
    p.c[1] = T(d);
    p.degree = d != 0 ? 1 : 0;
    p.valid = std::isfinite(o) && std::isfinite(d) && !is_empty(dom);
    p.has_dom = true;
    p.dom = dom;
    return p;
}

/// The same polynomial with coefficients and domain converted to U by U(x) (e.g. Interval ↔
/// UpInterval for evaluation inside one RoundingScope; the conversion must be exact or outward).
template <class U, class T>
Poly<U> poly_cast(const Poly<T>& x) {
    Poly<U> r;
    r.degree = x.degree;
    r.valid = x.valid;
    r.has_dom = x.has_dom;
    r.dom = U(x.dom);
    for (int k = 0; k <= x.degree; ++k) r.c[k] = U(x.c[k]);
    return r;
}

/// Horner's scheme in T: encloses Σ a_k t^k for every t in the interval t and every choice of the
/// a_k in the coefficient enclosures. An invalid p gives the entire line, not defined.
template <class T>
T horner(const Poly<T>& p, const T& t) {
    if (!p.valid) {
        T e = T::entire();
        e.defined = false;
        return e;
    }
    T r = p.c[p.degree];
    for (int k = p.degree - 1; k >= 0; --k) r = r * t + p.c[k];
    return r;
}

/// Encloses p over p.dom (every real t if !has_dom): the intersection of Horner over dom and the
/// centred (Taylor) form Σ q_k (dom − m)^k, the q_k the coefficients shifted to the midpoint m
/// (enclosed in T). An invalid p gives the entire line, not defined.
template <class T>
T range(const Poly<T>& p) {
    if (!p.valid) return horner(p, p.dom);
    if (p.degree == 0) return p.c[0];
    if (!p.has_dom) return T::entire();
    T direct = horner(p, p.dom);
    const double lo = lower(p.dom), hi = upper(p.dom);
    if (!std::isfinite(lo) || !std::isfinite(hi)) return direct;
    const T m(0.5 * lo + 0.5 * hi);  // any point: the enclosures below hold for every m
    // Taylor shift by synthetic division: q(s) = p(m + s).
    std::array<T, kMaxPolyDegree + 1> q = p.c;
    const int n = p.degree;
    for (int i = 0; i < n; ++i)
        for (int k = n - 1; k >= i; --k) q[k] = q[k] + m * q[k + 1];
    const T s = p.dom - m;  // contains 0: even powers are [0, r^k], odd [−r^k, r^k]
    T centred = q[0];
    for (int k = 1; k <= n; ++k) centred = centred + q[k] * pow(s, static_cast<unsigned>(k));
    return intersect(direct, centred);
}

template <class T>
int detail::certain_sign(const Poly<T>& p) {
    if (!p.valid) return 0;
    if (p.degree > 0 && !p.has_dom) return 0;
    const T r = range(p);
    if (is_empty(r)) return 0;
    if (lower(r) >= 0) return 1;
    if (upper(r) <= 0) return -1;
    return 0;
}

/// a + b coefficientwise; degree max(deg a, deg b).
template <class T>
Poly<T> operator+(const Poly<T>& a, const Poly<T>& b) {
    Poly<T> r = detail::poly_from(a, b);
    if (!r.valid) return Poly<T>::invalid();
    r.degree = a.degree > b.degree ? a.degree : b.degree;
    for (int k = 0; k <= r.degree; ++k) r.c[k] = a.c[k] + b.c[k];
    return r;
}

/// a − b coefficientwise; degree max(deg a, deg b).
template <class T>
Poly<T> operator-(const Poly<T>& a, const Poly<T>& b) {
    Poly<T> r = detail::poly_from(a, b);
    if (!r.valid) return Poly<T>::invalid();
    r.degree = a.degree > b.degree ? a.degree : b.degree;
    for (int k = 0; k <= r.degree; ++k) r.c[k] = a.c[k] - b.c[k];
    return r;
}

/// −a coefficientwise (exact).
template <class T>
Poly<T> operator-(const Poly<T>& a) {
    if (!a.valid) return Poly<T>::invalid();
    Poly<T> r = a;
    for (int k = 0; k <= r.degree; ++k) r.c[k] = -a.c[k];
    return r;
}

/// a · b: c_k = Σ_{i+j=k} a_i b_j; degree deg a + deg b (> kMaxPolyDegree → invalid).
template <class T>
Poly<T> operator*(const Poly<T>& a, const Poly<T>& b) {
    Poly<T> r = detail::poly_from(a, b);
    if (!r.valid || a.degree + b.degree > kMaxPolyDegree) return Poly<T>::invalid();
    r.degree = a.degree + b.degree;
    for (int i = 0; i <= a.degree; ++i)
        for (int j = 0; j <= b.degree; ++j) r.c[i + j] = r.c[i + j] + a.c[i] * b.c[j];
    return r;
}

/// a²: c_k = Σ_{i<j, i+j=k} 2 a_i a_j + a_{k/2}² (square() is tighter than a product);
/// degree 2·deg a.
template <class T>
Poly<T> square(const Poly<T>& a) {
    if (!a.valid || 2 * a.degree > kMaxPolyDegree) return Poly<T>::invalid();
    Poly<T> r = a;
    r.degree = 2 * a.degree;
    for (int k = 0; k <= r.degree; ++k) r.c[k] = T(0.0);
    const T two(2.0);
    for (int i = 0; i <= a.degree; ++i) {
        r.c[2 * i] = r.c[2 * i] + square(a.c[i]);
        for (int j = i + 1; j <= a.degree; ++j) r.c[i + j] = r.c[i + j] + two * (a.c[i] * a.c[j]);
    }
    return r;
}

/// aⁿ by binary powering (a⁰ = 1); a constant uses T's pow; n·deg a > kMaxPolyDegree → invalid.
template <class T>
Poly<T> pow(const Poly<T>& a, unsigned n) {
    if (!a.valid) return Poly<T>::invalid();
    if (n == 0) {
        Poly<T> one(1.0);
        one.has_dom = a.has_dom;
        one.dom = a.dom;
        return one;
    }
    if (a.degree == 0) return detail::poly_unary_constant(a, [n](const T& x) { return pow(x, n); });
    if (static_cast<long>(n) * a.degree > kMaxPolyDegree) return Poly<T>::invalid();
    Poly<T> result = a;
    Poly<T> base = a;
    bool first = true;
    for (unsigned e = n;;) {
        if (e & 1u) {
            result = first ? base : result * base;
            first = false;
        }
        e >>= 1u;
        if (!e) break;
        base = square(base);
    }
    return result;
}

/// a ÷ b: only for a degree-0 b whose enclosure excludes 0 (each coefficient divided by it).
template <class T>
Poly<T> operator/(const Poly<T>& a, const Poly<T>& b) {
    Poly<T> r = detail::poly_from(a, b);
    if (!r.valid || b.degree != 0 || !is_defined(b.c[0]) || is_empty(b.c[0]) ||
        !(lower(b.c[0]) > 0 || upper(b.c[0]) < 0))
        return Poly<T>::invalid();
    r.degree = a.degree;
    for (int k = 0; k <= r.degree; ++k) r.c[k] = a.c[k] / b.c[0];
    return r;
}

/// √a of a constant (invalid unless the constant's enclosure is ≥ 0); else invalid.
template <class T>
Poly<T> sqrt(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return sqrt(x); });
}
/// exp a of a constant; else invalid.
template <class T>
Poly<T> exp(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return exp(x); });
}
/// log a of a constant (invalid unless its enclosure is > 0); else invalid.
template <class T>
Poly<T> log(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return log(x); });
}
/// sin a of a constant; else invalid.
template <class T>
Poly<T> sin(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return sin(x); });
}
/// cos a of a constant; else invalid.
template <class T>
Poly<T> cos(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return cos(x); });
}

/// |a|: a constant uses T's abs; otherwise a if range(a) ≥ 0 on dom, −a if ≤ 0, else invalid.
template <class T>
Poly<T> abs(const Poly<T>& a) {
    if (!a.valid) return Poly<T>::invalid();
    if (a.degree == 0) return detail::poly_unary_constant(a, [](const T& x) { return abs(x); });
    const int s = detail::certain_sign(a);
    if (s > 0) return a;
    if (s < 0) return -a;
    return Poly<T>::invalid();
}

/// min(a, b): two constants use T's min; otherwise b if range(a − b) ≥ 0 on dom, a if ≤ 0, else
/// invalid. The result carries the merged domain.
template <class T>
Poly<T> min(const Poly<T>& a, const Poly<T>& b) {
    Poly<T> r = detail::poly_from(a, b);
    if (!r.valid) return Poly<T>::invalid();
    if (a.degree == 0 && b.degree == 0) {
        r.c[0] = min(a.c[0], b.c[0]);
        r.valid = is_defined(r.c[0]);
        return r;
    }
    const int s = detail::certain_sign(a - b);
    if (s == 0) return Poly<T>::invalid();
    const Poly<T>& pick = s > 0 ? b : a;
    r.c = pick.c;
    r.degree = pick.degree;
    return r;
}

/// max(a, b): two constants use T's max; otherwise a if range(a − b) ≥ 0 on dom, b if ≤ 0, else
/// invalid. The result carries the merged domain.
template <class T>
Poly<T> max(const Poly<T>& a, const Poly<T>& b) {
    Poly<T> r = detail::poly_from(a, b);
    if (!r.valid) return Poly<T>::invalid();
    if (a.degree == 0 && b.degree == 0) {
        r.c[0] = max(a.c[0], b.c[0]);
        r.valid = is_defined(r.c[0]);
        return r;
    }
    const int s = detail::certain_sign(a - b);
    if (s == 0) return Poly<T>::invalid();
    const Poly<T>& pick = s > 0 ? a : b;
    r.c = pick.c;
    r.degree = pick.degree;
    return r;
}

// ---- Fidget's further ops (issue 14): not polynomial; T's op on constants, else invalid --------

namespace detail {
/// Applies f to the constants of two degree-0 arguments; anything else is invalid.
template <class T, class F>
Poly<T> poly_binary_constant(const Poly<T>& a, const Poly<T>& b, F f) {
    Poly<T> r = poly_from(a, b);
    if (!r.valid || a.degree != 0 || b.degree != 0) return Poly<T>::invalid();
    r.c[0] = f(a.c[0], b.c[0]);
    r.valid = is_defined(r.c[0]);
    return r;
}
}  // namespace detail

/// floor of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> floor(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return floor(x); });
}

/// ceil of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> ceil(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return ceil(x); });
}

/// round of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> round(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return round(x); });
}

/// tan of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> tan(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return tan(x); });
}

/// asin of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> asin(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return asin(x); });
}

/// acos of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> acos(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return acos(x); });
}

/// atan of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> atan(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return atan(x); });
}

/// logic_not of a constant; else invalid (not a polynomial).
template <class T>
Poly<T> logic_not(const Poly<T>& a) {
    return detail::poly_unary_constant(a, [](const T& x) { return logic_not(x); });
}

/// atan2 of two constants; else invalid (not a polynomial).
template <class T>
Poly<T> atan2(const Poly<T>& a, const Poly<T>& b) {
    return detail::poly_binary_constant(a, b, [](const T& x, const T& y) { return atan2(x, y); });
}

/// compare of two constants; else invalid (not a polynomial).
template <class T>
Poly<T> compare(const Poly<T>& a, const Poly<T>& b) {
    return detail::poly_binary_constant(a, b, [](const T& x, const T& y) { return compare(x, y); });
}

/// mod of two constants; else invalid (not a polynomial).
template <class T>
Poly<T> mod(const Poly<T>& a, const Poly<T>& b) {
    return detail::poly_binary_constant(a, b, [](const T& x, const T& y) { return mod(x, y); });
}

/// logic_and of two constants; else invalid (not a polynomial).
template <class T>
Poly<T> logic_and(const Poly<T>& a, const Poly<T>& b) {
    return detail::poly_binary_constant(a, b,
                                        [](const T& x, const T& y) { return logic_and(x, y); });
}

/// logic_or of two constants; else invalid (not a polynomial).
template <class T>
Poly<T> logic_or(const Poly<T>& a, const Poly<T>& b) {
    return detail::poly_binary_constant(a, b,
                                        [](const T& x, const T& y) { return logic_or(x, y); });
}

}  // namespace certray
