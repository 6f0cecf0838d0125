// tests/interval/affine_test.cpp — Affine<N>: containment of exact MPFR values at corresponding
// points, the correlation it keeps (x − x, (x+1)(x−1) − x²), decorations, extreme magnitudes.
//
// A point of a form is x0 + Σ x_i ε_i + err·t for chosen ε_i, t ∈ [−1, 1]; it is built exactly in
// MPFR (kPointBits suffice for any sum of doubles and products of two doubles), and the exact
// value of the expression there is enclosed by `Big`, an MPFR interval with RNDD/RNDU bounds.
// Runs are reproducible with RC_PARAMS="seed=N".
#include "interval/affine.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include "tests/support/generators.h"

namespace certray {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Exponents of the terms span at most 2^1026 … 2^−2148: 3400 bits hold every point exactly.
constexpr mpfr_prec_t kPointBits = 3400;
/// Work per RapidCheck case (ctest runs 2000 cases per property through RC_PARAMS).
constexpr int kBoxesPerCase = 2;
constexpr int kPointsPerBox = 4;
/// Precision of transcendental values (twice the MPFR oracle's 256 bits).
constexpr mpfr_prec_t kValueBits = 512;

using A1 = Affine<1>;
/// Values of the primary symbols (non-deduced, so that N comes from the Affine<N> argument).
template <int N>
using Symbols = std::type_identity_t<std::array<double, N>>;
using A2 = Affine<2>;
using A3 = Affine<3>;

/// An MPFR interval [lo ↓, hi ↑]; `valid` is false once an operation left its domain.
struct Big {
    mpfr_t lo, hi;
    bool valid = true;
    /// False once a value was replaced by a coarse enclosure: such points are not checked.
    bool sharp = true;

