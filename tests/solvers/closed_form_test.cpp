// tests/solvers/closed_form_test.cpp — closed-form roots of degree ≤ 4 against the roots
// mathematics gives: hand-made cases and random roots whose polynomial is formed exactly in MPFR.
//
// Error bound of the property: a simple real root r of the double polynomial p̃ (the exact
// polynomial's coefficients rounded to nearest) has relative condition number
// κ(r) = Σ|a_k||r|^k / (|r|·|p'(r)|); rounding the coefficients moves r by ≤ κ·ε/2 relative (to
// first order), the solver adds its own backward error. Asserted: |computed − r| ≤
// (kCondFactor·κ + 4)·ε·|r|, and the exact root count, whenever every root z (complex ones too)
// has κ(z)·ε < 1e-4 and 64·κ(z)·ε below its relative distance to the nearest other root;
// otherwise (clustered roots, a nearly real complex pair) the rounded coefficients may have a
// different number of real roots and the linearised bound does not apply: nothing is asserted.
#include "solvers/closed_form.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <vector>

namespace certray::solvers {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kCondFactor = 8.0;

double ulps_apart(double x, double y) { return std::abs(x - y) / (std::abs(y) * kEps); }

TEST(ClosedForm, QuadraticDistinctRoots) {
    double r[2];
    ASSERT_EQ(solve_quadratic(1, -3, 2, r), 2);  // (t − 1)(t − 2)
    EXPECT_EQ(r[0], 1.0);
    EXPECT_EQ(r[1], 2.0);
    ASSERT_EQ(solve_quadratic(-2, 0, 8, r), 2);  // −2(t − 2)(t + 2)
    EXPECT_EQ(r[0], -2.0);
    EXPECT_EQ(r[1], 2.0);
}

TEST(ClosedForm, QuadraticWidelySeparatedRootsKeepRelativeAccuracy) {
    // (t − 1e-8)(t − 1e8): the small root is lost to cancellation by the textbook formula.
    double r[2];
    ASSERT_EQ(solve_quadratic(1, -(1e8 + 1e-8), 1e-8 * 1e8, r), 2);
    EXPECT_LE(ulps_apart(r[0], 1e-8), 4);
    EXPECT_LE(ulps_apart(r[1], 1e8), 4);
    ASSERT_EQ(solve_quadratic(1, 1e8 + 1e-8, 1e-8 * 1e8, r), 2);  // the mirror image
    EXPECT_LE(ulps_apart(r[0], -1e8), 4);
    EXPECT_LE(ulps_apart(r[1], -1e-8), 4);
}

TEST(ClosedForm, QuadraticDoubleRootAndNearTangency) {
    double r[2];
    ASSERT_EQ(solve_quadratic(1, -6, 9, r), 2);  // (t − 3)²
    EXPECT_EQ(r[0], 3.0);
    EXPECT_EQ(r[1], 3.0);
    // t² − 2(1 + 2⁻²⁷)t + (1 + 2⁻²⁶) = (t − 1)(t − 1 − 2⁻²⁶): b² needs 55 bits, so a naive
    // discriminant rounds to 0 and reports a double root at 1 + 2⁻²⁷.
    const double u = std::ldexp(1.0, -27);
    ASSERT_EQ(solve_quadratic(1, -2 * (1 + u), 1 + 2 * u, r), 2);
    EXPECT_EQ(r[0], 1.0);
    EXPECT_EQ(r[1], 1.0 + 2 * u);
    // Raise c by 2⁻⁵²: b²/4 − c = 2⁻⁵⁴ − 2⁻⁵² < 0, no real root.
    EXPECT_EQ(solve_quadratic(1, -2 * (1 + u), 1 + 2 * u + std::ldexp(1.0, -52), r), 0);
}

TEST(ClosedForm, DegenerateLeadingCoefficients) {
    double r[4];
    bool all_zero = true;
    ASSERT_EQ(solve_quadratic(0, 2, -3, r, &all_zero), 1);
    EXPECT_EQ(r[0], 1.5);
    EXPECT_FALSE(all_zero);
    EXPECT_EQ(solve_quadratic(0, 0, 5, r, &all_zero), 0);
    EXPECT_FALSE(all_zero);
    EXPECT_EQ(solve_quartic(0, 0, 0, 0, 0, r, &all_zero), 0);
    EXPECT_TRUE(all_zero);
    ASSERT_EQ(solve_quartic(0, 1, -6, 11, -6, r), 3);  // a cubic
    EXPECT_EQ(r[0], 1.0);
    EXPECT_EQ(r[1], 2.0);
    EXPECT_EQ(r[2], 3.0);
    EXPECT_EQ(solve_cubic(1, 0, 0, std::nan(""), r), 0);
}

TEST(ClosedForm, Cubic) {
    double r[3];
    ASSERT_EQ(solve_cubic(1, -6, 11, -6, r), 3);  // (t − 1)(t − 2)(t − 3)
    EXPECT_LE(ulps_apart(r[0], 1), 4);
    EXPECT_LE(ulps_apart(r[1], 2), 4);
    EXPECT_LE(ulps_apart(r[2], 3), 4);
    ASSERT_EQ(solve_cubic(2, 0, 2, -4, r), 1);  // 2(t − 1)(t² + t + 2)
    EXPECT_LE(ulps_apart(r[0], 1), 4);
    ASSERT_EQ(solve_cubic(1, -5, 7, -3, r), 3);  // (t − 1)²(t − 3)
    EXPECT_NEAR(r[0], 1, 1e-7);
    EXPECT_NEAR(r[1], 1, 1e-7);
    EXPECT_LE(ulps_apart(r[2], 3), 4);
    ASSERT_EQ(solve_cubic(1, -3, 3, -1, r), 3);  // (t − 1)³
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], 1, 1e-5);
    ASSERT_EQ(solve_cubic(1, 0, -1, 0, r), 3);  // t(t − 1)(t + 1)
    EXPECT_EQ(r[0], -1.0);
    EXPECT_EQ(r[1], 0.0);
    EXPECT_EQ(r[2], 1.0);
}

