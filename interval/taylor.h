// interval/taylor.h — TaylorModel<D>: a polynomial of total degree ≤ D in the offsets from a box's
// centre plus an interval remainder; one more number type of the evaluator (expr/eval.h).
//
// Contract: a model M = (P, R) built over a box B with centre c (offsets u = p − c ∈ U = B − c)
// satisfies, for every point p of B where the function f it was computed from is defined,
//     f(p) ∈ P(p − c) + R,
// and R.defined is true only if f is defined and continuous on the whole of B (Interval's
// decoration). Every operation keeps this: the terms of the exact result of degree > D are
// bounded over U (interval products of the monomial bounds) and moved into R; every coefficient
// is computed as an outward-rounded interval and replaced by a double inside it, the difference
// times the monomial's bound over U going into R. sqrt, exp, log, sin, cos and the reciprocal are
// Taylor expansions about the constant term a₀ composed in the truncated algebra, with the
// Lagrange remainder bounded by an interval enclosure of the (D+1)-th derivative over the hull of
// the argument's range and a₀; outside the function's domain (or for non-finite data) the op
// falls back to intervals (P = the midpoint of the interval result, R = the rest). abs, min, max
// pick a branch when the sign of range(a) or range(a − b) decides it, else keep the narrower of
// one branch plus a one-sided correction (max(a, b) = a + max(0, b − a) ∈ a + [0, hi(b − a)])
// and the interval result. Falling
// back only makes a model coarser; it is always sound.
//
// The domain (centre, offsets and monomial bounds) lives in a TaylorDomain<D> that the caller
// keeps alive while models that point at it are used; constants made from T(c) have none and
// binary ops take the one that is set (like interval/poly.h's `dom`).
//
// Reference: docs/theory/taylor.md; K. Makino and M. Berz, "Taylor models and other validated
// functional inclusion methods", Int. J. Pure Appl. Math. 4(4), 2003; M. Berz and G. Hoffstätter,
// "Computation and application of Taylor polynomials with interval remainder bounds", Reliable
// Computing 4, 1998.
#pragma once

#include <array>
#include <cmath>

#include "interval/interval.h"
#include "interval/number.h"
#include "interval/poly.h"

namespace certray {

namespace detail {

/// The monomials x^i y^j z^k of total degree ≤ N in graded order (degree 0, then 1, …; within a
/// degree by decreasing i then j). The list for N is a prefix of the list for any N' > N.
template <int N>
struct MonomialTable {
    static constexpr int kTerms = (N + 1) * (N + 2) * (N + 3) / 6;
    std::array<std::array<int, 3>, kTerms> e{};
    std::array<int, kTerms> degree{};

    constexpr MonomialTable() {
        int n = 0;
        for (int d = 0; d <= N; ++d)
            for (int i = d; i >= 0; --i)
                for (int j = d - i; j >= 0; --j) {
                    e[n] = {i, j, d - i - j};
                    degree[n] = d;
                    ++n;
                }
    }
    /// The index of x^i y^j z^k (its degree must be ≤ N).
    constexpr int index(int i, int j, int k) const {
        for (int n = 0; n < kTerms; ++n)
            if (e[n][0] == i && e[n][1] == j && e[n][2] == k) return n;
        return -1;
    }
};

/// For models of degree D: the index, in the degree-2D table, of the product of monomials a, b.
template <int D>
struct ProductTable {
    static constexpr int kTerms = MonomialTable<D>::kTerms;
    std::array<std::array<int, kTerms>, kTerms> index{};
    constexpr ProductTable() {
        constexpr MonomialTable<D> m;
        constexpr MonomialTable<2 * D> m2;
        for (int a = 0; a < kTerms; ++a)
            for (int b = 0; b < kTerms; ++b)
                index[a][b] =
                    m2.index(m.e[a][0] + m.e[b][0], m.e[a][1] + m.e[b][1], m.e[a][2] + m.e[b][2]);
    }
};

template <int D>
inline constexpr MonomialTable<D> kMonomials{};
template <int D>
inline constexpr ProductTable<D> kProducts{};

}  // namespace detail

/// The box a family of models lives on: centre c, offsets U = box − c (outward) and the interval
/// bounds over U of every monomial of degree ≤ 2D.
template <int D>
struct TaylorDomain {
    static constexpr int kWide = detail::MonomialTable<2 * D>::kTerms;
    /// The box B.
    std::array<Interval, 3> box;
    /// The centre c (a point of B: the midpoints).
    std::array<double, 3> c{};
    /// U ⊇ B − c, rounded outward.
    std::array<Interval, 3> u;
    /// bound[m] ⊇ {u^e_m : u ∈ U} for the monomials m of degree ≤ 2D (upward-mode intervals:
    /// operate on them only inside a RoundingScope).
    std::array<UpInterval, kWide> bound;