    Big(double v) {  // NOLINT: implicit, so that expressions mix doubles
        mpfr_init2(lo, kPointBits);
        mpfr_init2(hi, kPointBits);
        mpfr_set_d(lo, v, MPFR_RNDD);
        mpfr_set_d(hi, v, MPFR_RNDU);
    }
    Big(const Big& o) : valid(o.valid), sharp(o.sharp) {
        mpfr_init2(lo, kPointBits);
        mpfr_init2(hi, kPointBits);
        mpfr_set(lo, o.lo, MPFR_RNDD);
        mpfr_set(hi, o.hi, MPFR_RNDU);
    }
    Big& operator=(const Big& o) {
        mpfr_set(lo, o.lo, MPFR_RNDD);
        mpfr_set(hi, o.hi, MPFR_RNDU);
        valid = o.valid;
        sharp = o.sharp;
        return *this;
    }
    ~Big() {
        mpfr_clear(lo);
        mpfr_clear(hi);
    }
};

/// The exact point x0 + Σ c_i ε_i + err·t.
template <int N>
Big point_of(const Affine<N>& x, const Symbols<N>& eps, double t) {
    Big p(x.x0);
    mpfr_t term;
    mpfr_init2(term, kPointBits);
    for (int i = 0; i < N; ++i) {
        mpfr_set_d(term, x.xi[i], MPFR_RNDN);
        mpfr_mul_d(term, term, eps[i], MPFR_RNDN);  // exact
        mpfr_add(p.lo, p.lo, term, MPFR_RNDD);      // exact at kPointBits
        mpfr_add(p.hi, p.hi, term, MPFR_RNDU);
    }
    mpfr_set_d(term, x.err, MPFR_RNDN);
    mpfr_mul_d(term, term, t, MPFR_RNDN);
    mpfr_add(p.lo, p.lo, term, MPFR_RNDD);
    mpfr_add(p.hi, p.hi, term, MPFR_RNDU);
    mpfr_clear(term);
    return p;
}

Big operator+(const Big& a, const Big& b) {
    Big r(a);
    mpfr_add(r.lo, a.lo, b.lo, MPFR_RNDD);
    mpfr_add(r.hi, a.hi, b.hi, MPFR_RNDU);
    r.valid = a.valid && b.valid;
    r.sharp = a.sharp && b.sharp;
    return r;
}
Big operator-(const Big& a) {
    Big r(a);
    mpfr_neg(r.lo, a.hi, MPFR_RNDD);
    mpfr_neg(r.hi, a.lo, MPFR_RNDU);
    return r;
}
Big operator-(const Big& a, const Big& b) { return a + (-b); }
Big operator*(const Big& a, const Big& b) {
    Big r(a);
    r.valid = a.valid && b.valid;
    r.sharp = a.sharp && b.sharp;
    mpfr_t c;
    mpfr_init2(c, kPointBits);
    bool first = true;
    for (mpfr_srcptr u : {a.lo, a.hi}) {
        for (mpfr_srcptr v : {b.lo, b.hi}) {
            mpfr_mul(c, u, v, MPFR_RNDD);
            if (first || mpfr_less_p(c, r.lo)) mpfr_set(r.lo, c, MPFR_RNDD);
            mpfr_mul(c, u, v, MPFR_RNDU);
            if (first || mpfr_greater_p(c, r.hi)) mpfr_set(r.hi, c, MPFR_RNDU);
            first = false;
        }
    }
    mpfr_clear(c);
    return r;
}
Big abs(const Big& a) {
    if (mpfr_sgn(a.lo) >= 0) return a;
    if (mpfr_sgn(a.hi) <= 0) return -a;
    Big r(a);
    mpfr_set_zero(r.lo, 1);
    mpfr_neg(r.hi, a.lo, MPFR_RNDU);
    mpfr_max(r.hi, r.hi, a.hi, MPFR_RNDU);
    return r;
}
Big square(const Big& a) { return abs(a) * abs(a); }
/// dst = f(src) rounded in direction `rnd` to kValueBits (cheaper than kPointBits, still exact
/// enough: the bound is then stored exactly).
template <class F>
void rounded(F f, mpfr_ptr dst, mpfr_srcptr src, mpfr_rnd_t rnd) {
    mpfr_t t;
    mpfr_init2(t, kValueBits);
    f(t, src, rnd);
    mpfr_set(dst, t, rnd);
    mpfr_clear(t);
}
/// Increasing f on the domain lo > bound (or ≥ when closed): [f(lo) ↓, f(hi) ↑].
template <class F>
Big increasing(const Big& a, F f, bool valid) {
    Big r(a);
    r.valid = a.valid && valid;
    if (!r.valid) return r;
    rounded(f, r.lo, a.lo, MPFR_RNDD);
    rounded(f, r.hi, a.hi, MPFR_RNDU);
    return r;
}
Big sqrt(const Big& a) { return increasing(a, mpfr_sqrt, mpfr_sgn(a.lo) >= 0); }
Big exp(const Big& a) { return increasing(a, mpfr_exp, true); }
Big log(const Big& a) { return increasing(a, mpfr_log, mpfr_sgn(a.lo) > 0); }
Big pow(const Big& a, unsigned n) {
    const Big b = n % 2 == 0 ? abs(a) : a;
    Big r(b);
    mpfr_pow_ui(r.lo, b.lo, n, MPFR_RNDD);
    mpfr_pow_ui(r.hi, b.hi, n, MPFR_RNDU);
    return r;
}
Big operator/(const Big& a, const Big& b) {
    Big q(b);
    if (mpfr_sgn(b.lo) <= 0 && mpfr_sgn(b.hi) >= 0) {
        q.valid = false;
        return q;
    }
    mpfr_ui_div(q.lo, 1, b.hi, MPFR_RNDD);
    mpfr_ui_div(q.hi, 1, b.lo, MPFR_RNDU);
    return a * q;
}
/// sin, cos are 1-Lipschitz: f(lo) ± (hi − lo); beyond the doubles, [−1, 1] (MPFR's argument
/// reduction would need as many bits as the exponent).
template <class F>
Big lipschitz(const Big& a, F f) {
    Big r(a);
    if (mpfr_get_exp(a.lo) > 1100 || mpfr_get_exp(a.hi) > 1100 || !mpfr_number_p(a.lo) ||
        !mpfr_number_p(a.hi)) {
        mpfr_set_si(r.lo, -1, MPFR_RNDD);
        mpfr_set_si(r.hi, 1, MPFR_RNDU);
        r.sharp = false;
        return r;
    }
    mpfr_t w;
    mpfr_init2(w, kPointBits);
    mpfr_sub(w, a.hi, a.lo, MPFR_RNDU);
    if (mpfr_cmp_d(w, 0x1p-60) > 0) r.sharp = false;  // too coarse to check anything against
    rounded(f, r.lo, a.lo, MPFR_RNDD);
    rounded(f, r.hi, a.lo, MPFR_RNDU);
    mpfr_sub(r.lo, r.lo, w, MPFR_RNDD);
    mpfr_add(r.hi, r.hi, w, MPFR_RNDU);
    if (mpfr_cmp_si(r.lo, -1) < 0) mpfr_set_si(r.lo, -1, MPFR_RNDD);
    if (mpfr_cmp_si(r.hi, 1) > 0) mpfr_set_si(r.hi, 1, MPFR_RNDU);
    mpfr_clear(w);
    return r;
}
Big sin(const Big& a) { return lipschitz(a, mpfr_sin); }
Big cos(const Big& a) { return lipschitz(a, mpfr_cos); }
Big min(const Big& a, const Big& b) {
    Big r(a);
    mpfr_min(r.lo, a.lo, b.lo, MPFR_RNDD);
    mpfr_min(r.hi, a.hi, b.hi, MPFR_RNDU);
    r.valid = a.valid && b.valid;
    r.sharp = a.sharp && b.sharp;
    return r;
}
Big max(const Big& a, const Big& b) { return -min(-a, -b); }

/// The real values of `v` lie in `r` (compared exactly); true for a coarse `v`.
bool inside(const Interval& r, const Big& v) {
    if (!v.sharp) return true;
    if (r.is_empty()) return false;
    return mpfr_cmp_d(v.lo, r.lower()) >= 0 && mpfr_cmp_d(v.hi, r.upper()) <= 0;
}

std::string show(const Interval& r) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "[%.17g, %.17g]", r.lower(), r.upper());
    return buf;
}

