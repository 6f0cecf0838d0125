// Tests of MpfrInterval: exact results stated by mathematics, the IEEE 1788 set-based division
// table, empty/entire propagation, the `defined` decoration, RAII, and RapidCheck properties
// (a box result at 128 bits contains the point result at 256 bits, for every operation).
#include "interval/mpfr_interval.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cfenv>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "interval/number.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"

namespace certray {
namespace {

using testing::describe;
using testing::encloses;
using testing::FpEnvGuard;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Frees MPFR's constant caches (π) at exit so that LeakSanitizer reports only real leaks.
class MpfrCacheCleanup : public ::testing::Environment {
  public:
    void TearDown() override { mpfr_free_cache(); }
};
[[maybe_unused]] ::testing::Environment* const kCleanup =
    ::testing::AddGlobalTestEnvironment(new MpfrCacheCleanup);

/// x is exactly [lo, hi] (bounds compared exactly with mpfr_cmp_d; −0 equals +0).
::testing::AssertionResult is_exactly(const MpfrInterval& x, double lo, double hi) {
    if (!x.is_empty() && mpfr_cmp_d(x.lo(), lo) == 0 && mpfr_cmp_d(x.hi(), hi) == 0) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure()
           << describe(x) << " is not exactly [" << lo << ", " << hi << "]";
}

/// inner ⊆ outer, both as MPFR intervals, compared exactly (empty inner: always).
bool subset(const MpfrInterval& inner, const MpfrInterval& outer) {
    if (inner.is_empty()) {
        return true;
    }
    if (outer.is_empty()) {
        return false;
    }
    return mpfr_cmp(outer.lo(), inner.lo()) <= 0 && mpfr_cmp(inner.hi(), outer.hi()) <= 0;
}

/// A reference value f(v) at 1024 bits, rounded to nearest.
struct Reference {
    Reference() { mpfr_init2(v, 1024); }
    Reference(const Reference&) = delete;
    Reference& operator=(const Reference&) = delete;
    ~Reference() { mpfr_clear(v); }
    mpfr_t v;
};

// ---- construction ---------------------------------------------------------------------------

// MpfrInterval(x, 53) is ambiguous to a reader (point at 53 bits, or [x, 53]?): it must not
// compile.
static_assert(!std::is_constructible_v<MpfrInterval, double, int>);
static_assert(std::is_constructible_v<MpfrInterval, double, Precision>);
static_assert(std::is_constructible_v<MpfrInterval, double, double>);
static_assert(std::is_constructible_v<MpfrInterval, double, double, int>);
static_assert(std::is_nothrow_move_constructible_v<MpfrInterval>);
static_assert(std::is_nothrow_move_assignable_v<MpfrInterval>);
static_assert(Enclosure<MpfrInterval>);

TEST(MpfrInterval, ConstructsPointsBoundsEmptyAndEntire) {
    FpEnvGuard guard;
    const MpfrInterval p(1.5);
    EXPECT_EQ(p.precision(), MpfrInterval::kDefaultPrecision);
    EXPECT_TRUE(is_exactly(p, 1.5, 1.5));
    EXPECT_TRUE(p.defined);
    const MpfrInterval b(-2.0, 3.0, 64);
    EXPECT_EQ(b.precision(), 64);
    EXPECT_TRUE(is_exactly(b, -2.0, 3.0));
    EXPECT_EQ(b.lower_down(), -2.0);
    EXPECT_EQ(b.upper_up(), 3.0);
    EXPECT_TRUE(is_exactly(MpfrInterval(), 0.0, 0.0));

    const MpfrInterval e = MpfrInterval::empty(100);
    EXPECT_TRUE(e.is_empty());
    EXPECT_FALSE(e.defined);
    EXPECT_EQ(e.precision(), 100);
    EXPECT_TRUE(std::isnan(e.lower_down()));
    const MpfrInterval all = MpfrInterval::entire();
    EXPECT_TRUE(is_exactly(all, -kInf, kInf));
    EXPECT_TRUE(all.defined);

    // Sets of reals only: invalid inputs give the empty set.
    EXPECT_TRUE(MpfrInterval(kInf).is_empty());
    EXPECT_TRUE(MpfrInterval(std::nan("")).is_empty());
    EXPECT_TRUE(MpfrInterval(2.0, 1.0).is_empty());
    EXPECT_TRUE(MpfrInterval(kInf, kInf).is_empty());
    EXPECT_TRUE(MpfrInterval(-kInf, -kInf).is_empty());
    EXPECT_TRUE(is_exactly(MpfrInterval(-kInf, 0.0), -kInf, 0.0));

    // Below 53 bits a double is rounded outward.
    const MpfrInterval coarse(0.1, Precision{8});
    EXPECT_LT(coarse.lower_down(), 0.1);
    EXPECT_GT(coarse.upper_up(), 0.1);
}

// ---- arithmetic -----------------------------------------------------------------------------

TEST(MpfrInterval, ExactArithmetic) {
    FpEnvGuard guard;
    EXPECT_TRUE(is_exactly(MpfrInterval(1, 2) + MpfrInterval(3, 4), 4, 6));
    EXPECT_TRUE(is_exactly(MpfrInterval(1, 2) - MpfrInterval(3, 4), -3, -1));
    EXPECT_TRUE(is_exactly(MpfrInterval(-1, 2) * MpfrInterval(3, 4), -4, 8));
    EXPECT_TRUE(is_exactly(MpfrInterval(-3, -2) * MpfrInterval(-5, 4), -12, 15));
    EXPECT_TRUE(is_exactly(-MpfrInterval(1, 2), -2, -1));
    EXPECT_TRUE(is_exactly(+MpfrInterval(1, 2), 1, 2));
    // 0 · ∞ = 0 at the bounds: the sets hold reals only.
    EXPECT_TRUE(is_exactly(MpfrInterval(0.0) * MpfrInterval::entire(), 0, 0));
    EXPECT_TRUE(is_exactly(MpfrInterval(1, kInf) * MpfrInterval(0, 1), 0, kInf));
    EXPECT_TRUE(is_exactly(MpfrInterval(-kInf, 2.0) + MpfrInterval(1, kInf), -kInf, kInf));
    MpfrInterval acc(1.0);
    acc += MpfrInterval(2.0);
    acc *= MpfrInterval(4.0);
    acc -= MpfrInterval(2.0);
    acc /= MpfrInterval(5.0);
    EXPECT_TRUE(is_exactly(acc, 2, 2));
    EXPECT_TRUE(acc.defined);
}

TEST(MpfrInterval, OneThirdAt53BitsIsTwoNeighbours) {
    FpEnvGuard guard;
    const MpfrInterval third = MpfrInterval(1.0, Precision{53}) / MpfrInterval(3.0, Precision{53});
    ASSERT_EQ(third.precision(), 53);
    const double lo = third.lower_down();
    const double hi = third.upper_up();
    EXPECT_LT(lo, hi);
    EXPECT_EQ(lo, std::nextafter(hi, -kInf));
    // 3·lo < 1 < 3·hi, computed exactly (55 bits suffice for 3 × a 53-bit significand).
    mpfr_t t;
    mpfr_init2(t, 64);
    EXPECT_EQ(mpfr_mul_ui(t, third.lo(), 3, MPFR_RNDN), 0);
    EXPECT_LT(mpfr_cmp_ui(t, 1), 0);
    EXPECT_EQ(mpfr_mul_ui(t, third.hi(), 3, MPFR_RNDN), 0);
    EXPECT_GT(mpfr_cmp_ui(t, 1), 0);
    mpfr_clear(t);
    // The same at the default precision still gives doubles that enclose 1/3.
    const MpfrInterval fine = MpfrInterval(1.0) / MpfrInterval(3.0);
    EXPECT_LT(fine.lower_down(), fine.upper_up());
    EXPECT_LE(3 * fine.lower_down(), 1.0);
}

TEST(MpfrInterval, SetBasedDivisionTable) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    // 0 ∉ y: corner quotients, defined.
    const I q = I(6, 8) / I(2, 4);
    EXPECT_TRUE(is_exactly(q, 1.5, 4));
    EXPECT_TRUE(q.defined);
    EXPECT_TRUE(is_exactly(I(-8, -6) / I(2, 4), -4, -1.5));
    EXPECT_TRUE(is_exactly(I(-1, 2) / I(2, 4), -0.5, 1));
    EXPECT_TRUE(is_exactly(I(6, 8) / I(-4, -2), -4, -1.5));
    EXPECT_TRUE(is_exactly(I(-8, -6) / I(-4, -2), 1.5, 4));
    EXPECT_TRUE(is_exactly(I(-1, 2) / I(-4, -2), -1, 0.5));
    EXPECT_TRUE(is_exactly(I(1, kInf) / I(1, kInf), 0, kInf));
    EXPECT_TRUE(is_exactly(I(-kInf, -1.0) / I(-kInf, -1.0), 0, kInf));
    // y = [0, 0]: empty.
    const I by_zero = I(1, 2) / I(0.0);
    EXPECT_TRUE(by_zero.is_empty());
    EXPECT_FALSE(by_zero.defined);
    EXPECT_TRUE((I(0.0) / I(0.0)).is_empty());
    // y = [0, d].
    const I half_open = I(1, 2) / I(0, 1);
    EXPECT_TRUE(is_exactly(half_open, 1, kInf));
    EXPECT_FALSE(half_open.defined);
    EXPECT_TRUE(is_exactly(I(-2, -1) / I(0, 4), -kInf, -0.25));
    EXPECT_TRUE(is_exactly(I(-2, 0) / I(0, 4), -kInf, 0));
    EXPECT_TRUE(is_exactly(I(0, 2) / I(0, 4), 0, kInf));
    EXPECT_TRUE(is_exactly(I(-1, 2) / I(0, 1), -kInf, kInf));
    // y = [c, 0].
    EXPECT_TRUE(is_exactly(I(-30, 0) / I(-3, 0), 0, kInf));
    EXPECT_TRUE(is_exactly(I(1, 2) / I(-4, 0), -kInf, -0.25));
    EXPECT_TRUE(is_exactly(I(-2, -1) / I(-4, 0), 0.25, kInf));
    EXPECT_TRUE(is_exactly(I(0, 2) / I(-4, 0), -kInf, 0));
    EXPECT_TRUE(is_exactly(I(-1, 2) / I(-4, 0), -kInf, kInf));
    // c < 0 < d with a numerator holding nonzero values: entire.
    const I straddle = I(1, 2) / I(-1, 1);
    EXPECT_TRUE(is_exactly(straddle, -kInf, kInf));
    EXPECT_FALSE(straddle.defined);
    EXPECT_TRUE(is_exactly(I(-2, 0) / I(-1, 1), -kInf, kInf));
    // x = [0, 0], y ≠ [0, 0]: {0}, but not defined on the whole box.
    const I zero = I(0.0) / I(-1, 1);
    EXPECT_TRUE(is_exactly(zero, 0, 0));
    EXPECT_FALSE(zero.defined);
    EXPECT_TRUE(is_exactly(I(0.0) / I(0, 3), 0, 0));
    EXPECT_TRUE(is_exactly(I::entire() / I::entire(), -kInf, kInf));
}

// ---- elementary functions -------------------------------------------------------------------

TEST(MpfrInterval, AbsSquarePow) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    EXPECT_TRUE(is_exactly(abs(I(-3, 2)), 0, 3));
    EXPECT_TRUE(is_exactly(abs(I(-3, -2)), 2, 3));
    EXPECT_TRUE(is_exactly(abs(I(2, 3)), 2, 3));
    EXPECT_TRUE(is_exactly(square(I(-3, 2)), 0, 9));
    EXPECT_TRUE(is_exactly(square(I(-3, -2)), 4, 9));
    EXPECT_TRUE(is_exactly(square(I(-kInf, 1.0)), 0, kInf));
    EXPECT_TRUE(is_exactly(pow(I(-2, 3), 3), -8, 27));
    EXPECT_TRUE(is_exactly(pow(I(-2, 3), 2), 0, 9));
    EXPECT_TRUE(is_exactly(pow(I(-2, -1), 4), 1, 16));
    EXPECT_TRUE(is_exactly(pow(I(-2, 3), 1), -2, 3));
    EXPECT_TRUE(is_exactly(pow(I(-2, 3), 0), 1, 1));
    EXPECT_TRUE(is_exactly(pow(I::entire(), 0), 1, 1));
    EXPECT_TRUE(pow(I::empty(), 0).is_empty());
    // 3^41 > 2^53 is still exact at 256 bits but not at 53: rounded outward.
    const I big = pow(I(3.0, Precision{53}), 41);
    EXPECT_LT(mpfr_cmp(big.lo(), big.hi()), 0);
}