    /// The domain of `box` (finite, non-empty bounds), centred at its midpoint.
    explicit TaylorDomain(const std::array<Interval, 3>& b);
};

template <int D>
struct TaylorModel;

/// The univariate model of f along a ray: for t in dom (with o + t·d in the model's box),
/// f(o + t·d) ∈ p(t) + r whenever f is defined there.
struct RayModel {
    Poly<Interval> p;
    Interval r;
};

/// A polynomial of degree ≤ D in the offsets from a domain's centre plus a remainder (see the file
/// contract).
template <int D>
struct TaylorModel {
    static_assert(D >= 1 && D <= 3, "TaylorModel supports degrees 1 to 3");
    static constexpr int kTerms = detail::MonomialTable<D>::kTerms;

    /// Coefficients by monomial (graded order of detail::MonomialTable); all finite.
    std::array<double, kTerms> a{};
    /// The remainder; its decoration is the model's (f defined and continuous on the box).
    Interval r{0.0};
    /// The domain, or nullptr for a constant (then only a[0] may be non-zero).
    const TaylorDomain<D>* dom = nullptr;

    /// The constant 0.
    TaylorModel() = default;
    /// The constant v (exact); NaN or ±inf give a model with an empty or entire remainder.
    TaylorModel(double v) {  // NOLINT: implicit on purpose (the evaluator's T(c))
        if (std::isfinite(v))
            a[0] = v;
        else
            r = Interval(v);  // NaN → empty (not defined); ±inf as Interval has it
    }

    /// The coordinate `axis` (0, 1, 2) over the domain: c_axis + u_axis, exact, R = [0, 0].
    static TaylorModel variable(const TaylorDomain<D>& d, int axis);
    /// P = a point of x, R = x − P: the interval x as a model on dom (the fallback).
    static TaylorModel from_interval(const Interval& x, const TaylorDomain<D>* dom);

