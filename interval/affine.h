// interval/affine.h — affine arithmetic in Messine's AF1 form with a fixed number of noise symbols.
//
// An Affine<N> x̂ = x0 + Σ_{i<N} x_i ε_i + err·ε_N stands for the set of reals it takes as the
// primary noise symbols ε_0 … ε_{N−1} and the error symbol ε_N range over [−1, 1]. The primary
// symbols are shared between forms (that is the correlation interval arithmetic loses); the error
// term err ≥ 0 is private to each form and absorbs every rounding error and every error of a
// nonlinear approximation.
//
// Contract: for every operation op and every assignment of the primary symbols, if x (and y) are
// values of x̂ (and ŷ) under that assignment and op is defined there, then op(x, y) is a value of
// op(x̂, ŷ) under the same assignment (for some ε_N). Hence to_interval() of the result encloses
// op over the box. `defined` has the meaning of Interval's decoration: the function is defined
// and continuous on the whole input box.
//
// Rounding: each operation opens a RoundingScope (upward mode). A coefficient is computed rounded
// up and its rounding error is bounded by (its value rounded up − rounded down), added to err;
// err itself is summed upward. Nonlinear functions are approximated by f(x) ≈ α·x + ζ with
// |f(x) − α·x − ζ| ≤ δ on the range of x̂, where α is a double and the set {f(x) − α·x} is
// enclosed with UpInterval arithmetic (so ζ, δ carry no unbounded rounding error). Infinite or NaN
// coefficients fall back to from_interval of the Interval result.
//
// Reference: docs/theory/affine.md; J. Stolfi, L. H. de Figueiredo, "Self-validated numerical
// methods and applications", IMPA 1997; F. Messine, "Extensions of affine arithmetic: application
// to unconstrained global optimization", J. Universal Computer Science 8(11), 2002 (AF1).
#pragma once

#include <array>
#include <cassert>
#include <cmath>
#include <limits>

#include "interval/interval.h"
#include "interval/number.h"

namespace certray {

/// An affine form with N primary noise symbols and one accumulated error term (AF1).
template <int N>
struct Affine {
    static_assert(N >= 1, "Affine<N> needs at least one primary noise symbol");

    /// Central value.
    double x0 = 0.0;
    /// Partial deviations: the coefficient of the primary symbol ε_i.
    std::array<double, N> xi{};
    /// The accumulated error term (≥ 0; +inf for an unbounded form).
    double err = 0.0;
    /// The function that produced this form is defined and continuous on the whole input box.
    /// False for the empty form (x0 = NaN).
    bool defined = true;

    /// The point 0.
    Affine() = default;
    /// The point c (implicit, so that double constants of the DAG convert); see constant().
    Affine(double c) { *this = constant(c); }  // NOLINT: implicit on purpose

    /// The exact point c. NaN gives the empty form; ±inf the unbounded form, not defined.
    static Affine constant(double c);
    /// The input variable with symbol ε_i over `box`: x0 = midpoint, x_i = radius rounded up, so
    /// [x0 − x_i, x0 + x_i] ⊇ box. An unbounded or empty box gives from_interval(box).
    static Affine variable(const Interval& box, int i);
    /// No correlation: x0 = midpoint, err = radius rounded up (+inf when unbounded).
    static Affine from_interval(const Interval& v);
    /// The empty form.
    static Affine empty();

    /// The range x0 ± (Σ|x_i| + err), rounded outward; carries `defined`.
    Interval to_interval() const;
    /// As to_interval(), for use inside a live RoundingScope.
    UpInterval range_up() const;
    /// True when x0 is NaN (the empty set).
    bool is_empty() const { return std::isnan(x0); }
};

// ---- queries (the Enclosure concept) ---------------------------------------------------------

template <int N>
double lower(const Affine<N>& x) {
    return x.to_interval().lower();
}
template <int N>
double upper(const Affine<N>& x) {
    return x.to_interval().upper();
}
template <int N>
bool is_defined(const Affine<N>& x) {
    return x.defined;
}
template <int N>
bool is_empty(const Affine<N>& x) {
    return x.is_empty();
}
template <int N>
Interval to_interval(const Affine<N>& x) {
    return x.to_interval();
}

namespace detail {

/// Upward-mode primitives that record their rounding error. Valid only inside a RoundingScope.
struct ErrorAccumulator {
    IntervalArith rnd;
    double err = 0.0;