TEST(MpfrInterval, SqrtAndLogOnTheirDomain) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    const I s = sqrt(I(4, 9));
    EXPECT_TRUE(is_exactly(s, 2, 3));
    EXPECT_TRUE(s.defined);
    const I partial = sqrt(I(-5, 25));
    EXPECT_TRUE(is_exactly(partial, 0, 5));
    EXPECT_FALSE(partial.defined);
    EXPECT_TRUE(sqrt(I(-5, -1)).is_empty());
    EXPECT_TRUE(is_exactly(sqrt(I(-1, 0)), 0, 0));
    EXPECT_FALSE(sqrt(I(-1, 0)).defined);
    EXPECT_TRUE(sqrt(I(0, 0)).defined);
    const I two = sqrt(I(2.0, Precision{53}));
    EXPECT_EQ(two.lower_down(), std::nextafter(two.upper_up(), -kInf));

    const I l = log(I(1.0));
    EXPECT_TRUE(is_exactly(l, 0, 0));
    EXPECT_TRUE(l.defined);
    const I to_zero = log(I(0, 1));
    EXPECT_TRUE(is_exactly(to_zero, -kInf, 0));
    EXPECT_FALSE(to_zero.defined);
    EXPECT_TRUE(log(I(-3, 0)).is_empty());
    EXPECT_TRUE(log(I(-3, -1)).is_empty());
    EXPECT_FALSE(log(I(-3, -1)).defined);
    EXPECT_TRUE(is_exactly(log(I(1, kInf)), 0, kInf));

    const I e = exp(I(0.0));
    EXPECT_TRUE(is_exactly(e, 1, 1));
    EXPECT_TRUE(e.defined);
    EXPECT_TRUE(is_exactly(exp(I(-kInf, 0.0)), 0, 1));
    const I e1 = exp(I(1.0));
    EXPECT_LT(e1.lower_down(), e1.upper_up());
    EXPECT_LE(e1.lower_down(), M_E);
    EXPECT_GE(e1.upper_up(), M_E);
    // Round trip: log(exp(x)) ∋ x.
    EXPECT_TRUE(contains(log(exp(I(0.75))), 0.75));
}