    /// Encloses {P(u) : u ∈ U} (the polynomial part only), by monomial bounds.
    Interval poly_range() const;
    /// Encloses f over the box (for every point where f is defined): poly_range() + R.
    Interval range() const;
    /// Whether f is proven defined and continuous on the whole box.
    bool defined() const { return r.defined; }
    /// The highest degree with a non-zero coefficient.
    int degree() const;
    /// f along o + t·d for t ∈ t_dom (see RayModel): valid where o + t·d lies in the box.
    RayModel compose_ray(const std::array<double, 3>& o, const std::array<double, 3>& d,
                         const Interval& t_dom) const;
};

/// P(o + t·d − c) + r of the coefficients a[0 … terms(D)) (graded order) about centre c, on
/// t_dom: the substitution u_i = (o_i − c_i) + t·d_i done in interval arithmetic. Used by
/// TaylorModel::compose_ray and by stored per-cell models of any degree ≤ 3.
RayModel compose_ray(const double* a, int degree, const std::array<double, 3>& c, const Interval& r,
                     const std::array<double, 3>& o, const std::array<double, 3>& d,
                     const Interval& t_dom);

// ---- arithmetic (definitions below) ------------------------------------------------------------

/// Exact sum of coefficient intervals, each replaced by a double; rounding into R.
template <int D>
TaylorModel<D> operator+(const TaylorModel<D>& a, const TaylorModel<D>& b);
/// a − b, as +.
template <int D>
TaylorModel<D> operator-(const TaylorModel<D>& a, const TaylorModel<D>& b);
/// −a (exact).
template <int D>
TaylorModel<D> operator-(const TaylorModel<D>& a);
/// Product: terms of degree > D bounded over U into R; R = Pa·Rb + Pb·Ra + Ra·Rb + rounding.
template <int D>
TaylorModel<D> operator*(const TaylorModel<D>& a, const TaylorModel<D>& b);
/// a · (1/b), the reciprocal a Taylor expansion when range(b) excludes 0, else intervals.
template <int D>
TaylorModel<D> operator/(const TaylorModel<D>& a, const TaylorModel<D>& b);
/// a · a.
template <int D>
TaylorModel<D> square(const TaylorModel<D>& a);
/// aⁿ by binary powering (a⁰ = 1 with a's decoration).
template <int D>
TaylorModel<D> pow(const TaylorModel<D>& a, unsigned n);
/// √a: Taylor when hull(range(a), a₀) > 0, else intervals (a range touching 0 falls back).
template <int D>
TaylorModel<D> sqrt(const TaylorModel<D>& a);
/// exp a: Taylor (finite range), else intervals.
template <int D>
TaylorModel<D> exp(const TaylorModel<D>& a);
/// log a: Taylor when hull(range(a), a₀) > 0, else intervals.
template <int D>
TaylorModel<D> log(const TaylorModel<D>& a);
/// sin a: Taylor (finite range), else intervals.
template <int D>
TaylorModel<D> sin(const TaylorModel<D>& a);
/// cos a: Taylor (finite range), else intervals.
template <int D>
TaylorModel<D> cos(const TaylorModel<D>& a);
/// |a|: a if range(a) ≥ 0, −a if ≤ 0, else the narrower of ±a + a one-sided correction and the
/// interval |range(a)|.
template <int D>
TaylorModel<D> abs(const TaylorModel<D>& a);
/// min: b if range(a − b) ≥ 0, a if ≤ 0, else the narrowest of a or b plus a one-sided correction
/// and the interval min.
template <int D>
TaylorModel<D> min(const TaylorModel<D>& a, const TaylorModel<D>& b);
/// max: a if range(a − b) ≥ 0, b if ≤ 0, else as min.
template <int D>
TaylorModel<D> max(const TaylorModel<D>& a, const TaylorModel<D>& b);

/// The lower bound of range() (the Enclosure concept).
template <int D>
double lower(const TaylorModel<D>& m) {
    return m.range().lower();
}
/// The upper bound of range().
template <int D>
double upper(const TaylorModel<D>& m) {
    return m.range().upper();
}
/// Whether f is proven defined and continuous on the whole box.
template <int D>
bool is_defined(const TaylorModel<D>& m) {
    return m.defined();
}

// ---- implementation ----------------------------------------------------------------------------

namespace detail {

/// Intervals inside the RoundingScope that every public operation opens.
using TmI = UpInterval;

/// Number of coefficients of a model of degree d.
constexpr int taylor_terms(int d) { return (d + 1) * (d + 2) * (d + 3) / 6; }

template <int D>
TmI tm_bound(const TaylorDomain<D>* dom, int m) {
    return m == 0 ? TmI(1.0) : dom->bound[m];
}

template <int D>
const TaylorDomain<D>* tm_dom(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    return a.dom ? a.dom : b.dom;
}

/// Σ a_m · bound_m: encloses the polynomial part over U.
template <int D>
TmI tm_poly_range(const TaylorModel<D>& x) {
    TmI s(x.a[0]);
    for (int m = 1; m < TaylorModel<D>::kTerms; ++m)
        if (x.a[m] != 0) s = s + TmI(x.a[m]) * x.dom->bound[m];
    return s;
}

/// The model of coefficient intervals C and remainder R: each coefficient replaced by a double in
/// it, (C_m − a_m)·bound_m added to R.
template <int D>
TaylorModel<D> tm_finish(const std::array<TmI, TaylorModel<D>::kTerms>& c, TmI r,
                         const TaylorDomain<D>* dom) {
    TaylorModel<D> out;
    out.dom = dom;
    for (int m = 0; m < TaylorModel<D>::kTerms; ++m) {
        const double lo = c[m].lower(), hi = c[m].upper();
        if (lo == hi && std::isfinite(lo)) {
            out.a[m] = lo;  // exact
            continue;
        }
        double mid = midpoint(c[m]);
        if (!std::isfinite(mid)) mid = 0;
        out.a[m] = mid;
        r = r + (c[m] - TmI(mid)) * tm_bound(dom, m);
    }
    out.r = Interval(r);
    return out;
}

/// The interval x as a model: a₀ a point of x, R = x − a₀.
template <int D>
TaylorModel<D> tm_from(const TmI& x, const TaylorDomain<D>* dom) {
    TaylorModel<D> out;
    out.dom = dom;
    if (x.is_empty()) {
        out.r = Interval::empty();
        return out;
    }
    double mid = midpoint(x);
    if (!std::isfinite(mid)) mid = 0;
    out.a[0] = mid;
    out.r = Interval(x - TmI(mid));
    out.r.defined = x.defined && !out.r.is_empty();
    return out;
}

template <int D>
TaylorModel<D> tm_add(const TaylorModel<D>& a, const TaylorModel<D>& b, double sign) {
    std::array<TmI, TaylorModel<D>::kTerms> c;
    for (int m = 0; m < TaylorModel<D>::kTerms; ++m) c[m] = TmI(a.a[m]) + TmI(sign * b.a[m]);
    const TmI rb(b.r);
    return tm_finish<D>(c, TmI(a.r) + (sign > 0 ? rb : -rb), tm_dom(a, b));
}

template <int D>
TaylorModel<D> tm_mul(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    constexpr int K = TaylorModel<D>::kTerms;
    const TaylorDomain<D>* dom = tm_dom(a, b);
    std::array<TmI, K> c;
    for (auto& v : c) v = TmI(0.0);
    TmI high(0.0);
    for (int i = 0; i < K; ++i) {
        if (a.a[i] == 0) continue;
        for (int j = 0; j < K; ++j) {
            if (b.a[j] == 0) continue;
            const TmI t = TmI(a.a[i]) * TmI(b.a[j]);
            const int p = kProducts<D>.index[i][j];
            if (p < K)
                c[p] = c[p] + t;
            else
                high = high + t * dom->bound[p];
        }
    }
    const TmI ra(a.r), rb(b.r);
    const TmI r = high + tm_poly_range(a) * rb + tm_poly_range(b) * ra + ra * rb;
    return tm_finish<D>(c, r, dom);
}

template <int D>
TmI tm_range(const TaylorModel<D>& x) {
    return tm_poly_range(x) + TmI(x.r);
}

/// f(x) composed in the truncated algebra from `coef`, which fills c[0 … D] with f⁽ᵏ⁾(a₀)/k! and
/// c[D+1] with an enclosure of f⁽ᴰ⁺¹⁾(J)/(D+1)! over J = hull(range(x), a₀), and returns false
/// when J is outside f's domain (then `fallback`, f in interval arithmetic, is applied to the
/// range). Lagrange: f(v) = Σ_{k≤D} c_k (v − a₀)^k + f⁽ᴰ⁺¹⁾(ξ)/(D+1)! (v − a₀)^{D+1}, ξ ∈ J.
template <int D, class Coef, class Fallback>
TaylorModel<D> tm_unary(const TaylorModel<D>& x, Coef coef, Fallback fallback) {
    const TmI range = tm_range(x);
    const double a0 = x.a[0];
    if (range.is_empty() || !std::isfinite(range.lower()) || !std::isfinite(range.upper()))
        return tm_from<D>(fallback(range), x.dom);
    const TmI j = hull(range, TmI(a0));
    std::array<TmI, D + 2> c;
    if (!coef(a0, j, c)) return tm_from<D>(fallback(range), x.dom);
    for (const TmI& v : c)
        if (v.is_empty() || !std::isfinite(v.lower()) || !std::isfinite(v.upper()))
            return tm_from<D>(fallback(range), x.dom);
    TaylorModel<D> h = x;
    h.a[0] = 0;
    TaylorModel<D> s = tm_from<D>(c[D], x.dom);
    for (int k = D - 1; k >= 0; --k) s = tm_add(tm_mul(s, h), tm_from<D>(c[k], x.dom), 1.0);
    const TmI lagrange = c[D + 1] * pow(tm_range(h), static_cast<unsigned>(D + 1));
    const bool def = s.r.defined && x.r.defined;
    s.r = Interval(TmI(s.r) + lagrange);
    s.r.defined = def && !s.r.is_empty();
    return s;
}

/// C(1/2, k) = (1/2)(1/2 − 1)⋯(1/2 − k + 1)/k! for k ≤ 4 (exact dyadics): 1, 1/2, −1/8, 1/16,
/// −5/128. √(x + h) = √x · Σ C(1/2, k) (h/x)ᵏ; the last one is the Lagrange coefficient at D = 3.
inline constexpr double kSqrtBinomial[] = {1.0, 0.5, -0.125, 0.0625, -0.0390625};

/// 1/k! for k ≤ 5, as an interval.
inline TmI inv_factorial(int k) {
    static constexpr double kFact[] = {1, 1, 2, 6, 24, 120};
    return TmI(1.0) / TmI(kFact[k]);
}

}  // namespace detail

template <int D>
TaylorDomain<D>::TaylorDomain(const std::array<Interval, 3>& b) : box(b) {
    for (int i = 0; i < 3; ++i) {
        c[i] = midpoint(b[i]);
        u[i] = b[i] - Interval(c[i]);
    }
    RoundingScope scope;
    std::array<std::array<UpInterval, 2 * D + 1>, 3> pw;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k <= 2 * D; ++k) pw[i][k] = pow(UpInterval(u[i]), static_cast<unsigned>(k));
    constexpr auto& mono = detail::kMonomials<2 * D>;
    for (int m = 0; m < kWide; ++m)
        bound[m] = pw[0][mono.e[m][0]] * pw[1][mono.e[m][1]] * pw[2][mono.e[m][2]];
}

