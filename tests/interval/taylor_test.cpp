// tests/interval/taylor_test.cpp — TaylorModel<D>: the rules on hand-checked cases, the remainder's
// order of convergence, and (RapidCheck) f(p) ∈ P(p − c) + R at random points of random boxes for
// random DAGs, checked exactly against MPFR.
#include "interval/taylor.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "tests/support/mpfr_oracle.h"
#include "tests/support/random_dag.h"

namespace certray {
namespace {

using Box = std::array<Interval, 3>;

static_assert(Enclosure<TaylorModel<1>> && Enclosure<TaylorModel<2>> && Enclosure<TaylorModel<3>>);

template <int D>
TaylorModel<D> model_of(const expr::Tape& tape, const TaylorDomain<D>& dom) {
    expr::Evaluator<TaylorModel<D>> ev;
    return ev(tape, {TaylorModel<D>::variable(dom, 0), TaylorModel<D>::variable(dom, 1),
                     TaylorModel<D>::variable(dom, 2)});
}

expr::Tape tape_of(const char* text) { return expr::Tape(expr::parse_expr(text)); }

/// P(p − c) + R in outward-rounded interval arithmetic.
template <int D>
Interval model_at(const TaylorModel<D>& m, const std::array<double, 3>& p) {
    Interval s(m.a[0]);
    if (m.dom) {
        std::array<Interval, 3> u;
        for (int i = 0; i < 3; ++i) u[i] = Interval(p[i]) - Interval(m.dom->c[i]);
        constexpr auto& mono = detail::kMonomials<D>;
        for (int k = 1; k < TaylorModel<D>::kTerms; ++k) {
            if (m.a[k] == 0) continue;
            Interval t(m.a[k]);
            for (int i = 0; i < 3; ++i) t = t * pow(u[i], static_cast<unsigned>(mono.e[k][i]));
            s = s + t;
        }
    }
    return s + m.r;
}

TEST(Taylor, ExactPolynomialHasZeroRemainder) {
    const expr::Tape tape = tape_of("x*y + 3*z*z - x*x*x + 0.5*y");
    const Box box{Interval(0.5, 1.5), Interval(-2, -1), Interval(0.25, 0.75)};  // dyadic centres
    const TaylorDomain<3> dom(box);
    const TaylorModel<3> m = model_of(tape, dom);
    EXPECT_EQ(m.r.lower(), 0.0);
    EXPECT_EQ(m.r.upper(), 0.0);
    EXPECT_TRUE(m.defined());
    // x = 1 + u, y = −1.5 + v, z = 0.5 + w: the constant term is f(c) = −1.5 + 0.75 − 1 − 0.75.
    EXPECT_EQ(m.a[0], -2.5);
    // A non-dyadic centre: only rounding errors in R.
    const TaylorDomain<3> dom2(Box{Interval(0.1, 0.3), Interval(0.7, 0.9), Interval(-0.3, 0.1)});
    const TaylorModel<3> m2 = model_of(tape, dom2);
    EXPECT_LT(width(m2.r), 1e-14);
}

TEST(Taylor, ProductOfCoordinates) {
    const expr::Tape tape = tape_of("x*y");
    const Box box{Interval(1, 3), Interval(2, 4), Interval(0, 1)};
    // x·y = 6 + 3u + 2v + uv with u, v ∈ [−1, 1].
    const TaylorDomain<1> d1(box);
    const TaylorModel<1> m1 = model_of(tape, d1);
    EXPECT_EQ(m1.a[0], 6.0);
    EXPECT_EQ(m1.a[1], 3.0);  // x
    EXPECT_EQ(m1.a[2], 2.0);  // y
    EXPECT_EQ(m1.r.lower(), -1.0);
    EXPECT_EQ(m1.r.upper(), 1.0);
    const TaylorDomain<2> d2(box);
    const TaylorModel<2> m2 = model_of(tape, d2);
    EXPECT_EQ(m2.r.lower(), 0.0);
    EXPECT_EQ(m2.r.upper(), 0.0);
    EXPECT_EQ(m2.a[detail::kMonomials<2>.index(1, 1, 0)], 1.0);
    EXPECT_EQ(m2.range().lower(), 2.0 - 1.0 - 1.0 + 0.0);  // 6 − 3 − 2 − 1 (monomial bounds)
}

TEST(Taylor, ExpRemainderIsTheLagrangeTerm) {
    const expr::Tape tape = tape_of("exp(x)");
    const double h = 1.0 / 16;
    const TaylorDomain<3> dom(Box{Interval(-h, h), Interval(0, 0), Interval(0, 0)});
    const TaylorModel<3> m = model_of(tape, dom);
    EXPECT_NEAR(m.a[0], 1.0, 1e-15);
    EXPECT_NEAR(m.a[1], 1.0, 1e-15);
    EXPECT_NEAR(m.a[detail::kMonomials<3>.index(2, 0, 0)], 0.5, 1e-15);
    EXPECT_NEAR(m.a[detail::kMonomials<3>.index(3, 0, 0)], 1.0 / 6, 1e-15);
    // e^u − (1 + u + u²/2 + u³/6) = e^ξ u⁴/24: at u = h about h⁴/24, never above e^h h⁴/24.
    const double lagrange = std::exp(h) * std::pow(h, 4) / 24;
    const double at_h = std::pow(h, 4) / 24 * (1 + h / 5);  // e^h − cubic, to 1e-3 relative
    EXPECT_GE(m.r.upper(), at_h * 0.999);
    EXPECT_LE(m.r.upper(), lagrange * 1.01);
    EXPECT_GE(m.r.lower(), -1e-15);
}

TEST(Taylor, DomainEdgesFallBack) {
    const Box box{Interval(-1, 1), Interval(1, 2), Interval(0, 0)};
    const TaylorDomain<2> dom(box);
    const TaylorModel<2> s = model_of(tape_of("sqrt(x)"), dom);
    EXPECT_FALSE(s.defined());
    EXPECT_EQ(s.degree(), 0);
    EXPECT_LE(s.range().lower(), 0.0);
    EXPECT_GE(s.range().upper(), 1.0);
    const TaylorModel<2> l = model_of(tape_of("log(x)"), dom);
    EXPECT_FALSE(l.defined());
    const TaylorModel<2> q = model_of(tape_of("1/x"), dom);
    EXPECT_FALSE(q.defined());
    const TaylorModel<2> ok = model_of(tape_of("log(y) + sqrt(y) + 1/y"), dom);
    EXPECT_TRUE(ok.defined());
    EXPECT_EQ(ok.degree(), 2);
    const TaylorModel<2> e = model_of(tape_of("sqrt(0 - y - 1)"), dom);
    EXPECT_TRUE(e.range().is_empty());
}

TEST(Taylor, BranchesDecidedBySign) {
    const Box box{Interval(1, 2), Interval(-1, 0.5), Interval(3, 4)};
    const TaylorDomain<3> dom(box);
    const TaylorModel<3> a = model_of(tape_of("abs(x*x - 5)"), dom);  // x² − 5 < 0 on [1, 2]
    EXPECT_EQ(a.a[detail::kMonomials<3>.index(2, 0, 0)], -1.0);
    EXPECT_EQ(width(a.r), 0.0);
    const TaylorModel<3> mn = model_of(tape_of("min(x, z)"), dom);
    EXPECT_EQ(mn.a[1], 1.0);
    // Undecided: x − (y + 1) ∈ [−0.5, 2], so max = x + max(0, y + 1 − x) ∈ x + [0, 0.5] (narrower
    // than y + 1 + [0, 2] and than the interval [1, 2]).
    const TaylorModel<3> mx = model_of(tape_of("max(x, y + 1)"), dom);
    EXPECT_EQ(mx.a[1], 1.0);
    EXPECT_EQ(mx.r.lower(), 0.0);
    EXPECT_EQ(mx.r.upper(), 0.5);
    // min(x, y + 1) = (y + 1) − max(0, y + 1 − x) ∈ y + 1 + [−0.5, 0].
    const TaylorModel<3> mi = model_of(tape_of("min(x, y + 1)"), dom);
    EXPECT_EQ(mi.a[2], 1.0);
    EXPECT_EQ(mi.r.lower(), -0.5);
    EXPECT_EQ(mi.r.upper(), 0.0);
    // |x − 1.25| on [1, 2]: x − 1.25 + 2·max(0, 1.25 − x) ∈ x − 1.25 + [0, 0.5].
    const TaylorModel<3> ab = model_of(tape_of("abs(x - 1.25)"), dom);
    EXPECT_EQ(ab.a[1], 1.0);
    EXPECT_EQ(ab.r.lower(), 0.0);
    EXPECT_EQ(ab.r.upper(), 0.5);
    // Far from deciding: the interval result is narrower and kept.
    const TaylorModel<3> wide = model_of(tape_of("max(x*0, y)"), dom);
    EXPECT_EQ(wide.degree(), 0);
}

/// C(1/2, k) as an exact rational: ∏_{i<k} (1 − 2i) / (2ᵏ k!), both parts exact integers.
double binomial_half(int k) {
    double num = 1, den = 1;
    for (int i = 0; i < k; ++i) {
        num *= 1 - 2 * i;
        den *= 2 * (i + 1);
    }
    return num / den;  // den is 2ᵏ k!; the quotient is a dyadic, so the division is exact
}

TEST(Taylor, SqrtBinomialCoefficientsAreExact) {
    for (int k = 0; k <= 4; ++k) EXPECT_EQ(detail::kSqrtBinomial[k], binomial_half(k)) << "k=" << k;
    EXPECT_EQ(detail::kSqrtBinomial[4], -5.0 / 128);
}

TEST(Taylor, SqrtPolynomialPartIsTheBinomialSeries) {
    // √(4 + u) = 2 Σ C(1/2, k) (u/4)ᵏ: coefficients 2, 1/4, −1/64, 1/512 (exact dyadics).
    const double h = 1.0 / 8;
    const TaylorDomain<3> dom(Box{Interval(4 - h, 4 + h), Interval(0, 0), Interval(0, 0)});
    const TaylorModel<3> m = model_of(tape_of("sqrt(x)"), dom);
    for (int k = 0; k <= 3; ++k) {
        const double exact = 2 * binomial_half(k) / std::pow(4.0, k);
        EXPECT_NEAR(m.a[detail::kMonomials<3>.index(k, 0, 0)], exact, 1e-16) << "k=" << k;
    }
    // R is the Lagrange term C(1/2, 4) √ξ ξ⁻⁴ u⁴, ξ ∈ [4 − h, 4 + h], u ∈ [−h, h] (√ξ and ξ⁻⁴
    // enclosed apart), plus rounding: its lower end lies between −(5/128) (4 + h)^{-7/2} h⁴ and
    // −(5/128) √(4 + h) (4 − h)⁻⁴ h⁴; twice the coefficient would fall below the second.
    EXPECT_LE(m.r.lower(), -5.0 / 128 * std::pow(4 + h, -3.5) * std::pow(h, 4) * 0.999);
    EXPECT_GE(m.r.lower(),
              -5.0 / 128 * std::sqrt(4 + h) * std::pow(4 - h, -4) * std::pow(h, 4) * 1.001);
}

// √ of an argument whose offset from a₀ excludes 0: the Lagrange term is then not an interval
// around 0, and a wrong coefficient shows as an unsound enclosure. The argument is a constant
// model a₀ + [δ, δ] (the value a₀ + δ, everything but a₀ in the remainder), the one case where
// the rest of the computation is tight enough for the Lagrange term to matter; checked against
// MPFR over a grid of a₀ and δ of both signs.
TEST(Taylor, SqrtEnclosesWhenTheOffsetExcludesZero) {
    const Precision prec{256};
    int checked = 0;
    for (const double a0 : {0.5, 1.0, 2.0, 4.0, 9.0, 100.0}) {
        for (int k = 1; k <= 12; ++k) {
            for (const double sign : {1.0, -1.0}) {
                const double delta = sign * std::ldexp(a0, -k);  // exact; a₀ + δ > 0
                TaylorModel<3> arg(a0);
                arg.r = Interval(delta);
                const Interval r = sqrt(arg).range();
                const MpfrInterval exact = sqrt(MpfrInterval(a0, prec) + MpfrInterval(delta, prec));
                EXPECT_TRUE(testing::encloses(r.lower(), r.upper(), exact))
                    << "a0 " << a0 << " delta " << delta << ": [" << r.lower() << ", " << r.upper()
                    << "] vs " << testing::describe(exact);
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 144);
}

/// Width of R on boxes of half-width h: ~ C h^{D+1}. Returns the fitted exponent.
template <int D>
double remainder_order(const expr::Tape& tape) {
    double prev = 0, slope = 0;
    for (int k = 3; k <= 8; ++k) {
        const double h = std::ldexp(1.0, -k);
        const TaylorDomain<D> dom(Box{Interval(0.3 - h, 0.3 + h), Interval(0.7 - h, 0.7 + h),
                                      Interval(-0.2 - h, -0.2 + h)});
        const double w = width(model_of(tape, dom).r);
        if (k > 3) slope = std::log2(prev / w);
        std::printf("D=%d h=2^-%d width(R)=%.3e%s\n", D, k, w,
                    k > 3 ? (" order " + std::to_string(slope)).c_str() : "");
        prev = w;
    }
    return slope;
}

TEST(Taylor, RemainderShrinksLikeHToTheDegreePlusOne) {
    const expr::Tape tape =
        tape_of("sin(3*x) * exp(y) + sqrt(1 + z*z) - log(2 + x*y) + cos(z) / (2 + y)");
    EXPECT_GT(remainder_order<1>(tape), 1.7);
    EXPECT_GT(remainder_order<2>(tape), 2.7);
    EXPECT_GT(remainder_order<3>(tape), 3.7);
}

template <int D>
void check_random_cell() {
    const expr::Graph g = *testing::gen_dag(16);
    const expr::Tape tape(g);
    std::array<double, 3> c, p;
    const double h = std::ldexp(1.0, -*rc::gen::inRange(0, 12));
    Box box;
    for (int i = 0; i < 3; ++i) {
        c[i] = *rc::gen::inRange(-256, 257) / 64.0;
        box[i] = Interval(c[i] - h, c[i] + h);
        p[i] = c[i] + h * (*rc::gen::inRange(-1024, 1025) / 1024.0);  // exact (dyadic)
    }
    const TaylorDomain<D> dom(box);
    const TaylorModel<D> m = model_of(tape, dom);
    const Precision prec{4096};  // exact sums of 1e300 and 1 (as poly_test)
    const MpfrInterval exact = expr::eval<MpfrInterval>(
        tape, {MpfrInterval(p[0], prec), MpfrInterval(p[1], prec), MpfrInterval(p[2], prec)});
    RC_TAG(m.defined() ? "model defined" : "model not defined",
           exact.defined ? "point defined" : "point not defined", "degree", m.degree(),
           std::isfinite(width(m.r)) ? "finite R" : "infinite R");
    for (double v : m.a) RC_ASSERT(std::isfinite(v));
    if (!exact.defined) return;  // the contract is about points where f is defined
    const Interval at = model_at(m, p);
    RC_ASSERT(testing::encloses(at.lower(), at.upper(), exact));
    const Interval range = m.range();
    RC_ASSERT(testing::encloses(range.lower(), range.upper(), exact));
    // The ray composition through p (t = 0 at p) encloses it too.
    const std::array<double, 3> d{0.0, 0.0, 0.0};
    const RayModel rm = m.compose_ray(p, d, Interval(0.0));
    const Interval g0 = horner(rm.p, Interval(0.0)) + rm.r;
    RC_ASSERT(testing::encloses(g0.lower(), g0.upper(), exact));
}

RC_GTEST_PROP(TaylorProperty, Degree1EnclosesMpfrAtPointsOfTheCell, ()) { check_random_cell<1>(); }
RC_GTEST_PROP(TaylorProperty, Degree2EnclosesMpfrAtPointsOfTheCell, ()) { check_random_cell<2>(); }
RC_GTEST_PROP(TaylorProperty, Degree3EnclosesMpfrAtPointsOfTheCell, ()) { check_random_cell<3>(); }

/// compose_ray: for a ray through the cell, p(t) + r encloses f(o + t·d) at sample t.
RC_GTEST_PROP(TaylorProperty, RayCompositionEnclosesMpfrAlongTheRay, ()) {
    const expr::Graph g = *testing::gen_dag(12);
    const expr::Tape tape(g);
    const double h = std::ldexp(1.0, -*rc::gen::inRange(0, 8));
    std::array<double, 3> c, o, d;
    Box box;
    for (int i = 0; i < 3; ++i) {
        c[i] = *rc::gen::inRange(-128, 129) / 64.0;
        box[i] = Interval(c[i] - h, c[i] + h);
        o[i] = c[i] + h * (*rc::gen::inRange(-64, 65) / 64.0);
        d[i] = *rc::gen::inRange(-64, 65) / 64.0;
    }
    const TaylorDomain<3> dom(box);
    const TaylorModel<3> m = model_of(tape, dom);
    // t in [0, tmax] with o + t·d in the box: tmax = min over axes of the distance to the face.
    double tmax = 1.0;
    for (int i = 0; i < 3; ++i)
        if (d[i] != 0) tmax = std::min(tmax, ((d[i] > 0 ? c[i] + h : c[i] - h) - o[i]) / d[i]);
    tmax = std::ldexp(std::max(std::floor(std::ldexp(tmax, 20)) - 1, 0.0), -20);  // dyadic, inside
    const RayModel rm = m.compose_ray(o, d, Interval(0.0, tmax));
    const double t = tmax * (*rc::gen::inRange(0, 17) / 16.0);
    const Precision prec{4096};
    std::array<MpfrInterval, 3> q;
    for (int i = 0; i < 3; ++i)
        q[i] = MpfrInterval(o[i], prec) + MpfrInterval(t, prec) * MpfrInterval(d[i], prec);
    const MpfrInterval exact = expr::eval<MpfrInterval>(tape, q);
    if (!exact.defined) return;
    const Interval gt = horner(rm.p, Interval(t)) + rm.r;
    RC_ASSERT(testing::encloses(gt.lower(), gt.upper(), exact));
    const Interval gr = range(rm.p) + rm.r;
    RC_ASSERT(testing::encloses(gr.lower(), gr.upper(), exact));
}

}  // namespace
}  // namespace certray