TEST(MpfrInterval, CosAndSinOverWideAndNarrowBoxes) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    // [0, 7] holds the maximum 0 and the minimum π.
    const I c = cos(I(0, 7));
    EXPECT_TRUE(is_exactly(c, -1, 1));
    EXPECT_TRUE(c.defined);
    EXPECT_TRUE(is_exactly(cos(I(0.0)), 1, 1));
    EXPECT_TRUE(is_exactly(sin(I(0.0)), 0, 0));
    EXPECT_TRUE(is_exactly(sin(I(-kInf, 0.0)), -1, 1));
    EXPECT_TRUE(is_exactly(cos(I(-1e300, 1e300)), -1, 1));

    // sin on [0.1, 0.2] (increasing there): tight around the true values.
    const I s = sin(I(0.1, 0.2));
    Reference lo;
    Reference hi;
    mpfr_set_d(lo.v, 0.1, MPFR_RNDN);
    mpfr_sin(lo.v, lo.v, MPFR_RNDN);
    mpfr_set_d(hi.v, 0.2, MPFR_RNDN);
    mpfr_sin(hi.v, hi.v, MPFR_RNDN);
    EXPECT_LE(mpfr_cmp(s.lo(), lo.v), 0);
    EXPECT_GE(mpfr_cmp(s.hi(), hi.v), 0);
    Reference gap;
    mpfr_sub(gap.v, lo.v, s.lo(), MPFR_RNDU);
    EXPECT_LT(mpfr_cmp_d(gap.v, std::ldexp(1.0, -250)), 0) << describe(s);
    mpfr_sub(gap.v, s.hi(), hi.v, MPFR_RNDU);
    EXPECT_LT(mpfr_cmp_d(gap.v, std::ldexp(1.0, -250)), 0) << describe(s);
    EXPECT_LE(s.lower_down(), std::sin(0.1));
    EXPECT_GE(s.upper_up(), std::nextafter(std::sin(0.2), -kInf));

    // No false widening: the double π/2 and π lie just below the true ones.
    const I near_max = sin(I(M_PI_2));
    EXPECT_LT(mpfr_cmp_ui(near_max.hi(), 1), 0) << describe(near_max);
    const I near_min = cos(I(M_PI));
    EXPECT_GT(mpfr_cmp_si(near_min.lo(), -1), 0) << describe(near_min);
    // … and a box across them does reach ±1.
    EXPECT_EQ(mpfr_cmp_ui(sin(I(1, 2)).hi(), 1), 0);
    EXPECT_EQ(mpfr_cmp_si(cos(I(3, 3.5)).lo(), -1), 0);
    EXPECT_EQ(mpfr_cmp_si(sin(I(-2, -1)).lo(), -1), 0);
    EXPECT_EQ(mpfr_cmp_ui(cos(I(6, 6.5)).hi(), 1), 0);
    // Boxes narrower than 2π holding one extremum only: the other bound stays tight.
    const I one_min = cos(I(0.1, 6.2));  // holds π, not 0 nor 2π
    EXPECT_EQ(mpfr_cmp_si(one_min.lo(), -1), 0) << describe(one_min);
    EXPECT_LT(mpfr_cmp_ui(one_min.hi(), 1), 0) << describe(one_min);
    const I one_max = sin(I(-1.4, 4.6));  // holds π/2, not −π/2 nor 3π/2
    EXPECT_EQ(mpfr_cmp_ui(one_max.hi(), 1), 0) << describe(one_max);
    EXPECT_GT(mpfr_cmp_si(one_max.lo(), -1), 0) << describe(one_max);
    // cos is monotone on [1, 2]: no extremum, tight endpoints.
    const I mono = cos(I(1, 2));
    EXPECT_GT(mpfr_cmp_si(mono.lo(), -1), 0);
    EXPECT_LT(mpfr_cmp_ui(mono.hi(), 1), 0);
    EXPECT_LE(mono.lower_down(), std::cos(2.0));
    // A huge argument still gives a tight point enclosure (exact argument reduction).
    const I far = cos(I(1e300));
    EXPECT_LT(mpfr_cmp(far.lo(), far.hi()), 0);
    EXPECT_GT(mpfr_cmp_si(far.lo(), -1), 0);
    EXPECT_LT(mpfr_cmp_ui(far.hi(), 1), 0);
}

