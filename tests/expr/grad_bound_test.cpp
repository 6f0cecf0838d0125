// tests/expr/grad_bound_test.cpp — Lipschitz bounds with root forms (interval/grad_bound.h):
// the constants mathematics gives for Euclidean distances, and |f(p) − f(q)| ≤ λ‖p − q‖ in MPFR on
// random distance-like DAGs whose square roots may vanish inside the box.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "expr/builder.h"
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

}  // namespace
}  // namespace certray::expr