TEST(ClosedForm, QuarticRealRootCounts) {
    double r[4];
    ASSERT_EQ(solve_quartic(1, -10, 35, -50, 24, r), 4);  // (t − 1)(t − 2)(t − 3)(t − 4)
    for (int i = 0; i < 4; ++i) EXPECT_LE(ulps_apart(r[i], i + 1), 4);
    ASSERT_EQ(solve_quartic(1, 1, -1, 1, -2, r), 2);  // (t² + 1)(t − 1)(t + 2)
    EXPECT_LE(ulps_apart(r[0], -2), 4);
    EXPECT_LE(ulps_apart(r[1], 1), 4);
    EXPECT_EQ(solve_quartic(1, 0, 5, 0, 4, r), 0);   // (t² + 1)(t² + 4)
    EXPECT_EQ(solve_quartic(1, 0, 0, 0, 1, r), 0);   // t⁴ + 1
    ASSERT_EQ(solve_quartic(1, 0, -5, 0, 4, r), 4);  // (t² − 1)(t² − 4): biquadratic
    EXPECT_EQ(r[0], -2.0);
    EXPECT_EQ(r[1], -1.0);
    EXPECT_EQ(r[2], 1.0);
    EXPECT_EQ(r[3], 2.0);
    // A torus-like quartic (t² + 3)² − 16t² = (t − 1)(t + 1)(t − 3)(t + 3).
    ASSERT_EQ(solve_quartic(1, 0, -10, 0, 9, r), 4);
    EXPECT_EQ(r[0], -3.0);
    EXPECT_EQ(r[3], 3.0);
}

TEST(ClosedForm, ExtremeScales) {
    double r[4];
    const double big = std::ldexp(1.0, 500), small = std::ldexp(1.0, -500);
    ASSERT_EQ(solve_quadratic(small, 0, -big, r), 2);  // 2⁻⁵⁰⁰ t² − 2⁵⁰⁰: t = ±2⁵⁰⁰
    EXPECT_EQ(r[0], -big);
    EXPECT_EQ(r[1], big);
    ASSERT_EQ(solve_quadratic(1e-150, -1.0, 1e-150, r), 2);  // roots ≈ 1e-150 and 1e150
    EXPECT_LE(ulps_apart(r[0], 1e-150), 4);
    EXPECT_LE(ulps_apart(r[1], 1e150), 4);
    // (t − 2⁻¹⁰⁰)(t − 1)(t − 2¹⁰⁰) scaled by 1e-150: no overflow in b², c².
    const double s = 1e-150, p = std::ldexp(1.0, 100), q = std::ldexp(1.0, -100);
    ASSERT_EQ(solve_cubic(s, -s * (p + 1 + q), s * (p + p * q + q), -s * (p * q), r), 3);
    EXPECT_LE(ulps_apart(r[0], q), 4);
    EXPECT_LE(ulps_apart(r[1], 1), 4);
    EXPECT_LE(ulps_apart(r[2], p), 4);
    // (t − 1e100)(t + 1e100)(t² + 1) with coefficients ≈ 1e±150.
    ASSERT_EQ(solve_quartic(1e-150, 0, 1e-150 * (1 - 1e200), 0, -1e50, r), 2);
    EXPECT_LE(ulps_apart(r[0], -1e100), 4);
    EXPECT_LE(ulps_apart(r[1], 1e100), 4);
}