TEST(MpfrInterval, MinMaxHullIntersectContains) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    EXPECT_TRUE(is_exactly(min(I(1, 5), I(2, 3)), 1, 3));
    EXPECT_TRUE(is_exactly(max(I(1, 5), I(2, 3)), 2, 5));
    EXPECT_TRUE(is_exactly(hull(I(1, 2), I(4, 5)), 1, 5));
    EXPECT_TRUE(is_exactly(hull(I::empty(), I(4, 5)), 4, 5));
    EXPECT_TRUE(hull(I::empty(), I::empty()).is_empty());
    EXPECT_TRUE(is_exactly(intersect(I(1, 4), I(2, 5)), 2, 4));
    EXPECT_TRUE(intersect(I(1, 2), I(3, 4)).is_empty());
    EXPECT_FALSE(intersect(I(1, 2), I(3, 4)).defined);
    EXPECT_TRUE(is_exactly(intersect(I(1, 2), I(2, 4)), 2, 2));
    EXPECT_TRUE(contains(I(1, 2), 1.0));
    EXPECT_TRUE(contains(I(1, 2), 2.0));
    EXPECT_FALSE(contains(I(1, 2), std::nextafter(2.0, 3.0)));
    EXPECT_TRUE(contains(I::entire(), 1e308));
    EXPECT_FALSE(contains(I::entire(), kInf));
    EXPECT_FALSE(contains(I::entire(), std::nan("")));
    EXPECT_FALSE(contains(I::empty(), 0.0));
    EXPECT_TRUE(contains(I(-0.0, 0.0), 0.0));
}