/// ε ∈ [−1, 1], favouring −1, 0, 1.
rc::Gen<double> gen_eps() {
    return rc::gen::weightedOneOf<double>(
        {{1, rc::gen::just(-1.0)},
         {1, rc::gen::just(1.0)},
         {1, rc::gen::just(0.0)},
         {6, rc::gen::map(rc::gen::inRange<std::int64_t>(-(1 << 30), (1 << 30) + 1),
                          [](std::int64_t k) { return std::ldexp(double(k), -30); })}});
}

/// A random value of the form x for the symbols `eps` (and a random t for its error term); a
/// random point of the box when x is unbounded (its primary coefficients are then 0).
template <int N>
Big gen_value(const Affine<N>& x, const Interval& box, const Symbols<N>& eps) {
    if (detail::is_finite_form(x)) return point_of<N>(x, eps, *gen_eps());
    return Big(*testing::gen_point_in(box.lower(), box.upper()));
}

template <int N>
std::array<double, N> gen_symbols() {
    std::array<double, N> eps;
    for (double& e : eps) e = *gen_eps();
    return eps;
}

/// The AF1 contract at one assignment of the primary symbols: v ∈ z0 + Σ z_i ε_i ± err.
template <int N>
bool pointwise(const Affine<N>& z, const Symbols<N>& eps, const Big& v) {
    if (!v.sharp) return true;
    if (z.is_empty()) return false;
    const Big lo = point_of<N>(z, eps, -1.0), hi = point_of<N>(z, eps, 1.0);
    return mpfr_lessequal_p(lo.lo, v.lo) && mpfr_lessequal_p(v.hi, hi.hi);
}

/// op(x̂) for x̂ = variable(box): at kPointsPerBox random values of x̂, for kBoxesPerCase random
/// boxes, the exact value lies in to_interval() and in the result form at the same symbols.
template <class Op>
void check_unary(Op op) {
    for (int k = 0; k < kBoxesPerCase; ++k) {
        const auto [lo, hi] = *testing::gen_bounds();
        const Interval box(lo, hi);
        const A1 x = A1::variable(box, 0);
        RC_ASSERT(contains(x.to_interval(), box));
        const A1 z = op(x);
        const Interval r = z.to_interval();
        for (int j = 0; j < kPointsPerBox; ++j) {
            const auto eps = gen_symbols<1>();
            const Big v = op(gen_value(x, box, eps));
            if (!v.valid) continue;
            if (!inside(r, v) || !pointwise(z, eps, v)) {
                RC_FAIL("box " + show(box) + " result " + show(r) + " eps " +
                        std::to_string(eps[0]));
            }
        }
    }
}

