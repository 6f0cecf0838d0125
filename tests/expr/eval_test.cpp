// tests/expr/eval_test.cpp — the tape, the one evaluator over every number type, pruning and
// Lipschitz bounds, against mathematics and against MPFR on random DAGs.
#include "expr/eval.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "expr/derived.h"
#include "expr/graph.h"
#include "expr/prune.h"
#include "expr/tape.h"
#include "interval/affine.h"
#include "interval/dual.h"
#include "interval/mpfr_interval.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"
#include "tests/support/random_dag.h"

namespace certray::expr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// f = sqrt(x² + y² + z²) − 1, built node by node.
Graph unit_sphere() {
    Graph g;
    const NodeId x = g.var(0), y = g.var(1), z = g.var(2);
    const NodeId r2 =
        g.binary(Op::Add, g.binary(Op::Add, g.unary(Op::Square, x), g.unary(Op::Square, y)),
                 g.unary(Op::Square, z));
    g.set_output(g.binary(Op::Sub, g.unary(Op::Sqrt, r2), g.constant(1.0)));
    return g;
}

TEST(Tape, SphereValuesAreTheDistance) {
    const Tape t(unit_sphere());
    EXPECT_EQ(t.size(), 11u);  // x y z, three squares, two adds, sqrt, the constant, sub
    EXPECT_LE(t.registers(), 4u);
    EXPECT_EQ(eval<double>(t, {3.0, 4.0, 12.0}), 12.0);  // √169 − 1
    EXPECT_EQ(eval<double>(t, {0.0, 0.0, 0.0}), -1.0);
    EXPECT_EQ(eval<double>(t, {1.0, 0.0, 0.0}), 0.0);
}

TEST(Tape, IntervalEnclosesTheSphereOverABox) {
    const Tape t(unit_sphere());
    const Interval r = eval<Interval>(t, {Interval(1, 2), Interval(0, 0), Interval(0, 0)});
    EXPECT_EQ(r.lower(), 0.0);
    EXPECT_EQ(r.upper(), 1.0);
    EXPECT_TRUE(r.defined);
}

TEST(Tape, SharedRegistersStaySmallOnALongChain) {
    // f = ((x + 1)·x + 1)·x + … : every intermediate dies at once, so two or three registers do.
    Graph g;
    NodeId f = g.var(0);
    for (int i = 0; i < 1000; ++i) {
        f = g.binary(Op::Mul, g.binary(Op::Add, f, g.constant(1.0 + i)), g.var(0));
    }
    g.set_output(f);
    const Tape t(g);
    EXPECT_LE(t.registers(), 4u);
    EXPECT_EQ(eval<double>(t, {0.0, 0.0, 0.0}), 0.0);
}

TEST(Derived, GradientOfTheSphere) {
    const Tape t(unit_sphere());
    const auto d = gradient(t, {1.0, 2.0, 2.0});
    EXPECT_EQ(d.a, 2.0);
    EXPECT_NEAR(d.v[0], 1.0 / 3, 1e-15);
    EXPECT_NEAR(d.v[1], 2.0 / 3, 1e-15);
    EXPECT_NEAR(d.v[2], 2.0 / 3, 1e-15);
}

TEST(Derived, LipschitzOfADistanceIsAboutOne) {
    const Tape t(unit_sphere());
    // Away from the origin ‖∇f‖ = 1; the interval bound is ≥ 1 and not absurdly larger.
    const double l = lipschitz_bound(t, {Interval(1, 1.1), Interval(1, 1.1), Interval(1, 1.1)});
    EXPECT_GE(l, 1.0);
    EXPECT_LT(l, 1.3);
    // Through the origin √ has no bounded derivative, but ‖p‖ − 1 is 1-Lipschitz everywhere:
    // the root form of x² + y² + z² (Gram matrix I) gives exactly 1 (interval/grad_bound.h).
    EXPECT_EQ(lipschitz_bound(t, {Interval(-1, 1), Interval(-1, 1), Interval(-1, 1)}), 1.0);
    // A segment's bound is the bound over its bounding box.
    EXPECT_EQ(lipschitz_bound_segment(t, {1.1, 1.0, 1.1}, {1.0, 1.1, 1.0}),
              lipschitz_bound(t, {Interval(1, 1.1), Interval(1, 1.1), Interval(1, 1.1)}));
}