TEST(MpfrInterval, EmptyPropagatesThroughEveryOperation) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    const I e = I::empty();
    const I x(1, 2);
    const std::vector<std::pair<std::string, I>> results = {
        {"e+x", e + x},    {"x-e", x - e},     {"e*x", e * x},        {"x/e", x / e},
        {"-e", -e},        {"abs", abs(e)},    {"square", square(e)}, {"pow", pow(e, 3)},
        {"sqrt", sqrt(e)}, {"exp", exp(e)},    {"log", log(e)},       {"sin", sin(e)},
        {"cos", cos(e)},   {"min", min(e, x)}, {"max", max(x, e)},    {"meet", intersect(e, x)},
    };
    for (const auto& [name, r] : results) {
        EXPECT_TRUE(r.is_empty()) << name << ": " << describe(r);
        EXPECT_FALSE(r.defined) << name;
    }
    EXPECT_FALSE(hull(e, x).defined);
}

TEST(MpfrInterval, EntireAndDefinedFlag) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    const I all = I::entire();
    EXPECT_TRUE(is_exactly(all + I(1.0), -kInf, kInf));
    EXPECT_TRUE(is_exactly(all * all, -kInf, kInf));
    EXPECT_TRUE(is_exactly(exp(all), 0, kInf));
    EXPECT_TRUE(is_exactly(abs(all), 0, kInf));
    EXPECT_TRUE(is_exactly(sin(all), -1, 1));
    const I r = sqrt(all);
    EXPECT_TRUE(is_exactly(r, 0, kInf));
    EXPECT_FALSE(r.defined);
    const I l = log(all);
    EXPECT_TRUE(is_exactly(l, -kInf, kInf));
    EXPECT_FALSE(l.defined);
    EXPECT_TRUE((all + I(1.0)).defined);
    EXPECT_TRUE(exp(all).defined);
    // The AND of the operands: an undefined operand taints every later result.
    const I tainted = sqrt(I(-1, 4)) + I(1.0);
    EXPECT_TRUE(is_exactly(tainted, 1, 3));
    EXPECT_FALSE(tainted.defined);
    EXPECT_FALSE(exp(tainted).defined);
    EXPECT_FALSE((I(1.0) * tainted).defined);
    EXPECT_FALSE(min(I(1.0), tainted).defined);
    EXPECT_TRUE((I(1.0) / I(2, 3)).defined);
}