template <class Op>
void check_binary(Op op) {
    for (int k = 0; k < kBoxesPerCase; ++k) {
        const auto [alo, ahi] = *testing::gen_bounds();
        const auto [blo, bhi] = *testing::gen_bounds();
        const Interval a(alo, ahi), b(blo, bhi);
        const A2 x = A2::variable(a, 0), y = A2::variable(b, 1);
        const A2 z = op(x, y);
        const Interval r = z.to_interval();
        for (int j = 0; j < kPointsPerBox; ++j) {
            const auto eps = gen_symbols<2>();
            const Big v = op(gen_value(x, a, eps), gen_value(y, b, eps));
            if (!v.valid) continue;
            if (!inside(r, v) || !pointwise(z, eps, v)) {
                RC_FAIL("boxes " + show(a) + " " + show(b) + " result " + show(r));
            }
        }
    }
}

#define CERTRAY_AFFINE_UNARY(name, expr)                 \
    RC_GTEST_PROP(AffineContains, name, ()) {            \
        check_unary([](const auto& x) { return expr; }); \
    }
#define CERTRAY_AFFINE_BINARY(name, expr)                                \
    RC_GTEST_PROP(AffineContains, name, ()) {                            \
        check_binary([](const auto& x, const auto& y) { return expr; }); \
    }

CERTRAY_AFFINE_UNARY(Neg, -x)
CERTRAY_AFFINE_UNARY(Scale, x * 3.0)
CERTRAY_AFFINE_UNARY(ScaleTiny, x * 1e-300)
CERTRAY_AFFINE_UNARY(AddConstant, x + 0.1)
CERTRAY_AFFINE_UNARY(Abs, abs(x))
CERTRAY_AFFINE_UNARY(AbsShifted, abs(x - 0.5))
CERTRAY_AFFINE_UNARY(Square, square(x))
CERTRAY_AFFINE_UNARY(Pow3, pow(x, 3u))
CERTRAY_AFFINE_UNARY(Pow4, pow(x, 4u))
CERTRAY_AFFINE_UNARY(Pow7, pow(x, 7u))
CERTRAY_AFFINE_UNARY(Sqrt, sqrt(x))
CERTRAY_AFFINE_UNARY(Exp, exp(x))
CERTRAY_AFFINE_UNARY(Log, log(x))
CERTRAY_AFFINE_UNARY(Sin, sin(x))
CERTRAY_AFFINE_UNARY(Cos, cos(x))
CERTRAY_AFFINE_UNARY(Reciprocal, 1.0 / x)
// Correlated: the same symbol twice.
CERTRAY_AFFINE_UNARY(SelfSub, x - x)
CERTRAY_AFFINE_UNARY(SelfMul, x* x)
CERTRAY_AFFINE_UNARY(SelfDiv, x / (x * x + 1.0))
CERTRAY_AFFINE_UNARY(SelfMin, min(x, 1.0 - x))
CERTRAY_AFFINE_UNARY(SelfMax, max(x * 0.5, x - 1.0))
CERTRAY_AFFINE_UNARY(DiffOfSquares, (x + 1.0) * (x - 1.0) - square(x))
// Compositions: errors from one nonlinear step feed the next.
CERTRAY_AFFINE_UNARY(SqrtOfSquarePlusOne, sqrt(square(x) + 1.0))
CERTRAY_AFFINE_UNARY(LogOfExp, log(exp(x) + 0.5))
CERTRAY_AFFINE_UNARY(SinOfCos, sin(cos(x) * 2.0) - x)
CERTRAY_AFFINE_UNARY(ExpOfSin, exp(sin(x)) * abs(x))