    /// err += v (v ≥ 0), rounded up.
    void add_error(double v) { err = rnd.add_up(err, v); }
    /// a + b rounded up; |result − (a + b)| ≤ up − down is added to err.
    double add(double a, double b) {
        const double up = rnd.add_up(a, b);
        add_error(rnd.sub_up(up, rnd.add_down(a, b)));
        return up;
    }
    /// a · b rounded up; |result − a·b| ≤ up − down is added to err.
    double mul(double a, double b) {
        const double up = rnd.mul_up(a, b);
        add_error(rnd.sub_up(up, rnd.mul_down(a, b)));
        return up;
    }
};

template <int N>
bool is_finite_form(const Affine<N>& x) {
    if (!std::isfinite(x.x0) || !std::isfinite(x.err)) return false;
    for (double c : x.xi)
        if (!std::isfinite(c)) return false;
    return true;
}

/// from_interval inside a live RoundingScope: x0 = a point of v, err ≥ max(x0 − lo, hi − x0).
template <int N>
Affine<N> form_of(const UpInterval& v, bool def) {
    Affine<N> z;
    z.defined = def && !v.is_empty();
    if (v.is_empty()) {
        z.x0 = std::numeric_limits<double>::quiet_NaN();
        return z;
    }
    IntervalArith rnd;
    z.x0 = midpoint(v);  // 2·lo + 1 for [lo, +inf]: may overflow; keep x0 finite and in v
    if (!std::isfinite(z.x0)) z.x0 = std::isfinite(v.lower()) ? v.lower() : v.upper();
    if (!std::isfinite(z.x0)) z.x0 = 0.0;
    z.err = std::max(rnd.sub_up(z.x0, v.lower()), rnd.sub_up(v.upper(), z.x0));
    if (std::isnan(z.err)) z.err = std::numeric_limits<double>::infinity();
    return z;
}

/// A double c ∈ D and δ ≥ max(c − lo, hi − c): D ⊆ [c − δ, c + δ].
inline double center_of(const UpInterval& d, double& delta) {
    IntervalArith rnd;
    double c = midpoint(d);
    delta = std::max(rnd.sub_up(c, d.lower()), rnd.sub_up(d.upper(), c));
    return c;
}

/// z = α·x̂ + β·ŷ + c: z0 = α x0 + β y0 + c, z_i = α x_i + β y_i, err = |α| ex + |β| ey + rounding.
template <int N>
Affine<N> combine(double a, const Affine<N>& x, double b, const Affine<N>& y, double c, bool def) {
    ErrorAccumulator acc;
    Affine<N> z;
    z.x0 = acc.add(acc.add(acc.mul(a, x.x0), acc.mul(b, y.x0)), c);
    for (int i = 0; i < N; ++i) z.xi[i] = acc.add(acc.mul(a, x.xi[i]), acc.mul(b, y.xi[i]));
    const double ex =
        acc.rnd.add_up(acc.rnd.mul_up(std::fabs(a), x.err), acc.rnd.mul_up(std::fabs(b), y.err));
    z.err = acc.rnd.add_up(ex, acc.err);
    z.defined = def;
    return z;
}

/// The approximation f(x̂) ≈ α·x̂ + ζ ± δ, where D ⊇ {f(x) − α x : x in the range of x̂}:
/// ζ = a point of D, δ = its distance to D's far end. Falls back to from_interval(fx) when a
/// coefficient is not finite or when δ alone exceeds the radius of fx (correlation lost anyway).
template <int N>
Affine<N> linear_image(double alpha, const Affine<N>& x, const UpInterval& d, const UpInterval& fx,
                       bool def) {
    if (d.is_empty() || !std::isfinite(alpha)) return form_of<N>(fx, def);
    double delta = 0.0;
    const double c = center_of(d, delta);
    Affine<N> z = combine(alpha, x, 0.0, x, c, def);
    IntervalArith rnd;
    z.err = rnd.add_up(z.err, delta);
    const double fx_rad = rnd.mul_up(0.5, width(fx));
    if (!is_finite_form(z) || !(delta <= fx_rad)) return form_of<N>(fx, def);
    return z;
}

/// Chebyshev-style approximation for f convex or concave on the finite range xr = [a, b]:
/// d = f − α x is then convex or concave, so its extremes on [a, b] lie at a, b and at the
/// stationary point u (f'(u) = α), enclosed in `u`. D = hull(d(a), d(b), d(u ∩ [a, b])).
template <int N, class F>
Affine<N> chebyshev(const Affine<N>& x, const UpInterval& xr, F f, double alpha,
                    const UpInterval& u, const UpInterval& fx, bool def) {
    const UpInterval a(xr.lower()), b(xr.upper());
    UpInterval d = hull(f(a) - a * alpha, f(b) - b * alpha);
    const UpInterval uc = intersect(u, xr);
    if (!uc.is_empty()) d = hull(d, f(uc) - uc * alpha);
    return linear_image(alpha, x, d, fx, def);
}

/// The slope (f(b) − f(a)) / (b − a) as a double (any double is sound; this one is close).
template <class F>
double secant_slope(const UpInterval& xr, F f) {
    const UpInterval a(xr.lower()), b(xr.upper());
    return midpoint((f(b) - f(a)) / (b - a));
}

/// Taylor form about m = x0: f(x) − α x = f(m) − α m + (f'(m) − α)(x − m) + f''(ξ)(x − m)²/2,
/// with fm ∋ f(m), dm ∋ f'(m), d2 ⊇ f''(range), α = a point of dm.
template <int N>
Affine<N> taylor(const Affine<N>& x, const UpInterval& xr, const UpInterval& fm,
                 const UpInterval& dm, const UpInterval& d2, const UpInterval& fx, bool def) {
    const double alpha = midpoint(dm);
    const UpInterval m(x.x0), h = xr - m;
    const UpInterval d = fm - m * alpha + (dm - alpha) * h + d2 * square(h) * 0.5;
    return linear_image(alpha, x, d, fx, def);
}

}  // namespace detail

// ---- construction and conversion -------------------------------------------------------------

template <int N>
Affine<N> Affine<N>::empty() {
    Affine z;
    z.x0 = std::numeric_limits<double>::quiet_NaN();
    z.defined = false;
    return z;
}

template <int N>
Affine<N> Affine<N>::constant(double c) {
    if (std::isnan(c)) return empty();
    Affine z;
    if (std::isinf(c)) {
        z.err = std::numeric_limits<double>::infinity();
        z.defined = false;
        return z;
    }
    z.x0 = c;
    return z;
}

template <int N>
Affine<N> Affine<N>::from_interval(const Interval& v) {
    RoundingScope scope;
    return detail::form_of<N>(UpInterval(v), v.defined);
}

template <int N>
Affine<N> Affine<N>::variable(const Interval& box, int i) {
    assert(0 <= i && i < N);
    if (box.is_empty() || !std::isfinite(box.lower()) || !std::isfinite(box.upper()))
        return from_interval(box);
    RoundingScope scope;
    Affine z = detail::form_of<N>(UpInterval(box), box.defined);
    if (!std::isfinite(z.err)) return z;  // radius overflows: keep it as error
    z.xi[i] = z.err;
    z.err = 0.0;
    return z;
}

template <int N>
UpInterval Affine<N>::range_up() const {
    if (is_empty()) return UpInterval::empty();
    detail::IntervalArith rnd;
    double r = err;
    for (double c : xi) r = rnd.add_up(r, std::fabs(c));
    if (std::isnan(r)) r = std::numeric_limits<double>::infinity();
    double lo = rnd.sub_down(x0, r), hi = rnd.add_up(x0, r);
    if (std::isnan(lo)) lo = -std::numeric_limits<double>::infinity();
    if (std::isnan(hi)) hi = std::numeric_limits<double>::infinity();
    return {typename UpInterval::Boost(lo, hi), defined};
}

template <int N>
Interval Affine<N>::to_interval() const {
    RoundingScope scope;
    return Interval(range_up());
}

// ---- affine operations -----------------------------------------------------------------------
// Inputs that are not finite forms go through the Interval operation on their ranges.

namespace detail {
/// from_interval(f(range of x)) inside a scope: the fallback of every unary operation.
template <int N, class F>
Affine<N> unary_fallback(const Affine<N>& x, F f) {
    const UpInterval r = f(x.range_up());
    return form_of<N>(r, r.defined);
}
template <int N, class F>
Affine<N> binary_fallback(const Affine<N>& x, const Affine<N>& y, F f) {
    const UpInterval r = f(x.range_up(), y.range_up());
    return form_of<N>(r, r.defined);
}
}  // namespace detail

/// x̂ + ŷ: coefficients added (each sum's rounding error into err), err = ex + ey + rounding.
template <int N>
Affine<N> operator+(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    auto f = [](const UpInterval& a, const UpInterval& b) { return a + b; };
    if (!detail::is_finite_form(x) || !detail::is_finite_form(y))
        return detail::binary_fallback(x, y, f);
    Affine<N> z = detail::combine(1.0, x, 1.0, y, 0.0, x.defined && y.defined);
    return detail::is_finite_form(z) ? z : detail::binary_fallback(x, y, f);
}

/// x̂ − ŷ: as +; x̂ − x̂ is exactly 0 ± 2 ex.
template <int N>
Affine<N> operator-(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    auto f = [](const UpInterval& a, const UpInterval& b) { return a - b; };
    if (!detail::is_finite_form(x) || !detail::is_finite_form(y))
        return detail::binary_fallback(x, y, f);
    Affine<N> z = detail::combine(1.0, x, -1.0, y, 0.0, x.defined && y.defined);
    return detail::is_finite_form(z) ? z : detail::binary_fallback(x, y, f);
}

/// −x̂: every coefficient negated (exact), err unchanged.
template <int N>
Affine<N> operator-(const Affine<N>& x) {
    Affine<N> z = x;
    z.x0 = -x.x0;
    for (double& c : z.xi) c = -c;
    return z;
}

/// c·x̂: c x0, c x_i with rounding errors, err = |c| ex + rounding.
template <int N>
Affine<N> operator*(double c, const Affine<N>& x) {
    RoundingScope scope;
    auto f = [c](const UpInterval& a) { return a * c; };
    if (!detail::is_finite_form(x) || !std::isfinite(c)) return detail::unary_fallback(x, f);
    Affine<N> z = detail::combine(c, x, 0.0, x, 0.0, x.defined);
    return detail::is_finite_form(z) ? z : detail::unary_fallback(x, f);
}
template <int N>
Affine<N> operator*(const Affine<N>& x, double c) {
    return c * x;
}
template <int N>
Affine<N> operator+(const Affine<N>& x, double c) {
    return x + Affine<N>(c);
}
template <int N>
Affine<N> operator+(double c, const Affine<N>& x) {
    return Affine<N>(c) + x;
}
template <int N>
Affine<N> operator-(const Affine<N>& x, double c) {
    return x - Affine<N>(c);
}
template <int N>
Affine<N> operator-(double c, const Affine<N>& x) {
    return Affine<N>(c) - x;
}

/// x̂·ŷ = x0 y0 + Σ (x0 y_i + y0 x_i) ε_i + r̂x r̂y with |r̂x r̂y| ≤ Rx Ry (R = Σ|c_i| + err);
/// err = |y0| ex + |x0| ey + Rx Ry + rounding.
template <int N>
Affine<N> operator*(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    auto f = [](const UpInterval& a, const UpInterval& b) { return a * b; };
    if (!detail::is_finite_form(x) || !detail::is_finite_form(y))
        return detail::binary_fallback(x, y, f);
    detail::ErrorAccumulator acc;
    auto& rnd = acc.rnd;
    Affine<N> z;
    z.x0 = acc.mul(x.x0, y.x0);
    double rx = x.err, ry = y.err;
    for (int i = 0; i < N; ++i) {
        z.xi[i] = acc.add(acc.mul(x.x0, y.xi[i]), acc.mul(y.x0, x.xi[i]));
        rx = rnd.add_up(rx, std::fabs(x.xi[i]));
        ry = rnd.add_up(ry, std::fabs(y.xi[i]));
    }
    const double lin =
        rnd.add_up(rnd.mul_up(std::fabs(y.x0), x.err), rnd.mul_up(std::fabs(x.x0), y.err));
    z.err = rnd.add_up(rnd.add_up(lin, rnd.mul_up(rx, ry)), acc.err);
    z.defined = x.defined && y.defined;
    return detail::is_finite_form(z) ? z : detail::binary_fallback(x, y, f);
}

// ---- nonlinear operations --------------------------------------------------------------------

/// x̂² = x0² + 2 x0 r̂ + r̂² with r̂² ∈ [0, R²]: z0 = x0² + h, z_i = 2 x0 x_i,
/// err = 2|x0| ex + h + rounding, where h ≥ R²/2.
template <int N>
Affine<N> square(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return square(a); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    detail::ErrorAccumulator acc;
    auto& rnd = acc.rnd;
    double r = x.err;
    for (double c : x.xi) r = rnd.add_up(r, std::fabs(c));
    const double h = rnd.mul_up(0.5, rnd.mul_up(r, r));
    Affine<N> z;
    z.x0 = acc.add(acc.mul(x.x0, x.x0), h);
    const double two_x0 = 2.0 * x.x0;  // exact unless it overflows (caught below)
    for (int i = 0; i < N; ++i) z.xi[i] = acc.mul(two_x0, x.xi[i]);
    z.err = rnd.add_up(rnd.add_up(rnd.mul_up(std::fabs(two_x0), x.err), h), acc.err);
    z.defined = x.defined;
    return detail::is_finite_form(z) ? z : detail::unary_fallback(x, f);
}

/// xⁿ: n = 0 → 1; n = 1 → x̂; n = 2 → square. n ≥ 3: a range without 0 → Chebyshev (xⁿ is
/// convex there, or concave for odd n and x < 0): α = secant slope, stationary point
/// u = ±(|α|/n)^(1/(n−1)) with the sign of the range; a range containing 0 → Taylor form about
/// x0 with f'' = n(n−1) x^(n−2) over the range.
template <int N>
Affine<N> pow(const Affine<N>& x, unsigned n) {
    if (n == 0) {
        Affine<N> one(1.0);
        one.defined = x.defined && !x.is_empty();
        return x.is_empty() ? Affine<N>::empty() : one;
    }
    if (n == 1) return x;
    if (n == 2) return square(x);
    RoundingScope scope;
    auto f = [n](const UpInterval& a) { return pow(a, n); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up(), m(x.x0);
    const double dn = n;
    if (xr.lower() > 0 || xr.upper() < 0) {
        const double alpha = detail::secant_slope(xr, f);
        const UpInterval au = exp(log(UpInterval(std::fabs(alpha)) / dn) / (dn - 1.0));
        const UpInterval u = xr.lower() > 0 ? au : -au;
        return detail::chebyshev(x, xr, f, alpha, u, f(xr), x.defined);
    }
    return detail::taylor(x, xr, pow(m, n), pow(m, n - 1) * dn, pow(xr, n - 2) * (dn * (dn - 1.0)),
                          f(xr), x.defined);
}

/// √ on the range [a, b] (b ≥ 0): a < 0 → interval fallback, not defined; a = b → the point;
/// else Chebyshev (concave): α = 1/(√a + √b), stationary point u = 1/(4α²).
template <int N>
Affine<N> sqrt(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return sqrt(a); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up();
    if (xr.lower() < 0 || xr.lower() == xr.upper()) return detail::unary_fallback(x, f);
    const UpInterval sa = sqrt(UpInterval(xr.lower())), sb = sqrt(UpInterval(xr.upper()));
    const double alpha = midpoint(UpInterval(1.0) / (sa + sb));
    const UpInterval u = UpInterval(0.25) / square(UpInterval(alpha));
    return detail::chebyshev(x, xr, f, alpha, u, f(xr), x.defined);
}

/// exp: Chebyshev (convex): α = secant slope, stationary point u = log α (α > 0 required).
template <int N>
Affine<N> exp(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return exp(a); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up(), fx = f(xr);
    if (xr.lower() == xr.upper() || !std::isfinite(fx.upper())) return detail::unary_fallback(x, f);
    const double alpha = detail::secant_slope(xr, f);
    if (!(alpha > 0) || !std::isfinite(alpha)) return detail::form_of<N>(fx, fx.defined);
    return detail::chebyshev(x, xr, f, alpha, log(UpInterval(alpha)), fx, x.defined);
}

/// log on the range [a, b]: b ≤ 0 → empty; a ≤ 0 → interval fallback (unbounded, not defined);
/// else Chebyshev (concave): α = secant slope, stationary point u = 1/α.
template <int N>
Affine<N> log(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return log(a); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up();
    if (xr.lower() <= 0 || xr.lower() == xr.upper()) return detail::unary_fallback(x, f);
    const double alpha = detail::secant_slope(xr, f);
    if (!(alpha > 0) || !std::isfinite(alpha)) return detail::unary_fallback(x, f);
    return detail::chebyshev(x, xr, f, alpha, UpInterval(1.0) / UpInterval(alpha), f(xr),
                             x.defined);
}

/// 1/x̂ for a range [a, b] not containing 0: a > 0 → Chebyshev (convex): α = −1/(ab) (a point
/// of it), stationary point u = 1/√(−α); b < 0 → −(1/(−x̂)); 0 ∈ [a, b] → interval fallback.
template <int N>
Affine<N> reciprocal(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return UpInterval(1.0) / a; };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up();
    if (xr.upper() < 0) return -reciprocal(-x);
    if (!(xr.lower() > 0) || xr.lower() == xr.upper()) return detail::unary_fallback(x, f);
    const double alpha =
        midpoint(UpInterval(-1.0) / (UpInterval(xr.lower()) * UpInterval(xr.upper())));
    if (!(alpha < 0)) return detail::unary_fallback(x, f);
    const UpInterval u = UpInterval(1.0) / sqrt(UpInterval(-alpha));
    return detail::chebyshev(x, xr, f, alpha, u, f(xr), x.defined);
}

/// x̂ / ŷ = x̂ · (1/ŷ) when 0 ∉ range(ŷ); otherwise the Interval quotient (not defined).
template <int N>
Affine<N> operator/(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    const UpInterval yr = y.range_up();
    if (!detail::is_finite_form(x) || !detail::is_finite_form(y) || contains(yr, 0.0))
        return detail::binary_fallback(
            x, y, [](const UpInterval& a, const UpInterval& b) { return a / b; });
    return x * reciprocal(y);
}
template <int N>
Affine<N> operator/(const Affine<N>& x, double c) {
    return x / Affine<N>(c);
}
template <int N>
Affine<N> operator/(double c, const Affine<N>& x) {
    return Affine<N>(c) / x;
}

/// sin: range radius ≤ 1 → Taylor form about x0 with f'' = −sin over the range; wider → Interval.
template <int N>
Affine<N> sin(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return sin(a); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up(), m(x.x0);
    if (!(width(xr) <= 2.0)) return detail::unary_fallback(x, f);
    return detail::taylor(x, xr, sin(m), cos(m), -sin(xr), f(xr), x.defined);
}

/// cos: range radius ≤ 1 → Taylor form about x0 with f'' = −cos over the range; wider → Interval.
template <int N>
Affine<N> cos(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return cos(a); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up(), m(x.x0);
    if (!(width(xr) <= 2.0)) return detail::unary_fallback(x, f);
    return detail::taylor(x, xr, cos(m), -sin(m), -cos(xr), f(xr), x.defined);
}

/// |x̂| on [a, b]: a ≥ 0 → x̂; b ≤ 0 → −x̂; a < 0 < b → Chebyshev (convex):
/// α = (a + b)/(b − a), d = |x| − αx has its minimum at u = 0.
template <int N>
Affine<N> abs(const Affine<N>& x) {
    RoundingScope scope;
    auto f = [](const UpInterval& a) { return abs(a); };
    if (!detail::is_finite_form(x)) return detail::unary_fallback(x, f);
    const UpInterval xr = x.range_up();
    if (xr.lower() >= 0) return x;
    if (xr.upper() <= 0) return -x;
    const double alpha = detail::secant_slope(xr, f);
    return detail::chebyshev(x, xr, f, alpha, UpInterval(0.0), f(xr), x.defined);
}

/// min: certainly ordered ranges → the smaller form (correlation kept); otherwise the identity
/// min(a, b) = (a + b − |a − b|)/2, exact in the reals.
template <int N>
Affine<N> min(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    auto f = [](const UpInterval& a, const UpInterval& b) { return min(a, b); };
    if (!detail::is_finite_form(x) || !detail::is_finite_form(y))
        return detail::binary_fallback(x, y, f);
    const UpInterval xr = x.range_up(), yr = y.range_up();
    const bool def = x.defined && y.defined;
    Affine<N> z = xr.upper() <= yr.lower()   ? x
                  : yr.upper() <= xr.lower() ? y
                                             : 0.5 * (x + y - abs(x - y));
    z.defined = def;
    return z;
}

/// max: certainly ordered ranges → the larger form; otherwise max(a, b) = (a + b + |a − b|)/2.
template <int N>
Affine<N> max(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    auto f = [](const UpInterval& a, const UpInterval& b) { return max(a, b); };
    if (!detail::is_finite_form(x) || !detail::is_finite_form(y))
        return detail::binary_fallback(x, y, f);
    const UpInterval xr = x.range_up(), yr = y.range_up();
    const bool def = x.defined && y.defined;
    Affine<N> z = xr.upper() <= yr.lower()   ? y
                  : yr.upper() <= xr.lower() ? x
                                             : 0.5 * (x + y + abs(x - y));
    z.defined = def;
    return z;
}

template <int N>
Affine<N>& operator+=(Affine<N>& a, const Affine<N>& b) {
    return a = a + b;
}
template <int N>
Affine<N>& operator-=(Affine<N>& a, const Affine<N>& b) {
    return a = a - b;
}
template <int N>
Affine<N>& operator*=(Affine<N>& a, const Affine<N>& b) {
    return a = a * b;
}
template <int N>
Affine<N>& operator/=(Affine<N>& a, const Affine<N>& b) {
    return a = a / b;
}

// ---- Fidget's further ops (issue 14): through the Interval operation on the range (and, or:
// the selected operand itself when the range of the first decides it) ---------------------------

/// floor: the Interval floor of the range (no correlation kept).
template <int N>
Affine<N> floor(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return floor(a); });
}