TEST(MpfrInterval, MixedPrecisionTakesTheLarger) {
    FpEnvGuard guard;
    const MpfrInterval a(1.0, Precision{64});
    const MpfrInterval b(3.0, Precision{200});
    EXPECT_EQ((a / b).precision(), 200);
    EXPECT_EQ((b - a).precision(), 200);
    EXPECT_EQ(min(a, b).precision(), 200);
    EXPECT_EQ(hull(a, b).precision(), 200);
    EXPECT_EQ(sqrt(a).precision(), 64);
    EXPECT_EQ(sin(b).precision(), 200);
}

TEST(MpfrInterval, CopyAndMoveAreLeakFreeAndPreserveValues) {
    FpEnvGuard guard;
    using I = MpfrInterval;
    I a(1.0, 2.0, 300);
    I b = a;  // copy
    EXPECT_TRUE(is_exactly(b, 1, 2));
    EXPECT_EQ(b.precision(), 300);
    I c = std::move(b);  // move
    EXPECT_TRUE(is_exactly(c, 1, 2));
    EXPECT_TRUE(b.is_empty());  // NOLINT(bugprone-use-after-move): the documented moved-from state
    b = c;                      // assign to a moved-from object
    EXPECT_TRUE(is_exactly(b, 1, 2));
    I d(5.0, Precision{64});
    d = a;  // copy across precisions
    EXPECT_EQ(d.precision(), 300);
    EXPECT_TRUE(is_exactly(d, 1, 2));
    d = I::entire(80);  // move across precisions
    EXPECT_EQ(d.precision(), 80);
    EXPECT_TRUE(is_exactly(d, -kInf, kInf));
    const I& alias = d;
    d = alias;  // self copy-assignment
    EXPECT_TRUE(is_exactly(d, -kInf, kInf));
    d = std::move(d);  // self move-assignment leaves the value intact
    EXPECT_TRUE(is_exactly(d, -kInf, kInf));
    std::swap(a, d);
    EXPECT_TRUE(is_exactly(a, -kInf, kInf));
    EXPECT_TRUE(is_exactly(d, 1, 2));
    const I undefined = sqrt(I(-1, 1));
    const I copy = undefined;
    EXPECT_FALSE(copy.defined);
    // Growth of a vector moves every element many times.
    std::vector<I> many;
    for (int i = 0; i < 200; ++i) {
        many.emplace_back(static_cast<double>(i), static_cast<double>(i) + 1.0, 64 + i);
    }
    std::vector<I> copies = many;
    many.erase(many.begin(), many.begin() + 100);
    for (int i = 0; i < 100; ++i) {
        EXPECT_TRUE(is_exactly(many[static_cast<std::size_t>(i)], 100.0 + i, 101.0 + i));
        EXPECT_EQ(copies[static_cast<std::size_t>(i)].precision(), 64 + i);
    }
}