template <int D>
TaylorModel<D> TaylorModel<D>::variable(const TaylorDomain<D>& d, int axis) {
    TaylorModel m;
    m.dom = &d;
    m.a[0] = d.c[axis];
    m.a[1 + axis] = 1.0;  // graded order: x, y, z are monomials 1, 2, 3
    return m;
}

template <int D>
TaylorModel<D> TaylorModel<D>::from_interval(const Interval& x, const TaylorDomain<D>* dom) {
    RoundingScope scope;
    return detail::tm_from<D>(UpInterval(x), dom);
}

template <int D>
Interval TaylorModel<D>::poly_range() const {
    RoundingScope scope;
    return Interval(detail::tm_poly_range(*this));
}

template <int D>
Interval TaylorModel<D>::range() const {
    RoundingScope scope;
    return Interval(detail::tm_range(*this));
}

template <int D>
int TaylorModel<D>::degree() const {
    int d = 0;
    for (int m = 0; m < kTerms; ++m)
        if (a[m] != 0 && detail::kMonomials<D>.degree[m] > d) d = detail::kMonomials<D>.degree[m];
    return d;
}

namespace detail {

/// A polynomial in t of degree ≤ 3 with upward-mode interval coefficients.
struct TPoly {
    std::array<TmI, 4> c;
    int degree = 0;
    bool zero = true;  ///< all coefficients exactly 0
};

/// p · (q0 + q1·t) (degree + 1), or p + v (v a double) — inside a RoundingScope.
inline TPoly tpoly_mul_lin(const TPoly& p, const TmI& q0, const TmI& q1) {
    if (p.zero) return p;
    TPoly r;
    r.zero = false;
    r.degree = p.degree + 1;
    for (int j = 0; j <= r.degree; ++j) {
        TmI v = j <= p.degree ? p.c[j] * q0 : TmI(0.0);
        if (j > 0) v = v + p.c[j - 1] * q1;
        r.c[j] = v;
    }
    return r;
}
inline TPoly tpoly_add(const TPoly& p, const TPoly& q) {
    if (p.zero) return q;
    if (q.zero) return p;
    TPoly r;
    r.zero = false;
    r.degree = p.degree > q.degree ? p.degree : q.degree;
    for (int j = 0; j <= r.degree; ++j)
        r.c[j] = (j <= p.degree ? p.c[j] : TmI(0.0)) + (j <= q.degree ? q.c[j] : TmI(0.0));
    return r;
}
inline TPoly tpoly_const(double v) {
    TPoly r;
    r.c[0] = TmI(v);
    r.zero = v == 0;
    return r;
}

/// The index in the graded degree-3 table of x^i y^j z^k (i + j + k ≤ 3).
struct Index3 {
    std::array<std::array<std::array<int, 4>, 4>, 4> m{};
    constexpr Index3() {
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                for (int k = 0; k < 4; ++k) m[i][j][k] = kMonomials<3>.index(i, j, k);
    }
};
inline constexpr Index3 kIndex3{};

}  // namespace detail