/// ceil: the Interval ceil of the range (no correlation kept).
template <int N>
Affine<N> ceil(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return ceil(a); });
}

/// round: the Interval round of the range (no correlation kept).
template <int N>
Affine<N> round(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return round(a); });
}

/// tan: the Interval tan of the range (no correlation kept).
template <int N>
Affine<N> tan(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return tan(a); });
}

/// asin: the Interval asin of the range (no correlation kept).
template <int N>
Affine<N> asin(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return asin(a); });
}

/// acos: the Interval acos of the range (no correlation kept).
template <int N>
Affine<N> acos(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return acos(a); });
}

/// atan: the Interval atan of the range (no correlation kept).
template <int N>
Affine<N> atan(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return atan(a); });
}

/// logic_not: the Interval logic_not of the range (no correlation kept).
template <int N>
Affine<N> logic_not(const Affine<N>& x) {
    RoundingScope scope;
    return detail::unary_fallback(x, [](const UpInterval& a) { return logic_not(a); });
}

/// atan2: the Interval atan2 of the ranges.
template <int N>
Affine<N> atan2(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    return detail::binary_fallback(
        x, y, [](const UpInterval& a, const UpInterval& b) { return atan2(a, b); });
}

/// compare: the Interval compare of the ranges.
template <int N>
Affine<N> compare(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    return detail::binary_fallback(
        x, y, [](const UpInterval& a, const UpInterval& b) { return compare(a, b); });
}