CERTRAY_AFFINE_BINARY(Add, x + y)
CERTRAY_AFFINE_BINARY(Sub, x - y)
CERTRAY_AFFINE_BINARY(Mul, x* y)
CERTRAY_AFFINE_BINARY(Div, x / y)
CERTRAY_AFFINE_BINARY(Min, min(x, y))
CERTRAY_AFFINE_BINARY(Max, max(x, y))
CERTRAY_AFFINE_BINARY(Mixed, x* y - square(x) + y / (abs(x) + 1.0))

/// Random compositions of three unary steps on a moderate box.
RC_GTEST_PROP(AffineContains, RandomChains, ()) {
    const auto [lo, hi] = *testing::gen_bounds();
    const Interval box(lo, hi);
    const A1 x = A1::variable(box, 0);
    const int steps[3] = {*rc::gen::inRange(0, 10), *rc::gen::inRange(0, 10),
                          *rc::gen::inRange(0, 10)};
    auto apply = [&](auto v) {
        for (int s : steps) {
            switch (s) {
                case 0:
                    v = square(v);
                    break;
                case 1:
                    v = sqrt(v);
                    break;
                case 2:
                    v = exp(v);
                    break;
                case 3:
                    v = log(v);
                    break;
                case 4:
                    v = sin(v);
                    break;
                case 5:
                    v = cos(v);
                    break;
                case 6:
                    v = abs(v) - 0.25;
                    break;
                case 7:
                    v = 1.0 / v;
                    break;
                case 8:
                    v = pow(v, 3u) - v;
                    break;
                default:
                    v = min(v, v * v);
                    break;
            }
        }
        return v;
    };
    const A1 z = apply(x);
    const Interval r = z.to_interval();
    for (int j = 0; j < kPointsPerBox; ++j) {
        const auto eps = gen_symbols<1>();
        const Big v = apply(gen_value(x, box, eps));
        if (v.valid && (!inside(r, v) || !pointwise(z, eps, v))) {
            RC_FAIL("steps " + std::to_string(steps[0]) + "," + std::to_string(steps[1]) + "," +
                    std::to_string(steps[2]) + " box " + show(box) + " result " + show(r));
        }
    }
}

// ---- correlation: what affine forms are for ---------------------------------------------------

/// A box with bounds in [−100, 100] and width in [1e−3, 10].
rc::Gen<std::pair<double, double>> gen_moderate_box() {
    return rc::gen::apply(
        [](int c, int w) {
            const double lo = std::ldexp(double(c), -10);
            return std::pair{lo, lo + std::ldexp(double(w), -10)};
        },
        rc::gen::inRange(-100 << 10, 100 << 10), rc::gen::inRange(1, 10 << 10));
}

double ulp(double v) { return std::nextafter(std::fabs(v), kInf) - std::fabs(v); }

RC_GTEST_PROP(AffineCorrelation, SelfDifferenceIsNearlyZero, ()) {
    const auto [lo, hi] = *testing::gen_bounds();
    RC_PRE(std::isfinite(lo) && std::isfinite(hi) && lo < hi);
    const Interval box(lo, hi);
    const A1 x = A1::variable(box, 0);
    const Interval d = (x - x).to_interval();
    const Interval iv = box - box;
    RC_ASSERT(width(d) <= 4 * ulp(std::max(std::fabs(lo), std::fabs(hi))));
    RC_ASSERT(contains(d, 0.0));
    RC_ASSERT(width(iv) >= 2 * width(box) * (1 - 1e-15));
}

RC_GTEST_PROP(AffineCorrelation, DifferenceOfSquaresIsNarrowerThanInterval, ()) {
    const auto [lo, hi] = *gen_moderate_box();
    const Interval box(lo, hi);
    const A1 x = A1::variable(box, 0);
    const Interval a = ((x + 1.0) * (x - 1.0) - square(x)).to_interval();
    const Interval i = (box + 1.0) * (box - 1.0) - square(box);
    RC_ASSERT(contains(a, -1.0));
    RC_ASSERT(width(a) < width(i));
    // The exact bound: (x+1)(x−1) − x² = −1, and the affine error is 2 r² plus roundings.
    const double r = 0.5 * (hi - lo);
    RC_ASSERT(width(a) <= 4.0 * r * r + 1e-9);
}

// ---- three variables: the unit sphere ---------------------------------------------------------

template <class T>
T sphere(const T& x, const T& y, const T& z) {
    return sqrt(square(x) + square(y) + square(z)) - 1.0;
}