inline RayModel compose_ray(const double* a, int degree, const std::array<double, 3>& c,
                            const Interval& r, const std::array<double, 3>& o,
                            const std::array<double, 3>& d, const Interval& t_dom) {
    using detail::TmI;
    using detail::TPoly;
    RayModel out;
    out.r = r;
    out.p.valid = true;
    out.p.has_dom = true;
    out.p.dom = t_dom;
    TPoly p;
    {
        RoundingScope scope;
        // u_i(t) = q0_i + q1_i·t with q0 = o − c enclosed and q1 = d exact; P(u(t)) by nested
        // Horner schemes in x, then y, then z, each step a product by a linear polynomial in t.
        std::array<TmI, 3> q0, q1;
        for (int i = 0; i < 3; ++i) {
            q0[i] = TmI(o[i]) - TmI(c[i]);
            q1[i] = TmI(d[i]);
        }
        const int terms = detail::taylor_terms(degree);
        auto coef = [&](int i, int j, int k) {
            const int m = detail::kIndex3.m[i][j][k];
            return m < terms ? a[m] : 0.0;
        };
        p = detail::tpoly_const(0.0);
        for (int i = degree; i >= 0; --i) {
            TPoly q = detail::tpoly_const(0.0);
            for (int j = degree - i; j >= 0; --j) {
                const int n = degree - i - j;
                TPoly rz = detail::tpoly_const(coef(i, j, n));
                for (int k = n - 1; k >= 0; --k)
                    rz = detail::tpoly_add(detail::tpoly_mul_lin(rz, q0[2], q1[2]),
                                           detail::tpoly_const(coef(i, j, k)));
                q = detail::tpoly_add(detail::tpoly_mul_lin(q, q0[1], q1[1]), rz);
            }
            p = detail::tpoly_add(detail::tpoly_mul_lin(p, q0[0], q1[0]), q);
        }
    }
    out.p.degree = p.zero ? 0 : p.degree;
    if (!p.zero)
        for (int j = 0; j <= p.degree; ++j) out.p.c[j] = Interval(p.c[j]);
    return out;
}

