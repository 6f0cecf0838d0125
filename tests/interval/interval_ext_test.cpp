// tests/interval/interval_ext_test.cpp — Fidget's further ops (issue 14) over Interval,
// MpfrInterval and Dual: the case tables at the edges, RapidCheck properties against the MPFR
// oracle at 256 bits (enclosure at points of the box, decoration only where the op is continuous
// on the box), and Dual derivatives against MPFR central differences.
#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>

#include "interval/dual.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"

namespace certray {
namespace {

using testing::describe;
using testing::encloses;
using testing::gen_bounds;
using testing::gen_point_in;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.141592653589793;

void expect_bounds(const Interval& r, double lo, double hi, bool def) {
    EXPECT_EQ(r.lower(), lo);
    EXPECT_EQ(r.upper(), hi);
    EXPECT_EQ(r.defined, def) << "[" << r.lower() << ", " << r.upper() << "]";
}

// ---- case tables --------------------------------------------------------------------------------

TEST(IntervalExtCases, IntegerSteps) {
    expect_bounds(floor(Interval(1.2, 1.7)), 1, 1, true);  // no jump: constant, defined
    expect_bounds(floor(Interval(0.5, 1.5)), 0, 1, false);
    expect_bounds(floor(Interval(1.0, 1.5)), 1, 1, true);   // right-continuous at 1
    expect_bounds(floor(Interval(0.5, 1.0)), 0, 1, false);  // jumps at 1
    expect_bounds(ceil(Interval(0.5, 1.0)), 1, 1, true);
    expect_bounds(ceil(Interval(1.0, 1.5)), 1, 2, false);
    expect_bounds(round(Interval(0.4, 0.6)), 0, 1, false);
    expect_bounds(round(Interval(-0.4, 0.4)), 0, 0, true);
    expect_bounds(round(Interval(2.5, 2.5)), 3, 3, true);  // halves away from 0
    expect_bounds(round(Interval(-2.5, -2.5)), -3, -3, true);
    const Interval u = floor(Interval(-kInf, 3.5));
    EXPECT_EQ(u.lower(), -kInf);
    EXPECT_FALSE(u.defined);
    EXPECT_TRUE(floor(Interval::empty()).is_empty());
}

TEST(IntervalExtCases, TanPolesAndBranches) {
    const Interval t = tan(Interval(1.0, 2.0));  // holds π/2
    EXPECT_EQ(t.lower(), -kInf);
    EXPECT_EQ(t.upper(), kInf);
    EXPECT_FALSE(t.defined);
    const Interval s = tan(Interval(-1.0, 1.0));
    EXPECT_TRUE(s.defined);
    EXPECT_LT(s.lower(), std::tan(-1.0));
    EXPECT_GT(s.upper(), std::tan(1.0));
    EXPECT_TRUE(tan(Interval(2.0, 4.0)).defined);       // between π/2 and 3π/2
    EXPECT_FALSE(tan(Interval(1e300, 1e300)).defined);  // reduction too coarse to tell
    expect_bounds(tan(Interval(0.0)), 0, 0, true);
    EXPECT_FALSE(tan(Interval(0.0, kInf)).defined);
}

TEST(IntervalExtCases, InverseTrigDomains) {
    const Interval a = asin(Interval(0.0, 5.0));  // set-based: asin([0, 1])
    EXPECT_EQ(a.lower(), 0.0);
    EXPECT_GE(a.upper(), kPi / 2);
    EXPECT_FALSE(a.defined);
    EXPECT_TRUE(asin(Interval(2.0, 3.0)).is_empty());
    EXPECT_TRUE(asin(Interval(-1.0, 1.0)).defined);
    const Interval c = acos(Interval(-3.0, 1.0));
    EXPECT_EQ(c.lower(), 0.0);
    EXPECT_GE(c.upper(), kPi);
    EXPECT_FALSE(c.defined);
    const Interval t = atan(Interval(-kInf, kInf));
    EXPECT_LE(t.lower(), -kPi / 2);
    EXPECT_GE(t.upper(), kPi / 2);
    EXPECT_TRUE(t.defined);
    expect_bounds(atan(Interval(0.0)), 0, 0, true);
}

TEST(IntervalExtCases, Atan2OriginAndBranchCut) {
    EXPECT_TRUE(atan2(Interval(0.0), Interval(0.0)).is_empty());    // undefined at the origin
    EXPECT_FALSE(atan2(Interval(-1, 1), Interval(-1, 1)).defined);  // holds the origin
    const Interval cut = atan2(Interval(-1, 1), Interval(-2, -1));  // crosses y = 0, x < 0
    EXPECT_FALSE(cut.defined);
    EXPECT_LE(cut.lower(), -kPi);
    EXPECT_GE(cut.upper(), kPi);
    const Interval above = atan2(Interval(0, 1), Interval(-2, -1));  // touches the cut from above
    EXPECT_TRUE(above.defined);
    EXPECT_GE(above.upper(), kPi);
    EXPECT_GT(above.lower(), 2.0);
    EXPECT_FALSE(atan2(Interval(-1, 0), Interval(-2, -1)).defined);  // reaches it from below
    const Interval right = atan2(Interval(-1, 1), Interval(1, 2));   // across the positive axis
    EXPECT_TRUE(right.defined);
    EXPECT_LT(right.lower(), -0.78);
    EXPECT_GT(right.upper(), 0.78);
    expect_bounds(atan2(Interval(0.0), Interval(1, 2)), 0, 0, true);
}

TEST(IntervalExtCases, CompareModSelect) {
    expect_bounds(compare(Interval(1, 2), Interval(3, 4)), -1, -1, true);
    expect_bounds(compare(Interval(3, 4), Interval(1, 2)), 1, 1, true);
    expect_bounds(compare(Interval(2, 2), Interval(2, 2)), 0, 0, true);
    expect_bounds(compare(Interval(1, 3), Interval(2, 4)), -1, 1, false);
    expect_bounds(compare(Interval(1, 2), Interval(2, 4)), -1, 0, false);
    const Interval m = mod(Interval(2.5, 3.5), Interval(2.0));  // ⌊x/2⌋ = 1 on the box
    EXPECT_TRUE(m.defined);
    EXPECT_LE(m.lower(), 0.5);
    EXPECT_GE(m.upper(), 1.5);
    expect_bounds(mod(Interval(1.5, 2.5), Interval(2.0)), 0, 2, false);        // jumps at 2
    expect_bounds(mod(Interval(-0.5, -0.5), Interval(-2.0)), 1.5, 1.5, true);  // Euclidean
    expect_bounds(mod(Interval(1, 2), Interval(-1, 1)), 0, 1, false);          // b may be 0
    EXPECT_TRUE(mod(Interval(1, 2), Interval(0.0)).is_empty());
    expect_bounds(logic_and(Interval(0.0), Interval(5, 6)), 0, 0, true);
    expect_bounds(logic_and(Interval(1, 2), Interval(5, 6)), 5, 6, true);
    expect_bounds(logic_and(Interval(-1, 2), Interval(5, 6)), 0, 6, false);
    expect_bounds(logic_or(Interval(1, 2), Interval(5, 6)), 1, 2, true);
    expect_bounds(logic_or(Interval(0.0), Interval(5, 6)), 5, 6, true);
    expect_bounds(logic_or(Interval(-1, 2), Interval(5, 6)), -1, 6, false);
    expect_bounds(logic_not(Interval(0.0)), 1, 1, true);
    expect_bounds(logic_not(Interval(1, 2)), 0, 0, true);
    expect_bounds(logic_not(Interval(-1, 2)), 0, 1, false);
}

// ---- properties ---------------------------------------------------------------------------------

/// The value of op at the point(s) in MPFR at 256 bits (empty where undefined).
template <class MpfrOp>
MpfrInterval at(MpfrOp mop, double p) {
    return mop(MpfrInterval(p));
}

/// Both points' MPFR values are the same single real (what a `defined` piecewise-constant result
/// promises).
bool same_value(const MpfrInterval& a, const MpfrInterval& b) {
    return !a.is_empty() && !b.is_empty() && mpfr_equal_p(a.lo(), b.lo()) &&
           mpfr_equal_p(a.hi(), b.hi());
}

template <class IntervalOp, class MpfrOp>
void check_unary(IntervalOp iop, MpfrOp mop, bool piecewise_constant) {
    const auto [lo, hi] = *gen_bounds();
    const double p = *gen_point_in(lo, hi), q = *gen_point_in(lo, hi);
    const Interval r = iop(Interval(lo, hi));
    const MpfrInterval ep = mop(MpfrInterval(p)), eq = mop(MpfrInterval(q));
    RC_ASSERT(encloses(r.lower(), r.upper(), ep));
    RC_ASSERT(encloses(r.lower(), r.upper(), eq));
    if (r.defined) {
        RC_ASSERT(!ep.is_empty());
        if (piecewise_constant) RC_ASSERT(same_value(ep, eq));
    }
    // The MPFR box op encloses the points too, and claims no more continuity.
    const MpfrInterval mb = mop(MpfrInterval(lo, hi));
    RC_ASSERT(encloses(mb.lower(), mb.upper(), ep));
    if (mb.defined && piecewise_constant) RC_ASSERT(same_value(ep, eq));
    RoundingScope scope;
    const UpInterval f = iop(UpInterval(lo, hi));
    RC_ASSERT(f.is_empty() == r.is_empty());
    if (!r.is_empty()) RC_ASSERT(f.lower() == r.lower() && f.upper() == r.upper());
    RC_ASSERT(f.defined == r.defined);
}

template <class IntervalOp, class MpfrOp>
void check_binary(IntervalOp iop, MpfrOp mop, bool piecewise_constant) {
    const auto [alo, ahi] = *gen_bounds();
    const auto [blo, bhi] = *gen_bounds();
    const double p = *gen_point_in(alo, ahi), q = *gen_point_in(blo, bhi);
    const double p2 = *gen_point_in(alo, ahi), q2 = *gen_point_in(blo, bhi);
    const Interval r = iop(Interval(alo, ahi), Interval(blo, bhi));
    const MpfrInterval e = mop(MpfrInterval(p), MpfrInterval(q));
    const MpfrInterval e2 = mop(MpfrInterval(p2), MpfrInterval(q2));
    RC_ASSERT(encloses(r.lower(), r.upper(), e));
    RC_ASSERT(encloses(r.lower(), r.upper(), e2));
    if (r.defined) {
        RC_ASSERT(!e.is_empty());
        if (piecewise_constant) RC_ASSERT(same_value(e, e2));
    }
    const MpfrInterval mb = mop(MpfrInterval(alo, ahi), MpfrInterval(blo, bhi));
    RC_ASSERT(encloses(mb.lower(), mb.upper(), e));
    if (mb.defined && piecewise_constant) RC_ASSERT(same_value(e, e2));
    RoundingScope scope;
    const UpInterval f = iop(UpInterval(alo, ahi), UpInterval(blo, bhi));
    RC_ASSERT(f.is_empty() == r.is_empty());
    if (!r.is_empty()) RC_ASSERT(f.lower() == r.lower() && f.upper() == r.upper());
    RC_ASSERT(f.defined == r.defined);
}

#define CERTRAY_UNARY_PROP(name, expr, pc)                                                        \
    RC_GTEST_PROP(IntervalExtProperty, name, ()) {                                                \
        check_unary([](auto x) { return expr; }, [](const MpfrInterval& x) { return expr; }, pc); \
    }
#define CERTRAY_BINARY_PROP(name, expr, pc)                                                  \
    RC_GTEST_PROP(IntervalExtProperty, name, ()) {                                           \
        check_binary([](auto x, auto y) { return expr; },                                    \
                     [](const MpfrInterval& x, const MpfrInterval& y) { return expr; }, pc); \
    }

CERTRAY_UNARY_PROP(Floor, floor(x), true)
CERTRAY_UNARY_PROP(Ceil, ceil(x), true)
CERTRAY_UNARY_PROP(Round, round(x), true)
CERTRAY_UNARY_PROP(Not, logic_not(x), true)
CERTRAY_UNARY_PROP(Tan, tan(x), false)
CERTRAY_UNARY_PROP(Asin, asin(x), false)
CERTRAY_UNARY_PROP(Acos, acos(x), false)
CERTRAY_UNARY_PROP(Atan, atan(x), false)
CERTRAY_BINARY_PROP(Compare, compare(x, y), true)
CERTRAY_BINARY_PROP(Atan2, atan2(x, y), false)
CERTRAY_BINARY_PROP(Mod, mod(x, y), false)
CERTRAY_BINARY_PROP(And, logic_and(x, y), false)
CERTRAY_BINARY_PROP(Or, logic_or(x, y), false)

// tan over narrow boxes near the poles: still an enclosure, and defined only off the poles.
RC_GTEST_PROP(IntervalExtProperty, TanNearPoles, ()) {
    const int k = *rc::gen::inRange(-20, 20);
    const double c = (k + 0.5) * kPi, w = std::ldexp(1.0, *rc::gen::inRange(-50, 0));
    const double lo = c - w * *rc::gen::inRange(0, 4), hi = c + w * *rc::gen::inRange(0, 4);
    const double p = *gen_point_in(lo, hi);
    const Interval r = tan(Interval(lo, hi));
    const MpfrInterval e = tan(MpfrInterval(p));
    RC_ASSERT(encloses(r.lower(), r.upper(), e));
    const MpfrInterval box = tan(MpfrInterval(lo, hi));
    RC_ASSERT(encloses(box.lower(), box.upper(), e));
    // A defined result is bounded: no pole inside.
    if (r.defined) RC_ASSERT(std::isfinite(r.lower()) && std::isfinite(r.upper()));
}

// ---- Dual: derivatives against MPFR central differences
// ------------------------------------------

/// (f(x + h) − f(x − h)) / 2h at 256 bits, for a smooth f at x, rounded to double.
template <class F>
double central_difference(F f, double x, double h) {
    const MpfrInterval a = f(MpfrInterval(x) + MpfrInterval(h));
    const MpfrInterval b = f(MpfrInterval(x) - MpfrInterval(h));
    const MpfrInterval d = (a - b) / MpfrInterval(2 * h);
    return 0.5 * d.lower() + 0.5 * d.upper();
}

template <class DualOp, class MpfrOp>
void check_derivative(DualOp dop, MpfrOp mop, double lo, double hi) {
    const double x = *rc::gen::map(rc::gen::inRange(0, 1 << 20), [lo, hi](int k) {
        return lo + (hi - lo) * (k / double(1 << 20));
    });
    const Dual<double, 1> r = dop(Dual<double, 1>::variable(x, 0));
    const double h = 1e-7 * std::max(1.0, std::fabs(x));
    const double expect = central_difference(mop, x, h);
    RC_ASSERT(std::fabs(r.v[0] - expect) <= 1e-5 * std::max(1.0, std::fabs(expect)));
    // The interval Dual over a small box around x encloses the derivative there.
    const Dual<Interval, 1> box = dop(Dual<Interval, 1>::variable(Interval(x, x), 0));
    const double tol = 1e-5 * std::max(1.0, std::fabs(expect));
    RC_ASSERT(box.v[0].lower() - tol <= expect && expect <= box.v[0].upper() + tol);
}

/// The constant v in x's type.
template <class T>
T lit(const T&, double v) {
    return T(v);
}

#define CERTRAY_DUAL_PROP(name, expr, lo, hi)                                                     \
    RC_GTEST_PROP(DualExtProperty, name, ()) {                                                    \
        check_derivative([](auto x) { return expr; }, [](const MpfrInterval& x) { return expr; }, \
                         lo, hi);                                                                 \
    }

CERTRAY_DUAL_PROP(Tan, tan(x), -1.4, 1.4)
CERTRAY_DUAL_PROP(Asin, asin(x), -0.95, 0.95)
CERTRAY_DUAL_PROP(Acos, acos(x), -0.95, 0.95)
CERTRAY_DUAL_PROP(Atan, atan(x), -30.0, 30.0)
CERTRAY_DUAL_PROP(Atan2Y, atan2(x, x* x + lit(x, 0.5)), -3.0, 3.0)

TEST(DualExt, PiecewiseConstantAndSelect) {
    using D = Dual<double, 2>;
    const D x = D::variable(1.25, 0), y = D::variable(-2.0, 1);
    EXPECT_EQ(floor(x).a, 1.0);
    EXPECT_EQ(floor(x).v[0], 0.0);
    EXPECT_EQ(compare(x, y).a, 1.0);
    EXPECT_EQ(compare(x, y).v[1], 0.0);
    // mod(x, y) = x − |y|·⌊x/|y|⌋ = 1.25, ∂/∂x = 1, ∂/∂y = −sgn(y)·⌊x/|y|⌋ = 0.
    EXPECT_EQ(mod(x, y).a, 1.25);
    EXPECT_EQ(mod(x, y).v[0], 1.0);
    // mod(5.5, y = −2) = 1.5 = 5.5 − 2·2: ∂/∂y = −sgn(−2)·2 = 2.
    const D m = mod(D::variable(5.5, 0), y);
    EXPECT_EQ(m.a, 1.5);
    EXPECT_EQ(m.v[1], 2.0);
    EXPECT_EQ(logic_and(x, y).v[1], 1.0);       // x ≠ 0 selects y
    EXPECT_EQ(logic_or(x, y).v[0], 1.0);        // x ≠ 0 selects x
    EXPECT_EQ(logic_and(D(0.0), y).v[1], 0.0);  // 0 selects itself
    // atan2(y, x)' = (x·y' − y·x')/(x² + y²) at (x, y) = (1.25, −2).
    const D t = atan2(y, x);
    EXPECT_NEAR(t.v[0], 2.0 / (1.25 * 1.25 + 4.0), 1e-15);
    EXPECT_NEAR(t.v[1], 1.25 / (1.25 * 1.25 + 4.0), 1e-15);
    // Over an interval box where floor jumps, the value is not defined.
    using DI = Dual<Interval, 1>;
    EXPECT_FALSE(floor(DI::variable(Interval(0.5, 1.5), 0)).a.defined);
    EXPECT_TRUE(floor(DI::variable(Interval(1.2, 1.7), 0)).a.defined);
}

}  // namespace
}  // namespace certray