TEST(Derived, NormBoundIsTightAtExtremeMagnitudes) {
    // ‖(3, 4, 0)·2^k‖ = 5·2^k: the bound holds and is within a few ulps at every scale, where
    // plain squares would underflow (k = −600, −1060) or overflow (k = 600).
    for (int k : {-1060, -600, -300, 0, 300, 600}) {
        const double s = std::ldexp(1.0, k);
        const double n = norm_bound({Interval(3 * s), Interval(-4 * s, 2 * s), Interval(0)});
        EXPECT_GE(n, 5 * s) << k;
        EXPECT_LE(n, 5 * s * (1 + 1e-14)) << k;
    }
    EXPECT_EQ(norm_bound({Interval(0), Interval(0), Interval(0)}), 0.0);
    // √2·1e308 is still a double; √2·1.5e308 is not: the bound is +inf there.
    EXPECT_LE(norm_bound({Interval(1e308), Interval(1e308), Interval(0)}), 1.4142136e308);
    EXPECT_EQ(norm_bound({Interval(1.5e308), Interval(1.5e308), Interval(0)}),
              std::numeric_limits<double>::infinity());
}

TEST(Prune, MinOfTwoSpheresKeepsTheNearOne) {
    // f = min(|p − (−2,0,0)| − 1, |p − (2,0,0)| − 1): on x < 0 only the first sphere matters.
    Graph g;
    auto sphere = [&](double cx) {
        const NodeId dx = g.binary(Op::Sub, g.var(0), g.constant(cx));
        const NodeId r2 = g.binary(
            Op::Add, g.binary(Op::Add, g.unary(Op::Square, dx), g.unary(Op::Square, g.var(1))),
            g.unary(Op::Square, g.var(2)));
        return g.binary(Op::Sub, g.unary(Op::Sqrt, r2), g.constant(1.0));
    };
    g.set_output(g.binary(Op::Min, sphere(-2.0), sphere(2.0)));
    const Tape t(g);
    const std::array<Interval, 3> box{Interval(-3, -1), Interval(-1, 1), Interval(-1, 1)};
    const PruneResult p = prune(t, box);
    EXPECT_EQ(p.before, t.size());
    EXPECT_LT(p.after, p.before);
    EXPECT_FALSE(p.tape.ssa().back().op == Op::Min);
    EXPECT_EQ(eval<double>(p.tape, {-2.0, 0.0, 0.0}), -1.0);
    // A box that straddles both keeps the min.
    const PruneResult q = prune(t, {Interval(-3, 3), Interval(-1, 1), Interval(-1, 1)});
    EXPECT_EQ(q.after, q.before);
}

TEST(Prune, NeverDropsAnUndefinedBranch) {
    // min(x, sqrt(y)) over x ∈ [-2, -1], y ∈ [-1, 1]: x is always smaller where sqrt(y) exists, but
    // f is undefined for y < 0, so dropping sqrt(y) would change the function.
    Graph g;
    g.set_output(g.binary(Op::Min, g.var(0), g.unary(Op::Sqrt, g.var(1))));
    const Tape t(g);
    const PruneResult p = prune(t, {Interval(-2, -1), Interval(-1, 1), Interval(0.0)});
    EXPECT_EQ(p.after, p.before);
    const PruneResult q = prune(t, {Interval(-2, -1), Interval(0, 1), Interval(0.0)});
    EXPECT_LT(q.after, q.before);
}

// ---- properties on random DAGs --------------------------------------------------------------

struct Box {
    std::array<std::pair<double, double>, 3> b;
    std::array<double, 3> p;
};

Box gen_box_and_point() {
    Box box;
    for (int i = 0; i < 3; ++i) {
        box.b[i] = *testing::gen_bounds();
        box.p[i] = *testing::gen_point_in(box.b[i].first, box.b[i].second);
    }
    return box;
}

std::array<Interval, 3> intervals(const Box& box) {
    return {Interval(box.b[0].first, box.b[0].second), Interval(box.b[1].first, box.b[1].second),
            Interval(box.b[2].first, box.b[2].second)};
}

RC_GTEST_PROP(EvalProperty, IntervalContainsMpfrAtPointsOfTheBox, ()) {
    const Graph g = *testing::gen_dag();
    const Tape t(g);
    const Box box = gen_box_and_point();
    const Interval r = eval<Interval>(t, intervals(box));
    const MpfrInterval exact = eval<MpfrInterval>(
        t, {MpfrInterval(box.p[0]), MpfrInterval(box.p[1]), MpfrInterval(box.p[2])});
    RC_ASSERT(testing::encloses(r.lower(), r.upper(), exact));
    if (r.defined) RC_ASSERT(!exact.is_empty());
    // The double evaluation at the point agrees with the enclosure where f is defined.
    const double d = eval<double>(t, box.p);
    if (!exact.is_empty() && !std::isnan(d)) RC_ASSERT(contains(r, d) || std::isinf(d));
}