template <int D>
RayModel TaylorModel<D>::compose_ray(const std::array<double, 3>& o, const std::array<double, 3>& d,
                                     const Interval& t_dom) const {
    if (!dom) {
        RayModel out;
        out.r = r;
        out.p.valid = true;
        out.p.has_dom = true;
        out.p.dom = t_dom;
        out.p.c[0] = Interval(a[0]);
        return out;
    }
    return certray::compose_ray(a.data(), degree(), dom->c, r, o, d, t_dom);
}

template <int D>
TaylorModel<D> operator+(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_add(a, b, 1.0);
}
template <int D>
TaylorModel<D> operator-(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_add(a, b, -1.0);
}
template <int D>
TaylorModel<D> operator-(const TaylorModel<D>& a) {
    TaylorModel<D> r = a;
    for (double& v : r.a) v = -v;
    r.r = -a.r;
    return r;
}
template <int D>
TaylorModel<D> operator*(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_mul(a, b);
}
template <int D>
TaylorModel<D> square(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_mul(a, a);
}
template <int D>
TaylorModel<D> pow(const TaylorModel<D>& a, unsigned n) {
    if (n == 0) {
        TaylorModel<D> one(1.0);
        one.dom = a.dom;
        if (a.r.is_empty()) one.r = Interval::empty();
        one.r.defined = a.r.defined;
        return one;
    }
    RoundingScope scope;
    TaylorModel<D> result, base = a;
    bool first = true;
    for (unsigned e = n;;) {
        if (e & 1u) {
            result = first ? base : detail::tm_mul(result, base);
            first = false;
        }
        e >>= 1u;
        if (!e) break;
        base = detail::tm_mul(base, base);
    }
    return result;
}

// Derivative tables: d^k/dx^k of each function at a point, /k!, as intervals.
//   exp: exp(x)/k!                  log: (−1)^{k−1} / (k xᵏ), k ≥ 1
//   √:  C(1/2, k) √x / xᵏ           1/x: (−1)ᵏ / x^{k+1}
//   sin: sin, cos, −sin, −cos (k mod 4) / k!     cos: cos, −sin, −cos, sin (k mod 4) / k!

template <int D>
TaylorModel<D> exp(const TaylorModel<D>& a) {
    using detail::TmI;
    RoundingScope scope;
    return detail::tm_unary<D>(
        a,
        [](double a0, const TmI& j, std::array<TmI, D + 2>& c) {
            const TmI e = exp(TmI(a0));
            for (int k = 0; k <= D; ++k) c[k] = e * detail::inv_factorial(k);
            c[D + 1] = exp(j) * detail::inv_factorial(D + 1);
            return true;
        },
        [](const TmI& x) { return exp(x); });
}

template <int D>
TaylorModel<D> log(const TaylorModel<D>& a) {
    using detail::TmI;
    RoundingScope scope;
    return detail::tm_unary<D>(
        a,
        [](double a0, const TmI& j, std::array<TmI, D + 2>& c) {
            if (!(j.lower() > 0)) return false;
            const TmI x(a0);
            c[0] = log(x);
            for (int k = 1; k <= D + 1; ++k) {
                const TmI& at = k <= D ? x : j;
                c[k] = TmI(k % 2 ? 1.0 : -1.0) /
                       (TmI(static_cast<double>(k)) * pow(at, static_cast<unsigned>(k)));
            }
            return true;
        },
        [](const TmI& x) { return log(x); });
}

template <int D>
TaylorModel<D> sqrt(const TaylorModel<D>& a) {
    using detail::TmI;
    RoundingScope scope;
    return detail::tm_unary<D>(
        a,
        [](double a0, const TmI& j, std::array<TmI, D + 2>& c) {
            if (!(j.lower() > 0)) return false;
            const TmI x(a0);
            for (int k = 0; k <= D + 1; ++k) {
                const TmI& at = k <= D ? x : j;
                c[k] = TmI(detail::kSqrtBinomial[k]) * sqrt(at) / pow(at, static_cast<unsigned>(k));
            }
            return true;
        },
        [](const TmI& x) { return sqrt(x); });
}

