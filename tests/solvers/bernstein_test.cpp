// tests/solvers/bernstein_test.cpp — certified Bernstein/Bézier-clipping roots against the roots
// mathematics gives: products of linear factors with rational roots p/q, coefficients enclosed by
// interval products (so the exact polynomial is in the family), hand cases and a property.
#include "solvers/bernstein.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace certray::solvers {
namespace {

struct Rational {
    double p, q;  // exact small integers
    double approx() const { return p / q; }
};

/// Enclosures of the coefficients of Π (t − p_i/q_i)·(t² + 1)^extra.
std::vector<Interval> poly(const std::vector<Rational>& roots, int extra = 0) {
    std::vector<Interval> c{Interval(1.0)};
    auto mul = [&](const std::vector<Interval>& f) {
        std::vector<Interval> r(c.size() + f.size() - 1, Interval(0.0));
        for (std::size_t i = 0; i < c.size(); ++i)
            for (std::size_t j = 0; j < f.size(); ++j) r[i + j] = r[i + j] + c[i] * f[j];
        c = r;
    };
    for (const Rational& x : roots) mul({-(Interval(x.p) / Interval(x.q)), Interval(1.0)});
    for (int k = 0; k < extra; ++k) mul({Interval(1.0), Interval(0.0), Interval(1.0)});
    return c;
}

/// r = p/q lies in [lo, hi] (exact test: lo·q ≤ p ≤ hi·q in interval arithmetic).
bool in(const Rational& r, double lo, double hi) {
    return certainly_le(Interval(lo) * Interval(r.q), Interval(r.p)) &&
           certainly_le(Interval(r.p), Interval(hi) * Interval(r.q));
}
bool le(double x, const Rational& r) {
    return certainly_le(Interval(x) * Interval(r.q), Interval(r.p));
}

TEST(Bernstein, CubicFirstRoot) {
    const auto c = poly({{1, 4}, {1, 2}, {3, 4}});
    RayResult r = first_root_bernstein(c, 0, 1);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_TRUE(in({1, 4}, r.t_lo, r.t_hi));
    EXPECT_LE(r.t_hi - r.t_lo, 1e-15);
    r = first_root_bernstein(c, 0.3, 1);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_TRUE(in({1, 2}, r.t_lo, r.t_hi));
    r = first_root_bernstein(c, 0.8, 5);
    EXPECT_EQ(r.status, Status::Miss);
}

TEST(Bernstein, NoRealRoot) {
    const std::vector<Interval> c{Interval(1.0), Interval(0.0), Interval(1.0)};  // t² + 1
    EXPECT_EQ(first_root_bernstein(c, -10, 10).status, Status::Miss);
    EXPECT_EQ(first_root_bernstein(c, 0, std::numeric_limits<double>::infinity()).status,
              Status::Miss);
}

TEST(Bernstein, DoubleRootNeverMiss) {
    // (t − 0.5)² and (t − 1/3)² (the latter not exact in binary)
    for (const Rational x : {Rational{1, 2}, Rational{1, 3}}) {
        const auto c = poly({x, x});
        const RayResult r = first_root_bernstein(c, 0, 1);
        ASSERT_NE(r.status, Status::Miss);
        if (r.status == Status::Hit) {
            EXPECT_TRUE(in(x, r.t_lo, r.t_hi));
        }
        EXPECT_TRUE(le(r.t_lo, x));
    }
}

TEST(Bernstein, WideCoefficientsNotHit) {
    // t² − e with e ∈ [−0.01, 0.01]: contains t² + 0.01 (no root) and t² − 0.01 (root 0.1).
    const std::vector<Interval> c{Interval(-0.01, 0.01), Interval(0.0), Interval(1.0)};
    const RayResult r = first_root_bernstein(c, 0, 1);
    EXPECT_EQ(r.status, Status::Unknown);
    EXPECT_LE(r.t_lo, 0.0);  // the member t² has its root at 0
}

TEST(Bernstein, ClusteredDegree10) {
    // roots 1/2 + k·1e-10 written as (5e9 + k)/1e10 (exact integers), k = 0..9
    std::vector<Rational> roots;
    for (int k = 0; k < 10; ++k) roots.push_back({5e9 + k, 1e10});
    const auto c = poly(roots);
    const RayResult r = first_root_bernstein(c, 0, 1);
    ASSERT_NE(r.status, Status::Miss);
    EXPECT_TRUE(le(r.t_lo, roots[0]));
    if (r.status == Status::Hit) {
        EXPECT_TRUE(in(roots[0], r.t_lo, r.t_hi));
    }
    std::printf("clustered degree 10: %s [%.17g, %.17g]\n", std::string(name(r.status)).c_str(),
                r.t_lo, r.t_hi);
}

TEST(Bernstein, InfiniteEnds) {
    const auto c = poly({{-7, 2}, {5, 1}});
    const double inf = std::numeric_limits<double>::infinity();
    RayResult r = first_root_bernstein(c, 0, inf);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_TRUE(in({5, 1}, r.t_lo, r.t_hi));
    r = first_root_bernstein(c, -inf, inf);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_TRUE(in({-7, 2}, r.t_lo, r.t_hi));
    EXPECT_EQ(first_root_bernstein(c, 5.5, inf).status, Status::Miss);
}

TEST(Bernstein, Timing) {
    for (int deg : {4, 6, 10}) {
        std::vector<Rational> roots;
        for (int k = 0; k < deg; ++k) roots.push_back({double(3 * k + 1), 7});
        const auto c = poly(roots);
        const int reps = 2000;
        const auto t0 = std::chrono::steady_clock::now();
        RayResult r;
        for (int i = 0; i < reps; ++i) r = first_root_bernstein(c, 0.05 * (i % 3), 100);
        const double us =
            std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0)
                .count() /
            reps;
        EXPECT_EQ(r.status, Status::Hit);
        unsigned steps = 1;  // fewest steps that reach the same proof
        while (first_root_bernstein(c, 0.1, 100, {steps}).t_hi !=
               first_root_bernstein(c, 0.1, 100).t_hi)
            ++steps;
        std::printf("degree %d: %.2f us per solve, %u steps\n", deg, us, steps);
    }
}