/// mod: the Interval mod of the ranges.
template <int N>
Affine<N> mod(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    return detail::binary_fallback(
        x, y, [](const UpInterval& a, const UpInterval& b) { return mod(a, b); });
}

/// logic_and: y where x ≠ 0, x where x ≡ 0 (the operand itself); undecided: the Interval logic_and.
template <int N>
Affine<N> logic_and(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    const UpInterval xr = x.range_up();
    if (!xr.is_empty() && (xr.lower() > 0 || xr.upper() < 0)) {
        Affine<N> r = y;
        r.defined = r.defined && x.defined && !r.is_empty();
        return r;
    }
    if (xr.lower() == 0 && xr.upper() == 0) {
        Affine<N> r = x;
        r.defined = r.defined && x.defined && !r.is_empty();
        return r;
    }
    return detail::binary_fallback(
        x, y, [](const UpInterval& a, const UpInterval& b) { return logic_and(a, b); });
}

/// logic_or: x where x ≠ 0, y where x ≡ 0 (the operand itself); undecided: the Interval logic_or.
template <int N>
Affine<N> logic_or(const Affine<N>& x, const Affine<N>& y) {
    RoundingScope scope;
    const UpInterval xr = x.range_up();
    if (!xr.is_empty() && (xr.lower() > 0 || xr.upper() < 0)) {
        Affine<N> r = x;
        r.defined = r.defined && x.defined && !r.is_empty();
        return r;
    }
    if (xr.lower() == 0 && xr.upper() == 0) {
        Affine<N> r = y;
        r.defined = r.defined && x.defined && !r.is_empty();
        return r;
    }
    return detail::binary_fallback(
        x, y, [](const UpInterval& a, const UpInterval& b) { return logic_or(a, b); });
}

static_assert(Enclosure<Affine<1>>);
static_assert(Enclosure<Affine<3>>);

}  // namespace certray