// ---- Property: random roots, polynomial formed exactly in MPFR ----

/// The exact polynomial lead·Π(t − r_i)·(t² − 2ut + u² + v²)^pair, coefficients rounded to
/// nearest (ascending powers).
std::vector<double> exact_coefficients(double lead, const std::vector<double>& roots, bool pair,
                                       double u, double v) {
    constexpr mpfr_prec_t kPrec = 2400;  // every product of ≤ 4 doubles and their sums are exact
    std::vector<mpfr_t> c(roots.size() + (pair ? 2 : 0) + 1);
    for (auto& x : c) mpfr_init2(x, kPrec);
    mpfr_set_d(c[0], lead, MPFR_RNDN);
    int deg = 0;
    mpfr_t tmp, qc;
    mpfr_init2(tmp, kPrec);
    mpfr_init2(qc, kPrec);
    auto mul_linear = [&](const mpfr_t root) {  // c ← c·(t − root)
        mpfr_set(c[deg + 1], c[deg], MPFR_RNDN);
        for (int k = deg; k >= 1; --k) {
            mpfr_mul(tmp, c[k], root, MPFR_RNDN);
            mpfr_sub(c[k], c[k - 1], tmp, MPFR_RNDN);
        }
        mpfr_mul(c[0], c[0], root, MPFR_RNDN);
        mpfr_neg(c[0], c[0], MPFR_RNDN);
        ++deg;
    };
    for (double r : roots) {
        mpfr_set_d(qc, r, MPFR_RNDN);
        mul_linear(qc);
    }
    if (pair) {  // c ← c·(t² − 2ut + u² + v²), done as two shifted multiplications
        mpfr_t a1, a0;
        mpfr_init2(a1, kPrec);
        mpfr_init2(a0, kPrec);
        mpfr_set_d(a1, -2 * u, MPFR_RNDN);  // exact
        mpfr_set_d(a0, u, MPFR_RNDN);
        mpfr_sqr(a0, a0, MPFR_RNDN);
        mpfr_set_d(tmp, v, MPFR_RNDN);
        mpfr_sqr(tmp, tmp, MPFR_RNDN);
        mpfr_add(a0, a0, tmp, MPFR_RNDN);
        for (int k = deg + 2; k >= 0; --k) {
            mpfr_set_zero(qc, 1);
            if (k - 2 >= 0 && k - 2 <= deg) mpfr_add(qc, qc, c[k - 2], MPFR_RNDN);
            if (k - 1 >= 0 && k - 1 <= deg) {
                mpfr_mul(tmp, c[k - 1], a1, MPFR_RNDN);
                mpfr_add(qc, qc, tmp, MPFR_RNDN);
            }
            if (k <= deg) {
                mpfr_mul(tmp, c[k], a0, MPFR_RNDN);
                mpfr_add(qc, qc, tmp, MPFR_RNDN);
            }
            mpfr_set(c[k], qc, MPFR_RNDN);
        }
        deg += 2;
        mpfr_clear(a1);
        mpfr_clear(a0);
    }
    std::vector<double> out(c.size());
    for (std::size_t k = 0; k < c.size(); ++k) out[k] = mpfr_get_d(c[k], MPFR_RNDN);
    for (auto& x : c) mpfr_clear(x);
    mpfr_clear(tmp);
    mpfr_clear(qc);
    return out;
}

struct Worst {
    double ratio = 0;  // max error / (κ ε) over asserted roots
    double rel = 0;    // max relative error over well-conditioned roots (κ ≤ 100)
};
Worst g_worst[5];

/// Binary exponents of the random roots: ratios up to 2^120 between roots.
constexpr int kMinExp = -60, kMaxExp = 60;

/// A root value: sign, mantissa and a binary exponent from a wide range.
rc::Gen<double> gen_root() {
    return rc::gen::exec([] {
        const double m = *rc::gen::inRange(1000000, 9999999) / 1e6;
        const int e = *rc::gen::inRange(kMinExp, kMaxExp + 1);
        return (*rc::gen::arbitrary<bool>() ? -1 : 1) * std::ldexp(m, e);
    });
}

