// tests/solvers/exact_test.cpp — the exact oracle against roots mathematics gives: tangent, triple
// and clustered roots, roots at the ends of the segment, g ≡ 0, degenerate rays, huge, tiny and
// subnormal roots, the Barth sextic against the MPFR reference, a property on random products
// Π (bᵢ·x − aᵢ)^mᵢ (every root a known rational, checked in GMP rationals), and the fallback of
// the certified solver on tangent polynomial rays.
#include "solvers/exact.h"

#include <gmpxx.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "expr/builder.h"
#include "expr/graph.h"
#include "expr/load.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "solvers/analytic.h"
#include "solvers/certified.h"

namespace certray::solvers {
namespace {

using expr::Tape;
constexpr double kInf = std::numeric_limits<double>::infinity();

Tape tape_of(const char* text) { return Tape(expr::parse_expr(text)); }

ExactRoot along_x(const Tape& t, double tmin = 0, double tmax = kInf, double ox = 0) {
    return exact_root(t, Ray{{ox, 0, 0}, {1, 0, 0}, tmin, tmax});
}

/// A Hit at exactly the double `root`, of the given multiplicity.
void expect_exact_hit(const ExactRoot& r, double root, int multiplicity) {
    ASSERT_EQ(r.result.status, Status::Hit) << r.result.t_lo << " " << r.result.t_hi;
    EXPECT_EQ(r.result.t_lo, root);
    EXPECT_EQ(r.result.t_hi, root);
    EXPECT_EQ(r.multiplicity, multiplicity);
}

/// A Hit whose enclosure is two adjacent doubles around the rational `root` (not a double), or
/// the double it equals.
void expect_tight_hit(const RayResult& r, const mpq_class& root) {
    ASSERT_EQ(r.status, Status::Hit) << r.t_lo << " " << r.t_hi;
    ASSERT_TRUE(std::isfinite(r.t_lo) && std::isfinite(r.t_hi));
    EXPECT_LE(mpq_class(r.t_lo), root) << r.t_lo;
    EXPECT_GE(mpq_class(r.t_hi), root) << r.t_hi;
    if (r.t_lo != r.t_hi) {
        EXPECT_EQ(std::nextafter(r.t_lo, kInf), r.t_hi) << "not adjacent";
        EXPECT_NE(mpq_class(r.t_lo), root);  // the root is a double: it must be the answer
        EXPECT_NE(mpq_class(r.t_hi), root);
    }
}

TEST(Exact, TangentAtOneThird) {
    // (t − 1/3)²: a double root at 1/3, which no double equals.
    const ExactRoot r = along_x(tape_of("(x - 1/3)^2"));
    expect_tight_hit(r.result, mpq_class(1, 3));
    EXPECT_LT(r.result.t_lo, r.result.t_hi);
    EXPECT_EQ(r.multiplicity, 2);
    // The same written out: t² − (2/3)t + 1/9.
    const ExactRoot e = along_x(tape_of("x^2 - 2/3*x + 1/9"));
    expect_tight_hit(e.result, mpq_class(1, 3));
    EXPECT_EQ(e.multiplicity, 2);
}

TEST(Exact, AlgebraicSphereAlongTheAxes) {
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    const auto ray = [&](std::array<double, 3> o, std::array<double, 3> d, double tmin,
                         double tmax) {
        return exact_root(s, Ray{o, d, tmin, tmax});
    };
    expect_exact_hit(ray({0, 0, 0}, {1, 0, 0}, -10, 10), -1.0, 1);  // roots ±1: the first is −1
    expect_exact_hit(ray({0, 0, 0}, {1, 0, 0}, 0, kInf), 1.0, 1);   // from inside
    expect_exact_hit(ray({-3, 0, 0}, {1, 0, 0}, 0, kInf), 2.0, 1);
    expect_exact_hit(ray({0, 0, 3}, {0, 0, -1}, 0, kInf), 2.0, 1);
    expect_exact_hit(ray({0, -3, 0}, {0, 2, 0}, 0, kInf), 1.0, 1);  // scaled direction
    expect_exact_hit(ray({-3, 1, 0}, {1, 0, 0}, 0, 10), 3.0, 2);    // tangent at (0, 1, 0)
    EXPECT_EQ(ray({-3, 2, 0}, {1, 0, 0}, 0, kInf).result.status, Status::Miss);
    // Missing by 2⁻⁴⁰ (y = 1 + 2⁻⁴⁰): no real root; hitting by 2⁻⁴⁰: two, the first
    // 3 − √(2⁻³⁹ − 2⁻⁸⁰), not a double.
    const double eps = std::ldexp(1.0, -40);
    EXPECT_EQ(ray({-3, 1 + eps, 0}, {1, 0, 0}, 0, 10).result.status, Status::Miss);
    const ExactRoot near = ray({-3, 1 - eps, 0}, {1, 0, 0}, 0, 10);
    ASSERT_EQ(near.result.status, Status::Hit);
    EXPECT_EQ(near.multiplicity, 1);
    // (3 − t)² = 2⁻³⁹ − 2⁻⁸⁰ at the root: t_lo before it, t_hi past it.
    const mpq_class c = mpq_class(2 * eps) - mpq_class(eps) * mpq_class(eps);
    const mpq_class lo = 3 - mpq_class(near.result.t_lo), hi = 3 - mpq_class(near.result.t_hi);
    EXPECT_GT(lo * lo, c);
    EXPECT_LT(hi * hi, c);
    EXPECT_GT(hi, 0);
    EXPECT_EQ(std::nextafter(near.result.t_lo, kInf), near.result.t_hi);
}

TEST(Exact, TripleRoots) {
    expect_exact_hit(along_x(tape_of("(x - 0.75)^3")), 0.75, 3);
    expect_exact_hit(along_x(tape_of("(x - 0.1)^3")), 0.1, 3);  // the double nearest 0.1
    const ExactRoot third = along_x(tape_of("(3*x - 1)^3 * (x + 5)"));
    expect_tight_hit(third.result, mpq_class(1, 3));
    EXPECT_EQ(third.multiplicity, 3);
    // (x + 1)^64: degree 64, one root of multiplicity 64; degree 65 is over the limit.
    expect_exact_hit(along_x(tape_of("(x + 1)^64"), -2), -1.0, 64);
    EXPECT_EQ(along_x(tape_of("(x + 1)^65"), -2).result.status, Status::Unknown);
    EXPECT_FALSE(exact_polynomial(tape_of("(x + 1)^65"), Ray{{0, 0, 0}, {1, 0, 0}, 0, 1}));
    EXPECT_TRUE(exact_polynomial(tape_of("(x + 1)^65"), Ray{}));  // x = 0 along the z axis
}

TEST(Exact, TangentBeforeACrossing) {
    // The tangent comes first: it is the answer, however close the crossing behind it.
    expect_exact_hit(along_x(tape_of("(x - 0.5)^2 * (x - 0.75)")), 0.5, 2);
    expect_exact_hit(along_x(tape_of("(x - 0.5)^2 * (x - 0.5000000000000009)")), 0.5, 2);
    // A crossing first, a tangent behind it.
    expect_exact_hit(along_x(tape_of("(x - 0.25) * (x - 0.5)^2")), 0.25, 1);
    // Tangent to 1/3 with a crossing about 2⁻⁵⁰ after it.
    const ExactRoot r = along_x(tape_of("(3*x - 1)^2 * (x - 0.33333333333333426)"));
    expect_tight_hit(r.result, mpq_class(1, 3));
    EXPECT_EQ(r.multiplicity, 2);
}

TEST(Exact, NoRealRoots) {
    EXPECT_EQ(along_x(tape_of("x^2 + 1"), -kInf, kInf).result.status, Status::Miss);
    EXPECT_EQ(along_x(tape_of("(x^2 + 1)^3 * (x^2 + 0.001)")).result.status, Status::Miss);
    EXPECT_EQ(along_x(tape_of("(x - 3)*(x - 4)"), 0, 2.9).result.status, Status::Miss);
    EXPECT_EQ(along_x(tape_of("(x - 3)*(x - 4)"), 4.5, kInf).result.status, Status::Miss);
    EXPECT_EQ(along_x(tape_of("2.5")).result.status, Status::Miss);
}

TEST(Exact, RootsAtTheEndsOfTheSegment) {
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    const auto ray = [&](double tmin, double tmax) {
        return exact_root(s, Ray{{-3, 0, 0}, {1, 0, 0}, tmin, tmax});
    };
    expect_exact_hit(ray(2, 10), 2.0, 1);  // at tmin
    expect_exact_hit(ray(0, 2), 2.0, 1);   // at tmax
    expect_exact_hit(ray(2, 2), 2.0, 1);   // tmin = tmax on the root
    EXPECT_EQ(ray(0, std::nextafter(2.0, 0.0)).result.status, Status::Miss);
    EXPECT_EQ(ray(1, 1).result.status, Status::Miss);  // tmin = tmax off the root
    expect_exact_hit(ray(std::nextafter(2.0, 3.0), 10), 4.0, 1);
    expect_exact_hit(along_x(tape_of("(x - 0.5)^2"), 0.5, 1), 0.5, 2);  // tangent at tmin
}

TEST(Exact, IdenticallyZeroAndConstantRays) {
    // (x + 1)² − x² − 2x − 1 ≡ 0: every t is a root, the first is tmin.
    const ExactRoot z = along_x(tape_of("(x + 1)^2 - x^2 - 2*x - 1"), 0.25, 3);
    ASSERT_EQ(z.result.status, Status::Hit);
    EXPECT_EQ(z.result.t_lo, 0.25);
    EXPECT_EQ(z.result.t_hi, 0.25);
    EXPECT_EQ(z.multiplicity, 0);
    // A zero direction: g is the constant f(o).
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    const ExactRoot on = exact_root(s, Ray{{0, 1, 0}, {0, 0, 0}, 1, 2});
    ASSERT_EQ(on.result.status, Status::Hit);
    EXPECT_EQ(on.result.t_lo, 1.0);
    EXPECT_EQ(exact_root(s, Ray{{0, 0.5, 0}, {0, 0, 0}, 1, 2}).result.status, Status::Miss);
}

TEST(Exact, HugeTinyAndSubnormalRoots) {
    expect_exact_hit(along_x(tape_of("x - 1e300")), 1e300, 1);
    // The root 10⁶⁰⁰ is beyond the doubles: [largest double, ∞] holds it.
    const ExactRoot far = along_x(tape_of("x * 1e-300 - 1e300"));
    ASSERT_EQ(far.result.status, Status::Hit);
    EXPECT_EQ(far.result.t_lo, std::numeric_limits<double>::max());
    EXPECT_EQ(far.result.t_hi, kInf);
    // Capped by tmax: none before 1e308.
    EXPECT_EQ(along_x(tape_of("x * 1e-300 - 1e300"), 0, 1e308).result.status, Status::Miss);
    // The smallest subnormal, and half of it (between 0 and the smallest subnormal).
    const double tiny = std::numeric_limits<double>::denorm_min();
    expect_exact_hit(along_x(tape_of("x - 4.9406564584124654e-324")), tiny, 1);
    const ExactRoot half = along_x(tape_of("2*x - 4.9406564584124654e-324"));
    ASSERT_EQ(half.result.status, Status::Hit);
    EXPECT_EQ(half.result.t_lo, 0.0);
    EXPECT_EQ(half.result.t_hi, tiny);
    // A coefficient 2⁻¹⁰⁷⁰ (scenes/stress/subnormal.expr) and one of 10⁶⁰⁰ (a product).
    expect_exact_hit(along_x(tape_of("(x - 0.5) * 0.5^1070")), 0.5, 1);
    expect_exact_hit(along_x(tape_of("(x - 0.5) * 1e300 * 1e300")), 0.5, 1);
    // Huge and tiny ray components: o = 2⁻¹⁰⁷⁴ along x scaled by 2⁶⁰⁰; x² − 1 → t ≈ 2⁻⁶⁰⁰.
    const ExactRoot r =
        exact_root(tape_of("x^2 - 1"), Ray{{tiny, 0, 0}, {std::ldexp(1.0, 600), 0, 0}, 0, kInf});
    expect_tight_hit(r.result, (1 - mpq_class(tiny)) / mpq_class(std::ldexp(1.0, 600)));
}

TEST(Exact, NotPolynomial) {
    EXPECT_FALSE(why_not_exact_polynomial(tape_of("sqrt(x^2 + y^2) - 1")).empty());
    EXPECT_FALSE(why_not_exact_polynomial(tape_of("min(x, y)")).empty());
    EXPECT_FALSE(why_not_exact_polynomial(tape_of("1 / x - 1")).empty());
    EXPECT_FALSE(why_not_exact_polynomial(tape_of("x + sqrt(2)")).empty());  // irrational
    EXPECT_TRUE(why_not_exact_polynomial(tape_of("x / 3 - min(1, 2) * abs(-0.5)")).empty());
    const ExactRoot r = along_x(tape_of("sqrt(x) - 0.5"), 0, 4);
    EXPECT_EQ(r.result.status, Status::Unknown);
    EXPECT_EQ(r.result.t_lo, 0.0);
    EXPECT_FALSE(exact_polynomial(tape_of("x - 1"), Ray{{kInf, 0, 0}, {1, 0, 0}, 0, 1}));
    // Exact constants: x/3 − min(1, 2)·|−0.5| = 0 at x = 3/2.
    expect_exact_hit(along_x(tape_of("x / 3 - min(1, 2) * abs(-0.5)")), 1.5, 1);
}

TEST(Exact, CoefficientsAreExact) {
    // (o + t·d) with o = 0.1, d = 0.3 (doubles): g = (0.1 + 0.3·t)² − 0.1, coefficients from
    // the exact rationals of the three doubles.
    const std::optional<ExactPoly> g =
        exact_polynomial(tape_of("x^2 - 0.1"), Ray{{0.1, 0, 0}, {0.3, 0, 0}, 0, 1});
    ASSERT_TRUE(g);
    ASSERT_EQ(g->degree(), 2);
    const mpq_class o(0.1), d(0.3);
    EXPECT_EQ(g->c[0], o * o - o);
    EXPECT_EQ(g->c[1], 2 * o * d);
    EXPECT_EQ(g->c[2], d * d);
}

TEST(Exact, BudgetIsHonest) {
    ExactOptions o;
    o.budget = 6;
    const RayResult r =
        exact_first_root(tape_of("(3*x - 1)^2 * (x - 5)"), Ray{{0, 0, 0}, {1, 0, 0}, 0, 10}, o);
    ASSERT_NE(r.status, Status::Miss);
    EXPECT_LE(mpq_class(r.t_lo), mpq_class(1, 3));
    if (r.status == Status::Hit) {
        EXPECT_GE(mpq_class(r.t_hi), mpq_class(1, 3));
    }
    EXPECT_LE(r.evals.value, o.budget + 8);
    o.budget = 0;
    EXPECT_EQ(exact_first_root(tape_of("x - 1"), Ray{{0, 0, 0}, {1, 0, 0}, 0, 2}, o).status,
              Status::Unknown);
}

TEST(Exact, BarthSexticAgreesWithTheReference) {
    const Tape t(
        expr::load_graph_file(std::string(CERTRAY_SOURCE_DIR) + "/scenes/barth_sextic.vm"));
    ASSERT_TRUE(is_polynomial(t));
    int compared = 0;
    for (int i = 0; i < 12; ++i) {
        const double a = -1.0 + i / 6.0;
        const Ray ray{{-3, 0.37 * a, 0.21 + 0.5 * a}, {1, 0.013 * i, -0.02}, 0, 6};
        const ExactRoot e = exact_root(t, ray);
        const RayResult ref = certified_first_root_reference(t, ray);
        SCOPED_TRACE("ray " + std::to_string(i));
        ASSERT_NE(e.result.status, Status::Unknown);
        if (e.result.status == Status::Hit) {
            EXPECT_EQ(std::nextafter(e.result.t_lo, kInf) >= e.result.t_hi, true);
            EXPECT_GE(e.multiplicity, 1);
        }
        if (ref.status == Status::Unknown) continue;
        ++compared;
        ASSERT_EQ(e.result.status, ref.status);
        if (ref.status == Status::Hit) {
            EXPECT_LE(std::max(e.result.t_lo, ref.t_lo), std::min(e.result.t_hi, ref.t_hi));
        }
    }
    EXPECT_GE(compared, 8);
}

// ---- the fallback of the certified solver ------------------------------------------------------

TEST(ExactFallback, CertifiedProvesTangentPolynomialRays) {
    // The double-interval search cannot decide a sign near a double root; the exact oracle does.
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    const RayResult r = certified_first_root(s, Ray{{-3, 1, 0}, {1, 0, 0}, 0, 10});
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_EQ(r.t_lo, 3.0);
    EXPECT_EQ(r.t_hi, 3.0);
    const RayResult m =
        certified_first_root(s, Ray{{-3, 1 + std::ldexp(1.0, -40), 0}, {1, 0, 0}, 0, 10});
    EXPECT_EQ(m.status, Status::Miss);
    expect_tight_hit(certified_first_root(tape_of("(x - 1/3)^2"), Ray{{0, 0, 0}, {1, 0, 0}}),
                     mpq_class(1, 3));
    // Not polynomial: no fallback, still honest (the tangent of a torus stays Unknown or Hit).
    const RayResult torus = certified_first_root(tape_of("(sqrt(x^2 + y^2) - 1)^2 + z^2 - 0.0625"),
                                                 Ray{{-3, 0, 0.25}, {1, 0, 0}, 0, 6});
    EXPECT_NE(torus.status, Status::Miss);
}

// ---- properties --------------------------------------------------------------------------------

/// A random double: ±m·2^e with a 53-bit m, |value| between about 2⁻⁴⁰ and 2⁶.
rc::Gen<double> gen_double() {
    return rc::gen::exec([] {
        const auto m = *rc::gen::inRange<std::int64_t>(1, std::int64_t{1} << 53);
        const int e = *rc::gen::inRange(-92, -46);
        const double v = std::ldexp(static_cast<double>(m), e);
        return *rc::gen::arbitrary<bool>() ? -v : v;
    });
}

// g(t) = Π (bᵢ·x − aᵢ)^mᵢ along x = o + t·d: its roots tᵢ = (aᵢ/bᵢ − o)/d are known rationals.
RC_GTEST_PROP(ExactProperty, RandomRootProducts, ()) {
    const int n = *rc::gen::inRange(1, 7);
    expr::Graph g;
    auto [x, y, z] = expr::vars(g);
    const double ox = *rc::gen::element(0.0, 0.25, -1.5, 0.1);
    const double dx = *rc::gen::element(1.0, 2.0, 0.5, 3.0, -1.0);
    std::vector<std::pair<mpq_class, int>> roots;  // in t
    std::vector<double> as;
    expr::Expr f = expr::constant(g, 1.0);
    for (int i = 0; i < n; ++i) {
        // Sometimes a repeated root, to make multiplicities and clusters.
        const double a =
            (!as.empty() && *rc::gen::inRange(0, 4) == 0) ? *rc::gen::elementOf(as) : *gen_double();
        as.push_back(a);
        const double b = *rc::gen::element(1.0, 1.0, 3.0, 5.0, 7.0);
        const int m = *rc::gen::inRange(1, 4);
        f = f * expr::pow(b * x - a, static_cast<unsigned>(m));
        roots.emplace_back((mpq_class(a) / mpq_class(b) - mpq_class(ox)) / mpq_class(dx), m);
    }
    g.set_output(f.id);
    const Tape tape(g);
    // tmin: before everything, random, or exactly a root's double (when it is one).
    double tmin = *rc::gen::element(-1e3, 0.0) + *gen_double();
    if (*rc::gen::arbitrary<bool>()) tmin = roots[*rc::gen::inRange<int>(0, n)].first.get_d();
    const double tmax = *rc::gen::arbitrary<bool>() ? kInf : tmin + std::fabs(*gen_double()) * 8;
    // The expectation: the least root ≥ tmin (in ℚ), with the multiplicities of equal roots added.
    std::optional<mpq_class> first;
    for (const auto& [r, m] : roots) {
        if (r >= mpq_class(tmin) && (tmax == kInf || r <= mpq_class(tmax)) &&
            (!first || r < *first))
            first = r;
    }
    int mult = 0;
    for (const auto& [r, m] : roots) {
        if (first && r == *first) mult += m;
    }
    const ExactRoot res = exact_root(tape, Ray{{ox, 0, 0}, {dx, 0, 0}, tmin, tmax});
    if (!first) {
        RC_ASSERT(res.result.status == Status::Miss);
        return;
    }
    RC_ASSERT(res.result.status == Status::Hit);
    RC_ASSERT(mpq_class(res.result.t_lo) <= *first);
    RC_ASSERT(mpq_class(res.result.t_hi) >= *first);
    if (res.result.t_lo != res.result.t_hi) {
        RC_ASSERT(std::nextafter(res.result.t_lo, kInf) == res.result.t_hi);
        RC_ASSERT(mpq_class(res.result.t_lo) != *first);
        RC_ASSERT(mpq_class(res.result.t_hi) != *first);
    }
    RC_ASSERT(res.multiplicity == mult);
}

TEST(PolynomialCheck, BothRulesOverOneWalk) {
    // The exact oracle takes + − × powers and division by constants; abs/min/max only of
    // constants; sqrt and the other ops never, even of constants. The analytic methods also take
    // abs/min/max of anything (split where they switch), and sqrt of constants. The SSA of
    // "abs(x) - 1" is x, abs, 1, sub: the abs is instruction 2 of 4.
    EXPECT_EQ(why_not_exact_polynomial(tape_of("x^3 - 2*x*y + z/4 - 1")), "");
    EXPECT_EQ(why_not_exact_polynomial(tape_of("x * max(2, 3)")), "");
    EXPECT_EQ(why_not_exact_polynomial(tape_of("x / (y + 1)")),
              "division by a non-constant (instruction 5 of 5)");
    EXPECT_EQ(why_not_exact_polynomial(tape_of("abs(x) - 1")),
              "abs of a non-constant (instruction 2 of 4)");
    EXPECT_NE(why_not_exact_polynomial(tape_of("x + sqrt(2)")).find("sqrt, not a polynomial"),
              std::string::npos);
    EXPECT_EQ(why_not_polynomial(tape_of("abs(x) - 1")), "");
    EXPECT_EQ(why_not_polynomial(tape_of("x + sqrt(2)")), "");
    EXPECT_EQ(why_not_polynomial(tape_of("sqrt(x) - 1")),
              "sqrt of a non-constant (instruction 2 of 4)");
    EXPECT_EQ(why_not_polynomial(tape_of("atan2(1, x) + z")).rfind("atan2 of a non-constant", 0),
              0u);
}

}  // namespace
}  // namespace certray::solvers