template <int D>
TaylorModel<D> sin(const TaylorModel<D>& a) {
    using detail::TmI;
    RoundingScope scope;
    return detail::tm_unary<D>(
        a,
        [](double a0, const TmI& j, std::array<TmI, D + 2>& c) {
            for (int k = 0; k <= D + 1; ++k) {
                const TmI at = k <= D ? TmI(a0) : j;
                const TmI v = (k % 2 == 0) ? sin(at) : cos(at);
                c[k] = ((k % 4) >= 2 ? -v : v) * detail::inv_factorial(k);
            }
            return true;
        },
        [](const TmI& x) { return sin(x); });
}

template <int D>
TaylorModel<D> cos(const TaylorModel<D>& a) {
    using detail::TmI;
    RoundingScope scope;
    return detail::tm_unary<D>(
        a,
        [](double a0, const TmI& j, std::array<TmI, D + 2>& c) {
            for (int k = 0; k <= D + 1; ++k) {
                const TmI at = k <= D ? TmI(a0) : j;
                const TmI v = (k % 2 == 0) ? cos(at) : sin(at);
                c[k] = (k % 4 == 1 || k % 4 == 2 ? -v : v) * detail::inv_factorial(k);
            }
            return true;
        },
        [](const TmI& x) { return cos(x); });
}

template <int D>
TaylorModel<D> operator/(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    using detail::TmI;
    RoundingScope scope;
    if (!b.dom && b.a[0] != 0 && b.r.lower() == 0 && b.r.upper() == 0) {
        // Division by an exact non-zero constant: a · (1/b) with 1/b enclosed.
        const TaylorModel<D> inv = detail::tm_from<D>(TmI(1.0) / TmI(b.a[0]), nullptr);
        TaylorModel<D> q = detail::tm_mul(a, inv);
        q.r.defined = q.r.defined && b.r.defined && !q.r.is_empty();
        return q;
    }
    const TaylorModel<D> inv = detail::tm_unary<D>(
        b,
        [](double a0, const TmI& j, std::array<TmI, D + 2>& c) {
            if (!(j.lower() > 0 || j.upper() < 0)) return false;
            const TmI x(a0);
            for (int k = 0; k <= D + 1; ++k) {
                const TmI& at = k <= D ? x : j;
                c[k] = TmI(k % 2 ? -1.0 : 1.0) / pow(at, static_cast<unsigned>(k + 1));
            }
            return true;
        },
        [](const TmI& x) { return TmI(1.0) / x; });
    if (inv.r.is_empty() || a.r.is_empty()) {
        TaylorModel<D> e;
        e.dom = detail::tm_dom(a, b);
        e.r = Interval::empty();
        return e;
    }
    TaylorModel<D> q = detail::tm_mul(a, inv);
    q.r.defined = q.r.defined && a.r.defined && inv.r.defined && !q.r.is_empty();
    return q;
}

template <int D>
TaylorModel<D> abs(const TaylorModel<D>& a) {
    using detail::TmI;
    RoundingScope scope;
    const TmI range = detail::tm_range(a);
    if (!range.is_empty() && range.lower() >= 0) return a;
    if (!range.is_empty() && range.upper() <= 0) return -a;
    // Undecided: |a| = a + 2·max(0, −a) ∈ a + [0, −2·lo] and |a| = −a + 2·max(0, a) ∈
    // −a + [0, 2·hi]; the narrower of these and the interval |range|.
    TaylorModel<D> best = detail::tm_from<D>(abs(range), a.dom);
    if (!range.is_empty() && std::isfinite(range.lower()) && std::isfinite(range.upper())) {
        const bool pos = -range.lower() <= range.upper();  // the smaller correction
        TaylorModel<D> m = pos ? a : -a;
        const TmI extra = TmI(2.0) * (pos ? TmI(0.0, -range.lower()) : TmI(0.0, range.upper()));
        const bool def = a.r.defined;
        m.r = Interval(TmI(m.r) + extra);
        m.r.defined = def && !m.r.is_empty();
        if (width(m.r) < width(best.r)) best = m;
    }
    return best;
}