/// A cube of half-width 2^−k (k ∈ [kmin, kmax]) centred in [−2, 2]³, away from the origin.
struct Cube {
    std::array<Interval, 3> box;
    std::array<double, 3> c;
};
rc::Gen<Cube> gen_cube(int kmin, int kmax) {
    return rc::gen::apply(
        [](int cx, int cy, int cz, int k) {
            const double h = std::ldexp(1.0, -k);
            Cube q;
            q.c = {std::ldexp(double(cx), -12), std::ldexp(double(cy), -12),
                   std::ldexp(double(cz), -12)};
            for (int i = 0; i < 3; ++i) q.box[i] = Interval(q.c[i] - h, q.c[i] + h);
            return q;
        },
        rc::gen::inRange(-2 << 12, 2 << 12), rc::gen::inRange(-2 << 12, 2 << 12),
        rc::gen::inRange(-2 << 12, 2 << 12), rc::gen::inRange(kmin, kmax + 1));
}

RC_GTEST_PROP(AffineSphere, ContainsAndIsAsTightAsIntervalOnSmallBoxes, ()) {
    const Cube q = *gen_cube(10, 30);
    RC_PRE(std::hypot(q.c[0], q.c[1], q.c[2]) > 0.25);
    const A3 x = A3::variable(q.box[0], 0), y = A3::variable(q.box[1], 1),
             z = A3::variable(q.box[2], 2);
    const A3 f = sphere(x, y, z);
    const Interval r = f.to_interval();
    RC_ASSERT(f.defined);
    const Interval iv = sphere(q.box[0], q.box[1], q.box[2]);
    RC_ASSERT(width(r) <= 1.01 * width(iv));
    for (int j = 0; j < kPointsPerBox; ++j) {
        const auto e = gen_symbols<3>();
        const Big v = sphere(point_of<3>(x, e, *gen_eps()), point_of<3>(y, e, *gen_eps()),
                             point_of<3>(z, e, *gen_eps()));
        RC_ASSERT(v.valid);
        RC_ASSERT(inside(r, v));
        RC_ASSERT(pointwise(f, e, v));
    }
}

/// Measures width(affine) / width(interval) of the sphere by box size (printed, and bounded).
TEST(AffineSphere, WidthRatioByBoxSize) {
    for (int k : {1, 3, 6, 10, 20}) {
        double worst = 0, sum = 0;
        int n = 0;
        for (int cx = -7; cx <= 7; cx += 2) {
            for (int cy = -7; cy <= 7; cy += 3) {
                for (int cz = -7; cz <= 7; cz += 5) {
                    const double h = std::ldexp(1.0, -k);
                    const double c[3] = {cx * 0.25 + 0.1, cy * 0.25, cz * 0.25};
                    Interval b[3];
                    for (int i = 0; i < 3; ++i) b[i] = Interval(c[i] - h, c[i] + h);
                    const Interval iv = sphere(b[0], b[1], b[2]);
                    const Interval af =
                        sphere(A3::variable(b[0], 0), A3::variable(b[1], 1), A3::variable(b[2], 2))
                            .to_interval();
                    const double ratio = width(af) / width(iv);
                    worst = std::max(worst, ratio);
                    sum += ratio;
                    ++n;
                }
            }
        }
        std::printf("sphere half-width 2^-%d: width ratio affine/interval mean %.4f worst %.4f\n",
                    k, sum / n, worst);
        if (k >= 10) {
            EXPECT_LE(worst, 1.01) << "half-width 2^-" << k;
        }
    }
}

// ---- decorations, extreme magnitudes, unbounded and empty --------------------------------------

TEST(AffineCases, VariableAndConversions) {
    const A1 x = A1::variable(Interval(1.0, 3.0), 0);
    EXPECT_EQ(x.x0, 2.0);
    EXPECT_EQ(x.xi[0], 1.0);
    EXPECT_EQ(x.err, 0.0);
    EXPECT_EQ(lower(x), 1.0);
    EXPECT_EQ(upper(x), 3.0);
    const A3 c = A3::constant(0.1);
    EXPECT_EQ(lower(c), 0.1);
    EXPECT_EQ(upper(c), 0.1);
    const A3 f = A3::from_interval(Interval(-1.0, 5.0));
    EXPECT_EQ(f.err, 3.0);
    EXPECT_EQ(f.xi[0], 0.0);
    EXPECT_TRUE(is_defined(f));
}

