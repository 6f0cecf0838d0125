// tests/solvers/analytic_test.cpp — piecewise-polynomial first roots (closed forms and certified
// Bernstein isolation) against roots mathematics gives: quadrics, the torus, a blob field, CSG of
// polynomials, and a property on random polynomials with known roots.
#include "solvers/analytic.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "expr/parser.h"
#include "expr/tape.h"
#include "tests/support/generators.h"

namespace certray::solvers {
namespace {

using expr::Tape;
using Mode = AnalyticOptions::Mode;
constexpr double kInf = std::numeric_limits<double>::infinity();

Tape tape_of(const char* text) { return Tape(expr::parse_expr(text)); }

RayResult solve(const Tape& t, Ray ray, Mode mode) {
    AnalyticOptions o;
    o.mode = mode;
    return analytic_first_root(t, ray, o);
}

/// Bernstein hits are proofs: the enclosure holds the root. Closed-form hits are points: within
/// `tol` of it.
void expect_root(const RayResult& r, Mode mode, double root, double tol = 1e-12) {
    ASSERT_EQ(r.status, Status::Hit);
    if (mode == Mode::Bernstein) {
        EXPECT_LE(r.t_lo, root);
        EXPECT_GE(r.t_hi, root);
        EXPECT_LE(r.t_hi - r.t_lo, 1e-12 * std::max(1.0, std::fabs(root)));
    } else {
        EXPECT_NEAR(r.t, root, tol * std::max(1.0, std::fabs(root)));
    }
}

class Analytic : public ::testing::TestWithParam<Mode> {};

TEST_P(Analytic, QuadricsAndTheTorus) {
    const Mode m = GetParam();
    const Tape sphere = tape_of("x^2 + y^2 + z^2 - 1");
    expect_root(solve(sphere, Ray{{0, 0, -3}, {0, 0, 1}, 0, kInf}, m), m, 2.0);
    expect_root(solve(sphere, Ray{{0, 0, 0}, {1, 0, 0}, 0, 10}, m), m, 1.0);  // from inside
    EXPECT_EQ(solve(sphere, Ray{{0, 5, 0}, {1, 0, 0}, -10, 10}, m).status, Status::Miss);
    EXPECT_EQ(solve(sphere, Ray{{0, 0, -3}, {0, 0, 1}, 0, 1.5}, m).status, Status::Miss);
    // Ellipsoid x²/4 + y² + z² = 1 along +x from −5: root 3.
    expect_root(solve(tape_of("x^2 / 4 + y^2 + z^2 - 1"), Ray{{-5, 0, 0}, {1, 0, 0}, 0, 10}, m), m,
                3.0);
    // Torus R = 1, r = 0.5 (exact constants) in polynomial form along +x from −3: roots 1.5, 2.5,
    // 3.5, 4.5.
    const Tape torus = tape_of("(x^2 + y^2 + z^2 + 0.75)^2 - 4 * (x^2 + y^2)");
    expect_root(solve(torus, Ray{{-3, 0, 0}, {1, 0, 0}, 0, 10}, m), m, 1.5);
    expect_root(solve(torus, Ray{{-3, 0, 0}, {1, 0, 0}, 2, 10}, m), m, 2.5);
}

TEST_P(Analytic, BlobFieldSplitsAtKernelSupports) {
    const Mode m = GetParam();
    // One Wyvill kernel: 0.5 − max(1 − r², 0)³ along +x from (−3, 0, 0): root t = 3 − √(1 −
    // 2^(−1/3)).
    const Tape blob = tape_of("0.5 - max(1 - (x^2 + y^2 + z^2), 0)^3");
    const RayResult r = solve(blob, Ray{{-3, 0, 0}, {1, 0, 0}, 0, 10}, m);
    mpfr_t s;
    mpfr_init2(s, 200);
    mpfr_set_ui(s, 2, MPFR_RNDN);
    mpfr_cbrt(s, s, MPFR_RNDN);
    mpfr_ui_div(s, 1, s, MPFR_RNDN);
    mpfr_ui_sub(s, 1, s, MPFR_RNDN);
    mpfr_sqrt(s, s, MPFR_RNDN);
    mpfr_ui_sub(s, 3, s, MPFR_RNDN);
    const double root = mpfr_get_d(s, MPFR_RNDN);
    ASSERT_EQ(r.status, Status::Hit);
    if (m == Mode::Bernstein) {
        EXPECT_LE(mpfr_cmp_d(s, r.t_hi), 0);
        EXPECT_GE(mpfr_cmp_d(s, r.t_lo), 0);
    } else {
        EXPECT_NEAR(r.t, root, 1e-12);
    }
    mpfr_clear(s);
    // A ray that passes outside the kernel's support: the field is 0.5 there.
    EXPECT_EQ(solve(blob, Ray{{-3, 2, 0}, {1, 0, 0}, 0, 10}, m).status, Status::Miss);
}

TEST_P(Analytic, CsgOfPolynomials) {
    const Mode m = GetParam();
    // Union of unit spheres at x = 0 and x = 1.5, seen along +x from −3: first root 2; from
    // inside the first, past their intersection (x = 0.75): the second's far side at x = 2.5.
    const Tape u = tape_of("min(x^2 + y^2 + z^2 - 1, (x - 1.5)^2 + y^2 + z^2 - 1)");
    expect_root(solve(u, Ray{{-3, 0, 0}, {1, 0, 0}, 0, 10}, m), m, 2.0);
    expect_root(solve(u, Ray{{0, 0, 0}, {1, 0, 0}, 0, 10}, m), m, 2.5);
    // Difference: the unit sphere minus the slab |z| < 0.5, down the z axis from above: root 2.
    const Tape d = tape_of("max(x^2 + y^2 + z^2 - 1, 0.25 - z^2)");
    expect_root(solve(d, Ray{{0, 0, 3}, {0, 0, -1}, 0, 10}, m), m, 2.0);
    // ... and along the x axis (inside the slab): a miss.
    EXPECT_EQ(solve(d, Ray{{-3, 0, 0}, {1, 0, 0}, 0, 10}, m).status, Status::Miss);
}

TEST_P(Analytic, DegenerateRays) {
    const Mode m = GetParam();
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    EXPECT_EQ(solve(s, Ray{{0, 0, 0}, {0, 0, 0}, 0, 1}, m).status, Status::Miss);
    const RayResult on = solve(s, Ray{{1, 0, 0}, {0, 0, 0}, 0, 5}, m);
    ASSERT_EQ(on.status, Status::Hit);
    EXPECT_EQ(on.t, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Modes, Analytic, ::testing::Values(Mode::ClosedForm, Mode::Bernstein),
                         [](const auto& param_info) {
                             return param_info.param == Mode::ClosedForm ? "ClosedForm"
                                                                         : "Bernstein";
                         });

TEST(AnalyticScope, WhyNotPolynomialNamesTheOperation) {
    EXPECT_EQ(why_not_polynomial(tape_of("x^2 + sqrt(2) * y - 1 / 3")), "");
    EXPECT_EQ(why_not_polynomial(tape_of("min(x, y) - abs(z)")), "");
    EXPECT_NE(why_not_polynomial(tape_of("sqrt(x^2 + y^2) - 1")).find("sqrt"), std::string::npos);
    EXPECT_NE(why_not_polynomial(tape_of("1 / x")).find("division"), std::string::npos);
    EXPECT_NE(why_not_polynomial(tape_of("sin(x + 1)")).find("sin"), std::string::npos);
}

// g(t) = Π (t − rᵢ) with dyadic roots rᵢ = kᵢ / 64 along x: the certified mode encloses the first
// root in range (or says unknown, never a wrong miss); the closed forms are within 1e-9 of it.
RC_GTEST_PROP(AnalyticProperty, PolynomialWithKnownRoots, ()) {
    const auto [text, roots] = *testing::gen_root_product(6);
    const double tmin = *rc::gen::inRange(-300, 300) / 64.0 + 1.0 / 128;  // never on a root
    const double tmax = tmin + *rc::gen::inRange(0, 400) / 64.0;
    const Tape t(expr::parse_expr(text));
    double first = kInf;
    for (double r : roots) {
        if (r >= tmin && r <= tmax) first = std::min(first, r);
    }
    const Ray ray{{0, 0, 0}, {1, 0, 0}, tmin, tmax};
    const RayResult b = solve(t, ray, Mode::Bernstein);
    if (b.status == Status::Miss) RC_ASSERT(first == kInf);
    if (b.status == Status::Hit) RC_ASSERT(b.t_lo <= first && first <= b.t_hi);
    if (b.status == Status::Unknown) RC_ASSERT(first == kInf || b.t_lo <= first);
    // Simple roots are always proven.
    int mult = 0;
    for (double r : roots) mult += r == first;
    if (first != kInf && mult == 1) RC_ASSERT(b.status == Status::Hit);
    const RayResult c = solve(t, ray, Mode::ClosedForm);
    if (first != kInf && mult == 1 && roots.size() <= 4) {
        RC_ASSERT(c.status == Status::Hit);
        RC_ASSERT(std::fabs(c.t - first) <= 1e-9);
    }
}

}  // namespace
}  // namespace certray::solvers