namespace detail {
/// min (want_min) or max of a and b: a branch when range(a − b) decides it; otherwise the
/// narrowest of max(a, b) = a + max(0, b − a) ∈ a + [0, hi(b − a)] (and with a, b swapped;
/// min(a, b) = a − max(0, a − b) ∈ a + [lo(b − a), 0]) and the interval result.
template <int D>
TaylorModel<D> tm_minmax(const TaylorModel<D>& a, const TaylorModel<D>& b, bool want_min) {
    RoundingScope scope;
    const TmI ra = tm_range(a), rb = tm_range(b);
    const TaylorDomain<D>* dom = tm_dom(a, b);
    TaylorModel<D> best = tm_from<D>(want_min ? min(ra, rb) : max(ra, rb), dom);
    if (ra.is_empty() || rb.is_empty()) return best;
    const bool def = a.r.defined && b.r.defined;
    const TmI diff = tm_range(tm_add(a, b, -1.0));  // a − b
    if (diff.is_empty()) return best;
    int pick = 0;  // +1: a, −1: b
    if (diff.lower() >= 0) pick = want_min ? -1 : 1;
    if (diff.upper() <= 0) pick = want_min ? 1 : -1;
    if (pick != 0) {
        TaylorModel<D> r = pick > 0 ? a : b;
        r.dom = dom;
        r.r.defined = def && !r.r.is_empty();
        return r;
    }
    if (!std::isfinite(diff.lower()) || !std::isfinite(diff.upper())) return best;
    // With d = a − b ∈ [lo, hi], lo < 0 < hi:
    //   max = a + max(0, −d) ∈ a + [0, −lo]      max = b + max(0, d) ∈ b + [0, hi]
    //   min = a − max(0, d) ∈ a + [−hi, 0]       min = b − max(0, −d) ∈ b + [lo, 0]
    for (int side = 0; side < 2; ++side) {
        TaylorModel<D> m = side == 0 ? a : b;
        m.dom = dom;
        TmI extra;
        if (want_min)
            extra = side == 0 ? TmI(-diff.upper(), 0.0) : TmI(diff.lower(), 0.0);
        else
            extra = side == 0 ? TmI(0.0, -diff.lower()) : TmI(0.0, diff.upper());
        m.r = Interval(TmI(m.r) + extra);
        m.r.defined = def && !m.r.is_empty();
        if (width(m.r) < width(best.r)) best = m;
    }
    return best;
}
}  // namespace detail

template <int D>
TaylorModel<D> min(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    return detail::tm_minmax(a, b, true);
}
template <int D>
TaylorModel<D> max(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    return detail::tm_minmax(a, b, false);
}

// ---- Fidget's further ops (issue 14): the Interval operation on the range, as a model with a
// constant polynomial part (no Taylor expansion)
// ---------------------------------------------------

/// floor: the Interval floor of the range.
template <int D>
TaylorModel<D> floor(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(floor(detail::tm_range(a)), a.dom);
}

/// ceil: the Interval ceil of the range.
template <int D>
TaylorModel<D> ceil(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(ceil(detail::tm_range(a)), a.dom);
}

/// round: the Interval round of the range.
template <int D>
TaylorModel<D> round(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(round(detail::tm_range(a)), a.dom);
}

/// tan: the Interval tan of the range.
template <int D>
TaylorModel<D> tan(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(tan(detail::tm_range(a)), a.dom);
}

/// asin: the Interval asin of the range.
template <int D>
TaylorModel<D> asin(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(asin(detail::tm_range(a)), a.dom);
}

/// acos: the Interval acos of the range.
template <int D>
TaylorModel<D> acos(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(acos(detail::tm_range(a)), a.dom);
}

/// atan: the Interval atan of the range.
template <int D>
TaylorModel<D> atan(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(atan(detail::tm_range(a)), a.dom);
}

/// logic_not: the Interval logic_not of the range.
template <int D>
TaylorModel<D> logic_not(const TaylorModel<D>& a) {
    RoundingScope scope;
    return detail::tm_from<D>(logic_not(detail::tm_range(a)), a.dom);
}

/// atan2: the Interval atan2 of the ranges.
template <int D>
TaylorModel<D> atan2(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_from<D>(atan2(detail::tm_range(a), detail::tm_range(b)),
                              detail::tm_dom(a, b));
}

/// compare: the Interval compare of the ranges.
template <int D>
TaylorModel<D> compare(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_from<D>(compare(detail::tm_range(a), detail::tm_range(b)),
                              detail::tm_dom(a, b));
}

/// mod: the Interval mod of the ranges.
template <int D>
TaylorModel<D> mod(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_from<D>(mod(detail::tm_range(a), detail::tm_range(b)), detail::tm_dom(a, b));
}

/// logic_and: the Interval logic_and of the ranges.
template <int D>
TaylorModel<D> logic_and(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_from<D>(logic_and(detail::tm_range(a), detail::tm_range(b)),
                              detail::tm_dom(a, b));
}

/// logic_or: the Interval logic_or of the ranges.
template <int D>
TaylorModel<D> logic_or(const TaylorModel<D>& a, const TaylorModel<D>& b) {
    RoundingScope scope;
    return detail::tm_from<D>(logic_or(detail::tm_range(a), detail::tm_range(b)),
                              detail::tm_dom(a, b));
}

}  // namespace certray
