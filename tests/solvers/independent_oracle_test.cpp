// tests/solvers/independent_oracle_test.cpp — the judge of the property tests can say no: right
// claims about a sphere are confirmed, fabricated ones (the second root, a miss, an empty range, a
// sign change across a pole, an Unknown past the first root) are not, by either route.
#include "tests/support/independent_oracle.h"

#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <limits>

#include "expr/parser.h"
#include "expr/tape.h"

namespace certray::testing {
namespace {

using expr::Tape;
constexpr double kInf = std::numeric_limits<double>::infinity();

Tape tape_of(const char* text) { return Tape(expr::parse_expr(text)); }

RayResult hit(double lo, double hi) {
    RayResult r;
    r.status = Status::Hit;
    r.t_lo = lo;
    r.t_hi = hi;
    r.t = lo;
    return r;
}

RayResult unknown(double lo, double hi) {
    RayResult r = hit(lo, hi);
    r.status = Status::Unknown;
    return r;
}

RayResult miss() {
    RayResult r;
    r.status = Status::Miss;
    return r;
}

/// The two doubles around 3 + s·√0.75 (s = ±1): the roots along o = (0, 0.5, −3), d = +z of the
/// unit sphere, computed here in MPFR (not by any solver).
std::pair<double, double> root_around(int s) {
    mpfr_t r;
    mpfr_init2(r, 256);
    mpfr_set_d(r, 0.75, MPFR_RNDN);
    mpfr_sqrt(r, r, MPFR_RNDN);
    if (s < 0) mpfr_neg(r, r, MPFR_RNDN);
    mpfr_add_ui(r, r, 3, MPFR_RNDN);
    const double lo = mpfr_get_d(r, MPFR_RNDD), hi = mpfr_get_d(r, MPFR_RNDU);
    mpfr_clear(r);
    return {lo, hi};
}

const Ray kRay{{0, 0.5, -3}, {0, 0, 1}, 0, 10};

void expect(const Tape& t, const Ray& ray, const RayResult& claim, Verdict v, Verdict route,
            bool exact_route) {
    const Judgement j = judge_claim(t, ray, claim);
    EXPECT_EQ(j.verdict, v) << describe(ray, claim) << ": " << j.why;
    EXPECT_EQ(exact_route ? j.exact : j.mpfr, route) << describe(ray, claim) << ": " << j.why;
}

class SphereClaims : public ::testing::TestWithParam<bool> {};

// Both spheres, through both routes: the sqrt sphere is judged in MPFR only, the algebraic one
// also by the exact oracle (and the MPFR route is run alone on it too).
TEST_P(SphereClaims, RightClaimsAreConfirmedAndFabricatedOnesRejected) {
    const bool algebraic = GetParam();
    const Tape t = tape_of(algebraic ? "x^2 + y^2 + z^2 - 1" : "sqrt(x^2 + y^2 + z^2) - 1");
    const auto [a1, b1] = root_around(-1);
    const auto [a2, b2] = root_around(1);
    ASSERT_LT(a1, b1);  // √0.75 is irrational: never a double
    for (const bool exact : algebraic ? std::vector<bool>{true, false} : std::vector<bool>{false}) {
        SCOPED_TRACE(exact ? "exact route" : "mpfr route");
        OracleOptions opt;
        opt.use_exact = exact;
        opt.use_mpfr = !exact;
        auto verdict = [&](const Ray& ray, const RayResult& claim) {
            const Judgement j = judge_claim(t, ray, claim, opt);
            return std::pair{j.verdict, j.why};
        };
        auto expect_v = [&](const Ray& ray, const RayResult& claim, Verdict v) {
            const auto [got, why] = verdict(ray, claim);
            EXPECT_EQ(got, v) << describe(ray, claim) << ": " << why;
        };
        // The first root, tight and loose; tangent-free so both routes decide.
        expect_v(kRay, hit(a1, b1), Verdict::Confirmed);
        expect_v(kRay, hit(1.5, 2.5), Verdict::Confirmed);
        expect_v(kRay, hit(0, 3), Verdict::Confirmed);
        // The second root: a real zero, but not the first.
        expect_v(kRay, hit(a2, b2), Verdict::Refuted);
        expect_v(kRay, hit(3, 5), Verdict::Refuted);
        // No zero in the claimed range at all.
        expect_v(kRay, hit(1, 1.5), Verdict::Refuted);
        // A miss through the sphere; a miss of a ray that stops short is right.
        expect_v(kRay, miss(), Verdict::Refuted);
        expect_v(Ray{kRay.o, kRay.d, 0, 2}, miss(), Verdict::Confirmed);
        // Misses to infinity: beside the sphere, and behind it.
        expect_v(Ray{{0, 5, 0}, {1, 0.5, 0}, 0, kInf}, miss(), Verdict::Confirmed);
        expect_v(Ray{kRay.o, kRay.d, 4, kInf}, miss(), Verdict::Confirmed);
        expect_v(Ray{kRay.o, kRay.d, 0, kInf}, miss(), Verdict::Refuted);
        // An exact root at a double: the ray along the axis meets the sphere at t = 2 and 4.
        const Ray axis{{0, 0, -3}, {0, 0, 1}, 0, 10};
        expect_v(axis, hit(2, 2), Verdict::Confirmed);
        expect_v(axis, hit(4, 4), Verdict::Refuted);
        // Outside the ray's range.
        expect_v(kRay, hit(-1, 3), Verdict::Refuted);
        // Unknown: allowed anywhere up to the first root, never past it.
        expect_v(kRay, unknown(0, 10), Verdict::Confirmed);
        expect_v(kRay, unknown(a1, b1), Verdict::Confirmed);
        expect_v(kRay, unknown(3, 10), Verdict::Refuted);
    }
}

INSTANTIATE_TEST_SUITE_P(Independent, SphereClaims, ::testing::Bool());

TEST(IndependentOracle, SignChangesAcrossAPoleAreNotZeros) {
    // 1/x − 1 from x = −2: a sign change across the pole at t = 2, the zero at t = 3. MPFR
    // intervals cannot exclude a zero across a pole (1/[−ε, ε] is the whole line): claims past
    // it stay unverified, never confirmed by the sign change across it.
    const Tape t = tape_of("1 / x - 1");
    const Ray ray{{-2, 0, 0}, {1, 0, 0}, 0, 10};
    EXPECT_EQ(judge_claim(t, ray, hit(1.5, 2.5)).verdict, Verdict::Refuted);  // no zero there
    EXPECT_EQ(judge_claim(t, ray, hit(1.5, 2.75)).verdict, Verdict::Unverified);
    EXPECT_EQ(judge_claim(t, ray, hit(2.5, 3.5)).verdict, Verdict::Unverified);
    EXPECT_EQ(judge_claim(t, ray, hit(4, 5)).verdict, Verdict::Refuted);
    // From the other side the zero comes first.
    const Ray back{{4, 0, 0}, {-1, 0, 0}, 0, 10};
    EXPECT_EQ(judge_claim(t, back, hit(3, 3)).verdict, Verdict::Confirmed);
    EXPECT_EQ(judge_claim(t, back, hit(2.5, 3.5)).verdict, Verdict::Confirmed);
    // sqrt(x) − 0.5 is undefined before x = 0: no zero there, the zero at x = 0.25 (t = 1.25,
    // an exact double: [0, 1.25) is excluded up to it by monotonicity).
    const Tape s = tape_of("sqrt(x) - 0.5");
    EXPECT_EQ(judge_claim(s, Ray{{-1, 0, 0}, {1, 0, 0}, 0, 5}, hit(1.25, 1.25)).verdict,
              Verdict::Confirmed);
    EXPECT_EQ(judge_claim(s, Ray{{-1, 0, 0}, {1, 0, 0}, 0, 1.2}, miss()).verdict,
              Verdict::Confirmed);
}

TEST(IndependentOracle, TangentsAreLeftToTheExactRoute) {
    // x² + y² + z² − 1 along y = 1 touches at x = 0, t = 1/3 (a double root, not a double, no sign
    // change): the exact route confirms a hit around it, the MPFR route cannot prove the zero.
    const Tape t = tape_of("x^2 + y^2 + z^2 - 1");
    const Ray ray{{-1, 1, 0}, {3, 0, 0}, 0, 2};
    expect(t, ray, hit(0.25, 0.5), Verdict::Confirmed, Verdict::Confirmed, true);
    const Judgement j = judge_claim(t, ray, hit(0.25, 0.5));
    EXPECT_EQ(j.mpfr, Verdict::Unverified) << j.why;
    expect(t, ray, miss(), Verdict::Refuted, Verdict::Refuted, true);
    expect(t, ray, hit(0.5, 1), Verdict::Refuted, Verdict::Refuted, true);
}

TEST(IndependentOracle, TallyCountsEachVerdict) {
    OracleTally tally;
    const Tape t = tape_of("sqrt(x^2 + y^2 + z^2) - 1");
    for (const RayResult& r : {hit(1.5, 2.5), miss(), unknown(0, 10)}) {
        tally.add(r, judge_claim(t, kRay, r));
    }
    EXPECT_EQ(tally.hits, 1u);
    EXPECT_EQ(tally.misses, 1u);
    EXPECT_EQ(tally.unknowns, 1u);
    EXPECT_EQ(tally.confirmed, 1u);
    EXPECT_EQ(tally.refuted, 1u);
    EXPECT_EQ(tally.claims(), 2u);
}

}  // namespace
}  // namespace certray::testing
