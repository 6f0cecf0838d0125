// tests/expr/grad_bound_test.cpp — Lipschitz bounds with root forms (interval/grad_bound.h):
// the constants mathematics gives for Euclidean distances, and |f(p) − f(q)| ≤ λ‖p − q‖ in MPFR on
// random distance-like DAGs whose square roots may vanish inside the box; and the smooth blends
// of Lipschitz-Pruning's trees (expr/derived.h): 1-Lipschitz through any chain of them, recognised
// only in their exact form.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "expr/builder.h"
#include "expr/csg_shapes.h"
#include "expr/derived.h"
#include "expr/eval.h"
#include "expr/tape.h"
#include "interval/mpfr_interval.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"

namespace certray::expr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The tape of f (sets f as its graph's output).
Tape tape_of(const Expr& f) {
    f.graph->set_output(f.id);
    return Tape(*f.graph);
}

std::array<Interval, 3> cube(double lo, double hi) {
    return {Interval(lo, hi), Interval(lo, hi), Interval(lo, hi)};
}

TEST(RootForm, EuclideanDistancesAreOneLipschitzThroughTheirZero) {
    Graph g;
    auto [x, y, z] = vars(g);
    // ‖p − c‖ − r: ‖∇‖ = 1 wherever defined, so the best bound is 1 — and 1 is what we get.
    const Tape ball = tape_of(sqrt(square(x - 0.3) + square(y + 0.2) + square(z)) - 1.05);
    EXPECT_EQ(lipschitz_bound(ball, cube(-2, 2)), 1.0);
    const Tape stick = tape_of(sqrt(square(x) + square(y)) - 0.25);
    EXPECT_EQ(lipschitz_bound(stick, cube(-1, 1)), 1.0);
    // pow(·, 2) is a square too.
    const Tape powered = tape_of(sqrt(pow(x, 2) + pow(y, 2) + pow(z, 2)));
    EXPECT_EQ(lipschitz_bound(powered, cube(-1, 1)), 1.0);
    // A union and a difference of distances: still 1.
    const Tape csg = tape_of(max(min(sqrt(square(x) + square(y) + square(z)) - 1.0,
                                     sqrt(square(x - 2.0) + square(y) + square(z)) - 0.5),
                                 -(sqrt(square(x) + square(y)) - 0.25)));
    EXPECT_EQ(lipschitz_bound(csg, cube(-3, 3)), 1.0);
}

TEST(RootForm, ScaledDistancesGiveTheirLargestAxisScale) {
    Graph g;
    auto [x, y, z] = vars(g);
    // √((x/2)² + (3y)² + z²): ‖∇‖ ≤ 3 (the largest singular value of diag(1/2, 3, 1)), reached
    // along y. The bound must be at least 3 and, from Gram diag(1/4, 9, 1), is 3 up to rounding.
    const Tape t = tape_of(sqrt(square(x / 2.0) + 9.0 * square(y) + square(z)));
    const double l = lipschitz_bound(t, cube(-1, 1));
    EXPECT_GE(l, 3.0);
    EXPECT_LE(l, 3.0 * (1 + 1e-15));
    // A rotation by 45° about z: (x ± y)/√2 are orthonormal coordinates; the Gram matrix of
    // ((x + y)·s, (x − y)·s) with s = 0.5 is diag(0.5, 0.5) exactly, so λ = √0.5.
    const Tape rot = tape_of(sqrt(square((x + y) * 0.5) + square((x - y) * 0.5)));
    EXPECT_EQ(lipschitz_bound(rot, cube(-1, 1)), std::sqrt(0.5));
}

TEST(RootForm, NoFormNoClaim) {
    Graph g;
    auto [x, y, z] = vars(g);
    // √x is not Lipschitz at 0; neither is √(x² − y²) near its zero (a difference, no form),
    // nor ∛-like √|x|.
    EXPECT_EQ(lipschitz_bound(tape_of(sqrt(x) + 0.0 * z), cube(0, 1)), kInf);
    EXPECT_EQ(lipschitz_bound(tape_of(sqrt(abs(x)) + y), cube(-1, 1)), kInf);
    EXPECT_EQ(lipschitz_bound(tape_of(sqrt(square(x) - square(y) + 1.0)), cube(-1, 1)), kInf);
    // A negative constant added to a sum of squares breaks the form (the sum may reach 0 only
    // where √ is undefined, and no claim is made).
    EXPECT_EQ(lipschitz_bound(tape_of(sqrt(square(x) + square(y) - 0.5)), cube(-1, 1)), kInf);
}

/// A random distance-like expression: Euclidean norms of random affine maps, their smooth
/// compositions, unions, intersections, scalings and offsets.
rc::Gen<Graph> gen_distance_dag() {
    return rc::gen::exec([] {
        Graph g;
        auto [x, y, z] = vars(g);
        const std::array<Expr, 3> v{x, y, z};
        auto coef = [] { return *rc::gen::inRange(-8, 9) / 4.0; };
        auto affine = [&] {
            Expr e = v[*rc::gen::inRange(0, 3)] * coef();
            for (int k = 0; k < 2; ++k) e = e + v[*rc::gen::inRange(0, 3)] * coef();
            return e + coef();
        };
        auto norm = [&] {
            const int terms = *rc::gen::inRange(1, 4);
            Expr s = *rc::gen::element(0, 1) ? square(affine()) : pow(affine(), 2);
            for (int k = 1; k < terms; ++k) s = s + square(affine());
            switch (*rc::gen::inRange(0, 4)) {
                case 0:
                    s = s * std::fabs(coef());
                    break;
                case 1:
                    s = s / (std::fabs(coef()) + 0.5);
                    break;
                case 2:
                    s = min(s, square(affine()) + square(affine()));
                    break;
                default:
                    s = s + std::fabs(coef());
            }
            return sqrt(s) - std::fabs(coef());
        };
        Expr f = norm();
        const int more = *rc::gen::inRange(0, 4);
        for (int k = 0; k < more; ++k) {
            switch (*rc::gen::inRange(0, 5)) {
                case 0:
                    f = min(f, norm());
                    break;
                case 1:
                    f = max(f, -norm());
                    break;
                case 2:
                    f = abs(f) - 0.1;
                    break;
                case 3:
                    f = f * coef() + norm();
                    break;
                default:
                    f = sin(f) + x * coef();
            }
        }
        g.set_output(f.id);
        return g;
    });
}

RC_GTEST_PROP(RootFormProperty, LipschitzBoundHoldsBetweenPointsOfTheBox, ()) {
    const Graph g = *gen_distance_dag();
    const Tape t(g);
    std::array<Interval, 3> box;
    std::array<double, 3> p, q;
    for (int i = 0; i < 3; ++i) {
        const double lo = *rc::gen::inRange(-300, 300) / 100.0;
        const double w = *rc::gen::inRange(1, 400) / 100.0;
        box[i] = Interval(lo, lo + w);
        p[i] = *testing::gen_point_in(lo, lo + w);
        // Pairs close together probe the local slope (where a loose bound would first fail).
        q[i] = *rc::gen::element(0, 1)
                   ? *testing::gen_point_in(lo, lo + w)
                   : std::clamp(p[i] + *rc::gen::inRange(-100, 100) * 1e-6, lo, lo + w);
    }
    const double lambda = lipschitz_bound(t, box);
    RC_PRE(std::isfinite(lambda));
    // |f(p) − f(q)| ≤ λ‖p − q‖, decided in MPFR at 256 bits (a finite λ means f is defined).
    RC_ASSERT(testing::lipschitz_holds(t, lambda, p, q));
}

/// The distance to the ball of centre c and radius r, as Lipschitz-Pruning's sphere writes it.
Expr ball(const Expr& x, const Expr& y, const Expr& z, std::array<double, 3> c, double r) {
    return csg::sphere({x - c[0], y - c[1], z - c[2]}, r);
}

// A smooth union, intersection or difference of 1-Lipschitz functions is 1-Lipschitz (its
// gradient is a convex combination of the operands'), whatever the depth: a chain of 300 blends
// of balls has the bound 1 — which the root forms give each ball — and not 2³⁰⁰.
TEST(SmoothBlend, ChainsOfBlendsAreOneLipschitz) {
    for (const csg::Blend mode : {csg::Blend::Union, csg::Blend::Inter, csg::Blend::Sub}) {
        Graph g;
        auto [x, y, z] = vars(g);
        Expr f = ball(x, y, z, {0, 0, 0}, 0.5);
        for (int i = 1; i < 300; ++i) {
            const double a = 0.021 * i;
            f = csg::blend(mode, 0.05 + 0.001 * (i % 7), f,
                           ball(x, y, z, {std::cos(a), std::sin(a), 0.003 * i}, 0.2));
        }
        const Tape t = tape_of(f);
        EXPECT_EQ(smooth_blends(t.ssa()).size(), 299u);
        EXPECT_EQ(lipschitz_bound(t, cube(-2, 2)), 1.0) << static_cast<int>(mode);
        EXPECT_EQ(lipschitz_bound(t, cube(0.1, 0.3)), 1.0) << static_cast<int>(mode);
    }
}

// Only the exact blend is recognised: its look-alikes whose weights do not lie in [0, 1] (a max
// minus the kernel, a min plus it), a kernel over another difference or with c ≠ 4k, and k ≤ 0.
TEST(SmoothBlend, OnlyTheExactFormIsRecognised) {
    Graph g;
    auto [x, y, z] = vars(g);
    const Expr a = ball(x, y, z, {0, 0, 0}, 0.5), b = ball(x, y, z, {0.6, 0, 0}, 0.4);
    const Expr c = ball(x, y, z, {0, 0.6, 0}, 0.3);
    auto kernel = [](const Expr& d, double k, double div) {
        return square(max(k - abs(d), 0.0)) / div;
    };
    auto count = [&](const Expr& f) {
        const Tape t = tape_of(f);
        return smooth_blends(t.ssa()).size();
    };
    EXPECT_EQ(count(min(a, b) - kernel(a - b, 0.1, 0.4)), 1u);
    EXPECT_EQ(count(min(a, b) - kernel(b - a, 0.1, 0.4)), 1u);
    EXPECT_EQ(count(kernel(a - b, 0.1, 0.4) + max(a, b)), 1u);
    EXPECT_EQ(count(max(a, b) - kernel(a - b, 0.1, 0.4)), 0u);
    EXPECT_EQ(count(min(a, b) + kernel(a - b, 0.1, 0.4)), 0u);
    EXPECT_EQ(count(min(a, b) - kernel(a - c, 0.1, 0.4)), 0u);
    EXPECT_EQ(count(min(a, b) - kernel(a - b, 0.1, 0.5)), 0u);
    EXPECT_EQ(count(min(a, b) - kernel(a - b, -0.1, -0.4)), 0u);
    EXPECT_EQ(count(min(a, b) - square(max(0.1 - abs(a - b), 0.1)) / 0.4), 0u);

    // Of x and −x, the blend's slope is at most 1 (its bound: 1), while the look-alike
    // max(x, −x) − K(|2x|) has slope 1 + (k − 2|x|)/k, up to 2 near 0: any sound bound is ≥ 2.
    const Expr blend = min(x, -x) - kernel(x - (-x), 0.2, 0.8);
    EXPECT_EQ(lipschitz_bound(tape_of(blend), cube(-0.5, 0.5)), 1.0);
    const Expr fake = max(x, -x) - kernel(x - (-x), 0.2, 0.8);
    EXPECT_GE(lipschitz_bound(tape_of(fake), cube(-0.5, 0.5)), 2.0);
}

/// A random tree of balls joined by exact blends and by their look-alikes (a max minus the
/// kernel: weights up to 3/2, so a bound of 1 would be wrong for it).
rc::Gen<Graph> gen_blend_dag() {
    return rc::gen::exec([] {
        Graph g;
        auto [x, y, z] = vars(g);
        auto coord = [] { return *rc::gen::inRange(-60, 61) / 100.0; };
        auto leaf = [&] {
            return ball(x, y, z, {coord(), coord(), coord()}, *rc::gen::inRange(5, 80) / 100.0);
        };
        Expr f = leaf();
        const int n = *rc::gen::inRange(1, 12);
        for (int i = 0; i < n; ++i) {
            const double k = *rc::gen::inRange(1, 100) / 100.0;
            const Expr b = leaf();
            switch (*rc::gen::inRange(0, 4)) {
                case 0:
                    f = csg::blend(csg::Blend::Union, k, f, b);
                    break;
                case 1:
                    f = csg::blend(csg::Blend::Inter, k, f, b);
                    break;
                case 2:
                    f = csg::blend(csg::Blend::Sub, k, f, b);
                    break;
                default:
                    f = max(f, b) - square(max(k - abs(f - b), 0.0)) / (4 * k);
            }
        }
        g.set_output(f.id);
        return g;
    });
}

RC_GTEST_PROP(SmoothBlendProperty, LipschitzBoundHoldsBetweenPointsOfTheBox, ()) {
    const Graph g = *gen_blend_dag();
    const Tape t(g);
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) {
        const double lo = *rc::gen::inRange(-200, 200) / 100.0;
        box[i] = Interval(lo, lo + *rc::gen::inRange(1, 300) / 100.0);
    }
    const double lambda = lipschitz_bound(t, box);
    RC_PRE(std::isfinite(lambda));
    // Twenty pairs per tree, most of them close together (the slope a wrong bound would miss).
    for (int pair = 0; pair < 20; ++pair) {
        std::array<double, 3> p, q;
        const bool near = *rc::gen::inRange(0, 4) != 0;
        for (int i = 0; i < 3; ++i) {
            const double lo = box[i].lower(), hi = box[i].upper();
            p[i] = *testing::gen_point_in(lo, hi);
            q[i] = near ? std::clamp(p[i] + *rc::gen::inRange(-100, 100) * 1e-4, lo, hi)
                        : *testing::gen_point_in(lo, hi);
        }
        // |f(p) − f(q)| ≤ λ‖p − q‖, decided in MPFR at 256 bits.
        RC_ASSERT(testing::lipschitz_holds(t, lambda, p, q));
    }
}

}  // namespace
}  // namespace certray::expr