TEST(MpfrInterval, OracleEnclosesAndDescribes) {
    using I = MpfrInterval;
    EXPECT_TRUE(encloses(1, 2, I(1, 2)));
    EXPECT_TRUE(encloses(-kInf, kInf, I::entire()));
    EXPECT_FALSE(encloses(1, 2, I(1, std::nextafter(2.0, 3.0))));
    EXPECT_FALSE(encloses(1, 2, I::entire()));
    EXPECT_TRUE(encloses(2, 1, I::empty()));
    EXPECT_FALSE(encloses(std::nan(""), 2, I(1, 2)));
    const I third = I(1.0) / I(3.0);
    EXPECT_TRUE(encloses(third.lower_down(), third.upper_up(), third));
    EXPECT_FALSE(encloses(third.upper_up(), third.upper_up(), third));
    EXPECT_EQ(describe(I(1, 2)), "[1, 2] (prec 256, defined)");
    EXPECT_EQ(describe(I::empty(64)), "[empty] (prec 64)");
    EXPECT_NE(describe(third).find("0.33333333333333333333"), std::string::npos) << describe(third);
}

// ---- properties: a box at 128 bits contains the point result at 256 bits ---------------------

constexpr Precision kBoxPrecision{128};
constexpr Precision kPointPrecision{256};

using Unary = std::function<MpfrInterval(const MpfrInterval&)>;
using Binary = std::function<MpfrInterval(const MpfrInterval&, const MpfrInterval&)>;

/// Whether an operation is a function evaluation (the decoration is checked) or a set operation.
enum class Kind { kFunction, kSetOperation };

/// The containment and decoration checks shared by every property.
void check_contains(const MpfrInterval& box, const MpfrInterval& point, Kind kind = Kind::kFunction,
                    Precision box_precision = kBoxPrecision) {
    RC_LOG() << "box result " << describe(box) << "\npoint result " << describe(point) << "\n";
    RC_ASSERT(std::fegetround() == FE_TONEAREST);
    RC_ASSERT(subset(point, box));
    // Defined on the whole box implies defined (and nonempty) at each of its points. (The
    // intersection of two points of defined boxes may well be empty: set operations are exempt.)
    if (kind == Kind::kFunction) {
        RC_ASSERT(!box.defined || (point.defined && !point.is_empty()));
    }
    RC_ASSERT(box.is_empty() || box.precision() == box_precision.bits);
}

/// The random point p plus the finite ends of [lo, hi]: the extremes of monotone pieces sit at the
/// corners, so checking them exercises the rounding direction of every bound formula.
std::vector<double> probes(double lo, double hi, double p) {
    std::vector<double> out = {p};
    for (const double end : {lo, hi}) {
        if (std::isfinite(end)) {
            out.push_back(end);
        }
    }
    return out;
}

void check_unary(const Unary& op, Precision box_precision = kBoxPrecision) {
    FpEnvGuard guard;
    const auto [lo, hi] = *testing::gen_bounds();
    const double p = *testing::gen_point_in(lo, hi);
    RC_LOG() << "x in [" << lo << ", " << hi << "], point " << p << "\n";
    RC_ASSERT(lo <= p && p <= hi);
    const MpfrInterval box = op(MpfrInterval(lo, hi, box_precision));
    for (const double v : probes(lo, hi, p)) {
        RC_LOG() << "at " << v << "\n";
        check_contains(box, op(MpfrInterval(v, kPointPrecision)), Kind::kFunction, box_precision);
    }
}

void check_binary(const Binary& op, Kind kind = Kind::kFunction,
                  Precision box_precision = kBoxPrecision) {
    FpEnvGuard guard;
    const auto [xlo, xhi] = *testing::gen_bounds();
    const auto [ylo, yhi] = *testing::gen_bounds();
    const double p = *testing::gen_point_in(xlo, xhi);
    const double q = *testing::gen_point_in(ylo, yhi);
    RC_LOG() << "x in [" << xlo << ", " << xhi << "] at " << p << ", y in [" << ylo << ", " << yhi
             << "] at " << q << "\n";
    RC_ASSERT(xlo <= p && p <= xhi && ylo <= q && q <= yhi);
    const MpfrInterval box =
        op(MpfrInterval(xlo, xhi, box_precision), MpfrInterval(ylo, yhi, box_precision));
    for (const double u : probes(xlo, xhi, p)) {
        for (const double v : probes(ylo, yhi, q)) {
            RC_LOG() << "at (" << u << ", " << v << ")\n";
            check_contains(box,
                           op(MpfrInterval(u, kPointPrecision), MpfrInterval(v, kPointPrecision)),
                           kind, box_precision);
        }
    }
}