RC_GTEST_PROP(EvalProperty, AffineContainsMpfrAtPointsOfTheBox, ()) {
    const Graph g = *testing::gen_dag();
    const Tape t(g);
    const Box box = gen_box_and_point();
    const std::array<Interval, 3> iv = intervals(box);
    using A = Affine<3>;
    const A r = eval<A>(t, {A::variable(iv[0], 0), A::variable(iv[1], 1), A::variable(iv[2], 2)});
    const MpfrInterval exact = eval<MpfrInterval>(
        t, {MpfrInterval(box.p[0]), MpfrInterval(box.p[1]), MpfrInterval(box.p[2])});
    RC_ASSERT(testing::encloses(lower(r), upper(r), exact));
    if (is_defined(r)) RC_ASSERT(!exact.is_empty());
}

RC_GTEST_PROP(EvalProperty, IntervalGradientContainsMpfrGradient, ()) {
    const Graph g = *testing::gen_dag();
    const Tape t(g);
    const Box box = gen_box_and_point();
    const Dual<Interval, 3> d = interval_gradient(t, intervals(box));
    using M = Dual<MpfrInterval, 3>;
    const M exact =
        eval<M>(t, {M::variable(MpfrInterval(box.p[0]), 0), M::variable(MpfrInterval(box.p[1]), 1),
                    M::variable(MpfrInterval(box.p[2]), 2)});
    RC_ASSERT(testing::encloses(d.a.lower(), d.a.upper(), exact.a));
    // Where f is defined and continuous on the box, each partial at the point lies in the
    // box's partial enclosure.
    if (!d.a.defined || exact.a.is_empty()) return;
    for (int i = 0; i < 3; ++i) {
        RC_ASSERT(testing::encloses(d.v[i].lower(), d.v[i].upper(), exact.v[i]));
    }
}

RC_GTEST_PROP(EvalProperty, PrunedTapeAgreesInsideItsBox, ()) {
    const Graph g = *testing::gen_dag(40);
    const Tape t(g);
    const Box box = gen_box_and_point();
    const PruneResult p = prune(t, intervals(box));
    RC_ASSERT(p.after <= p.before);
    // Same real function: at the point, the 256-bit enclosures of both are empty together
    // (f undefined) or overlap (both contain f(p)). Doubles would not do: exp(15625)·0 is NaN in
    // binary64 but 0 in the reals, and pruning rightly folds it to 0.
    auto at = [&](const Tape& tape) {
        return eval<MpfrInterval>(
            tape, {MpfrInterval(box.p[0]), MpfrInterval(box.p[1]), MpfrInterval(box.p[2])});
    };
    const MpfrInterval full = at(t), pruned = at(p.tape);
    RC_ASSERT(full.is_empty() == pruned.is_empty());
    if (!full.is_empty()) RC_ASSERT(!intersect(full, pruned).is_empty());
    const Interval fi = eval<Interval>(t, intervals(box));
    const Interval pi = eval<Interval>(p.tape, intervals(box));
    RC_ASSERT(contains(fi, pi));
}

RC_GTEST_PROP(EvalProperty, LipschitzBoundHoldsBetweenPointsOfTheBox, ()) {
    const Graph g = *testing::gen_dag();
    const Tape t(g);
    // Moderate boxes: an infinite bound holds trivially and says nothing.
    std::array<Interval, 3> box;
    std::array<double, 3> p, q;
    for (int i = 0; i < 3; ++i) {
        const double lo = *rc::gen::inRange(-400, 400) / 100.0;
        const double w = *rc::gen::inRange(1, 200) / 100.0;
        box[i] = Interval(lo, lo + w);
        p[i] = *testing::gen_point_in(lo, lo + w);
        q[i] = *testing::gen_point_in(lo, lo + w);
    }
    const double lambda = lipschitz_bound(t, box);
    RC_PRE(std::isfinite(lambda));
    // |f(p) − f(q)| ≤ λ‖p − q‖, decided in MPFR at 256 bits (a finite λ means f is defined).
    RC_ASSERT(testing::lipschitz_holds(t, lambda, p, q));
}

}  // namespace
}  // namespace certray::expr