void check_random_polynomial(int degree) {
    const int n_pair = degree >= 3 ? *rc::gen::inRange(0, 2) : 0;
    const int n_real = degree - 2 * n_pair;
    std::vector<double> roots;
    for (int i = 0; i < n_real; ++i) {
        if (i > 0 && *rc::gen::inRange(0, 4) == 0) {  // a cluster: r·(1 + 2^−k)
            const int k = *rc::gen::inRange(1, 40);
            roots.push_back(roots.back() * (1 + std::ldexp(1.0, -k)));
        } else {
            roots.push_back(*gen_root());
        }
    }
    const double u = n_pair ? *gen_root() : 0.0;
    const double v = n_pair ? std::abs(*gen_root()) : 0.0;
    const double lead = std::ldexp(*rc::gen::inRange(1, 1000) / 7.0, *rc::gen::inRange(-100, 100));
    const std::vector<double> a = exact_coefficients(lead, roots, n_pair == 1, u, v);
    std::sort(roots.begin(), roots.end());
    double got[4];
    int n = 0;
    if (degree == 2) n = solve_quadratic(a[2], a[1], a[0], got);
    if (degree == 3) n = solve_cubic(a[3], a[2], a[1], a[0], got);
    if (degree == 4) n = solve_quartic(a[4], a[3], a[2], a[1], a[0], got);
    // Conditioning of every root z (the complex pair included) and its relative distance to the
    // nearest other root; the exact count is demanded only when every root moves (by the
    // linearised bound) far less than that distance, so no pair can merge or turn complex.
    using C = std::complex<long double>;
    std::vector<C> all(roots.begin(), roots.end());
    if (n_pair) {
        all.emplace_back(u, v);
        all.emplace_back(u, -v);
    }
    std::vector<double> kappa(roots.size());
    bool all_good = true;
    for (std::size_t i = 0; i < all.size(); ++i) {
        C dp = lead;
        long double sep = std::numeric_limits<long double>::infinity();
        for (std::size_t j = 0; j < all.size(); ++j) {
            if (j == i) continue;
            dp *= all[i] - all[j];
            sep = std::min(sep, std::abs(all[i] - all[j]) / std::abs(all[i]));
        }
        long double s = 0;
        for (std::size_t k = 0; k < a.size(); ++k)
            s += std::abs(a[k]) * std::pow(std::abs(all[i]), static_cast<long double>(k));
        const double k_i = static_cast<double>(s / (std::abs(all[i]) * std::abs(dp)));
        if (i < roots.size()) kappa[i] = k_i;
        if (!(k_i * kEps < 1e-4 && 64 * k_i * kEps < sep)) all_good = false;
    }
    if (!all_good) return;  // clustered beyond the linear regime: nothing sharp to assert
    RC_LOG() << "coefficients (ascending):";
    for (double x : a) RC_LOG() << " " << x;
    RC_LOG() << "\nexact roots:";
    for (double x : roots) RC_LOG() << " " << x;
    RC_LOG() << "\nsolver roots:";
    for (int i = 0; i < n; ++i) RC_LOG() << " " << got[i];
    RC_LOG() << "\n";
    RC_ASSERT(n == static_cast<int>(roots.size()));
    for (int i = 0; i < n; ++i) {
        const double err = std::abs(got[i] - roots[i]) / std::abs(roots[i]);
        RC_ASSERT(err <= (kCondFactor * kappa[i] + 4) * kEps);
        Worst& w = g_worst[degree];
        w.ratio = std::max(w.ratio, err / ((kappa[i] + 1) * kEps));
        if (kappa[i] <= 100) w.rel = std::max(w.rel, err);
    }
}

RC_GTEST_PROP(ClosedFormProperty, QuadraticRootsWithinConditioning, ()) {
    check_random_polynomial(2);
}
RC_GTEST_PROP(ClosedFormProperty, CubicRootsWithinConditioning, ()) { check_random_polynomial(3); }
RC_GTEST_PROP(ClosedFormProperty, QuarticRootsWithinConditioning, ()) {
    check_random_polynomial(4);
}

TEST(ClosedFormProperty, ReportWorstErrors) {
    for (int d = 2; d <= 4; ++d)
        std::printf("degree %d: max err/((κ+1)ε) = %.3g, max rel err (κ ≤ 100) = %.3g\n", d,
                    g_worst[d].ratio, g_worst[d].rel);
}

}  // namespace
}  // namespace certray::solvers