TEST(AffineCases, DomainDecorations) {
    auto var = [](double lo, double hi) { return A1::variable(Interval(lo, hi), 0); };
    EXPECT_TRUE(sqrt(var(0.0, 4.0)).defined);
    EXPECT_EQ(lower(sqrt(var(0.0, 4.0))), 0.0);
    EXPECT_TRUE(sqrt(var(0.0, 5e-324)).defined);
    EXPECT_FALSE(sqrt(var(-1e-300, 1.0)).defined);
    EXPECT_FALSE(sqrt(var(-2.0, -1.0)).defined);
    EXPECT_TRUE(sqrt(var(-2.0, -1.0)).is_empty());
    EXPECT_FALSE(log(var(0.0, 1.0)).defined);
    EXPECT_EQ(lower(log(var(0.0, 1.0))), -kInf);
    EXPECT_TRUE(log(var(0.5, 2.0)).defined);
    EXPECT_TRUE(log(var(-1.0, 0.0)).is_empty());
    EXPECT_FALSE((1.0 / var(-1.0, 1.0)).defined);
    EXPECT_TRUE((1.0 / var(1.0, 2.0)).defined);
    EXPECT_TRUE(contains((1.0 / var(1.0, 2.0)).to_interval(), Interval(0.5, 1.0)));
    // Decorations propagate through affine operations.
    const A1 bad = sqrt(var(-1.0, 1.0));
    EXPECT_FALSE((bad + var(1.0, 2.0)).defined);
    EXPECT_FALSE((bad * 2.0).defined);
}

TEST(AffineCases, ExtremeMagnitudes) {
    const A1 big = A1::variable(Interval(1e300, 2e300), 0);
    const Interval sq = square(big).to_interval();
    EXPECT_EQ(sq.upper(), kInf);
    EXPECT_LE(sq.lower(), 1e300 * 1e300);  // overflow falls back to the Interval square
    EXPECT_TRUE(contains((big - big).to_interval(), 0.0));
    EXPECT_LE(width((big - big).to_interval()), 0.0);
    const Interval inv = (1.0 / big).to_interval();
    EXPECT_TRUE(contains(inv, Interval(5e-301, 1e-300)));
    const A1 tiny = A1::variable(Interval(5e-324, 2e-323), 0);  // subnormal width
    const Interval t2 = square(tiny).to_interval();
    EXPECT_LE(t2.lower(), 0.0);
    EXPECT_GT(t2.upper(), 0.0);
    const Interval ts = sqrt(tiny).to_interval();
    EXPECT_TRUE(
        contains(ts, Interval(std::sqrt(5e-324) * (1 + 1e-15), std::sqrt(2e-323) * (1 - 1e-15))));
    EXPECT_TRUE(exp(A1::variable(Interval(700.0, 710.0), 0)).to_interval().upper() >= 1e308);
}

TEST(AffineCases, UnboundedAndEmptyFallBack) {
    const A1 half = A1::variable(Interval(1.0, kInf), 0);
    EXPECT_EQ(upper(half), kInf);
    EXPECT_TRUE(half.defined);
    const Interval s = sqrt(half).to_interval();
    EXPECT_EQ(s.upper(), kInf);
    EXPECT_TRUE(contains(s, 1e100));
    const Interval e = exp(-half).to_interval();
    EXPECT_TRUE(contains(e, 0.0) || e.lower() <= 0.0);
    EXPECT_TRUE(contains((half * half).to_interval(), 1e300));
    const A1 none = A1::from_interval(Interval::empty());
    EXPECT_TRUE(none.is_empty());
    EXPECT_FALSE(none.defined);
    EXPECT_TRUE((none + half).to_interval().is_empty());
    EXPECT_TRUE(sqrt(none).to_interval().is_empty());
    EXPECT_TRUE(A1(std::numeric_limits<double>::quiet_NaN()).is_empty());
}

}  // namespace
}  // namespace certray