RC_GTEST_PROP(Bernstein, AgreesWithKnownRoots, ()) {
    const int k = *rc::gen::inRange(1, 7);
    std::vector<Rational> roots;
    for (int i = 0; i < k; ++i) {
        if (i > 0 && *rc::gen::inRange(0, 5) == 0) {  // sometimes a double root
            roots.push_back(roots[*rc::gen::inRange(0, i)]);
            continue;
        }
        const int q = *rc::gen::inRange(1, 65);
        roots.push_back({double(*rc::gen::inRange(-12 * q, 12 * q + 1)), double(q)});
    }
    const int extra = *rc::gen::inRange(0, 2);
    const auto c = poly(roots, extra);
    double tmin = *rc::gen::inRange(-1200, 1200) / 100.0;
    double tmax = tmin + *rc::gen::inRange(0, 2400) / 100.0;
    const RayResult r = first_root_bernstein(c, tmin, tmax);
    // first known root in [tmin, tmax] (p/q with q > 0: compare p1·q2 < p2·q1, exact)
    const Rational* first = nullptr;
    for (const Rational& x : roots)
        if (in(x, tmin, tmax) && (!first || x.p * first->q < first->p * x.q)) first = &x;
    RC_CLASSIFY(r.status == Status::Hit, "hit");
    RC_CLASSIFY(r.status == Status::Miss, "miss");
    RC_CLASSIFY(r.status == Status::Unknown, "unknown");
    if (r.status == Status::Miss) {
        RC_ASSERT(first == nullptr);
    } else if (r.status == Status::Hit) {
        RC_ASSERT(first != nullptr);
        RC_ASSERT(in(*first, r.t_lo, r.t_hi));
    } else if (first) {
        RC_ASSERT(le(r.t_lo, *first));
    }
}

}  // namespace
}  // namespace certray::solvers