RC_GTEST_PROP(MpfrIntervalProperty, Add, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x + y; });
}
RC_GTEST_PROP(MpfrIntervalProperty, Sub, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x - y; });
}
RC_GTEST_PROP(MpfrIntervalProperty, Mul, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x * y; });
}
RC_GTEST_PROP(MpfrIntervalProperty, Div, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x / y; });
}
RC_GTEST_PROP(MpfrIntervalProperty, Min, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return min(x, y); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Max, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return max(x, y); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Hull, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return hull(x, y); },
                 Kind::kSetOperation);
}
RC_GTEST_PROP(MpfrIntervalProperty, Intersect, ()) {
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return intersect(x, y); },
                 Kind::kSetOperation);
}
RC_GTEST_PROP(MpfrIntervalProperty, Neg, ()) {
    check_unary([](const MpfrInterval& x) { return -x; });
}
RC_GTEST_PROP(MpfrIntervalProperty, Abs, ()) {
    check_unary([](const MpfrInterval& x) { return abs(x); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Square, ()) {
    check_unary([](const MpfrInterval& x) { return square(x); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Pow, ()) {
    const unsigned n = *rc::gen::inRange(0u, 8u);
    RC_LOG() << "n = " << n << "\n";
    check_unary([n](const MpfrInterval& x) { return pow(x, n); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Sqrt, ()) {
    check_unary([](const MpfrInterval& x) { return sqrt(x); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Exp, ()) {
    check_unary([](const MpfrInterval& x) { return exp(x); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Log, ()) {
    check_unary([](const MpfrInterval& x) { return log(x); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Sin, ()) {
    check_unary([](const MpfrInterval& x) { return sin(x); });
}
RC_GTEST_PROP(MpfrIntervalProperty, Cos, ()) {
    check_unary([](const MpfrInterval& x) { return cos(x); });
}
/// Boxes at 24 bits, below the 106 bits of an exact product of doubles: every bound formula
/// rounds, so a wrong rounding direction shows.
RC_GTEST_PROP(MpfrIntervalProperty, ArithmeticAtLowPrecision, ()) {
    constexpr Precision kLow{24};
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x + y; },
                 Kind::kFunction, kLow);
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x - y; },
                 Kind::kFunction, kLow);
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x * y; },
                 Kind::kFunction, kLow);
    check_binary([](const MpfrInterval& x, const MpfrInterval& y) { return x / y; },
                 Kind::kFunction, kLow);
    check_unary([](const MpfrInterval& x) { return square(x); }, kLow);
    check_unary([](const MpfrInterval& x) { return pow(x, 3); }, kLow);
    check_unary([](const MpfrInterval& x) { return sqrt(x); }, kLow);
    check_unary([](const MpfrInterval& x) { return sin(x); }, kLow);
    check_unary([](const MpfrInterval& x) { return cos(x); }, kLow);
}
/// Moderate boxes (|x| ≤ 64) so that sin and cos meet their extrema often.
RC_GTEST_PROP(MpfrIntervalProperty, SinCosNearExtrema, ()) {
    FpEnvGuard guard;
    const int a = *rc::gen::inRange(-4096, 4096);
    const int w = *rc::gen::inRange(0, 400);
    const double lo = std::ldexp(a, -6);
    const double hi = std::ldexp(a + w, -6);
    const double p = *testing::gen_point_in(lo, hi);
    for (const bool is_sin : {true, false}) {
        const auto f = [is_sin](const MpfrInterval& x) { return is_sin ? sin(x) : cos(x); };
        check_contains(f(MpfrInterval(lo, hi, kBoxPrecision)), f(MpfrInterval(p, kPointPrecision)));
    }
}
/// The box built from doubles holds exactly the generated points; the doubles round outward.
RC_GTEST_PROP(MpfrIntervalProperty, BoundsRoundOutward, ()) {
    const auto [lo, hi] = *testing::gen_bounds();
    const double p = *testing::gen_point_in(lo, hi);
    const MpfrInterval box(lo, hi, kBoxPrecision);
    RC_ASSERT(contains(box, p));
    RC_ASSERT(encloses(box.lower_down(), box.upper_up(), box));
    const MpfrInterval third = MpfrInterval(p, kBoxPrecision) / MpfrInterval(3.0, kBoxPrecision);
    RC_ASSERT(encloses(third.lower_down(), third.upper_up(), third));
}

}  // namespace
}  // namespace certray
