// tests/interval/interval_test.cpp — Interval: the canary, the IEEE 1788 case tables, the
// decoration, and RapidCheck properties against the MPFR oracle at 256 bits.
#include "interval/interval.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <bit>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "interval/mpfr_interval.h"
#include "tests/support/fp_env.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"

namespace certray {
namespace {

using testing::describe;
using testing::encloses;

constexpr double kInf = std::numeric_limits<double>::infinity();

// The compiler must not fold these to round-to-nearest points (the known -frounding-math trap).
// The outward steps of the transcendental functions: the next double up and down, as
// std::nextafter gives them, at the special values and the ends of every range.
TEST(IntervalSteps, NextUpAndDownAreNextafter) {
    using L = std::numeric_limits<double>;
    const double values[] = {0.0,
                             -0.0,
                             L::denorm_min(),
                             -L::denorm_min(),
                             L::min(),
                             -L::min(),
                             1.0,
                             -1.0,
                             0.1,
                             -1e300,
                             L::max(),
                             -L::max(),
                             L::infinity(),
                             -L::infinity(),
                             3.0 * L::denorm_min(),
                             2.0};
    for (double v : values) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(detail::next_up(v)),
                  std::bit_cast<std::uint64_t>(std::nextafter(v, L::infinity())))
            << v;
        EXPECT_EQ(std::bit_cast<std::uint64_t>(detail::next_down(v)),
                  std::bit_cast<std::uint64_t>(std::nextafter(v, -L::infinity())))
            << v;
    }
    EXPECT_TRUE(std::isnan(detail::next_up(L::quiet_NaN())));
    EXPECT_TRUE(std::isnan(detail::next_down(L::quiet_NaN())));
}

RC_GTEST_PROP(IntervalSteps, NextUpIsNextafterEverywhere, ()) {
    const double v = std::bit_cast<double>(*rc::gen::arbitrary<std::uint64_t>());
    if (std::isnan(v)) return;
    using L = std::numeric_limits<double>;
    RC_ASSERT(std::bit_cast<std::uint64_t>(detail::next_up(v)) ==
              std::bit_cast<std::uint64_t>(std::nextafter(v, L::infinity())));
    RC_ASSERT(std::bit_cast<std::uint64_t>(detail::next_down(v)) ==
              std::bit_cast<std::uint64_t>(std::nextafter(v, -L::infinity())));
}

RC_GTEST_PROP(IntervalSteps, StepsAreRepeatedNextafter, ()) {
    // step_up/step_down take a shortcut away from 0 and ±inf: n steps of nextafter everywhere,
    // across binades, near the shortcut's edges, the subnormals, 0 and the largest doubles.
    using L = std::numeric_limits<double>;
    const double v = *rc::gen::oneOf(
        rc::gen::map(rc::gen::arbitrary<std::uint64_t>(),
                     [](std::uint64_t b) { return std::bit_cast<double>(b); }),
        rc::gen::map(rc::gen::inRange(-8, 9),
                     [](int k) { return std::ldexp(1.0, 1000) + k * std::ldexp(1.0, 948); }),
        rc::gen::map(rc::gen::inRange(-8, 9),
                     [](int k) { return std::ldexp(1.0, -1000) + k * std::ldexp(1.0, -1052); }),
        rc::gen::element(0.0, -0.0, L::denorm_min(), -L::denorm_min(), L::max(), -L::max(),
                         L::infinity(), -L::infinity(), 1.0, -1.0, 2.0, 0.5));
    if (std::isnan(v)) return;
    const int n = *rc::gen::inRange(0, 9);
    double up = v, down = v;
    for (int i = 0; i < n; ++i) {
        up = std::nextafter(up, L::infinity());
        down = std::nextafter(down, -L::infinity());
    }
    RC_ASSERT(std::bit_cast<std::uint64_t>(detail::step_up(v, n)) ==
              std::bit_cast<std::uint64_t>(up));
    RC_ASSERT(std::bit_cast<std::uint64_t>(detail::step_down(v, n)) ==
              std::bit_cast<std::uint64_t>(down));
}

TEST(IntervalCanary, OneThirdHasPositiveWidth) {
    volatile double one = 1.0, three = 3.0;
    Interval r = Interval(1.0) / Interval(3.0);
    Interval v = Interval(one) / Interval(three);
    EXPECT_LT(r.lower(), r.upper());
    EXPECT_LT(v.lower(), v.upper());
    EXPECT_EQ(r.upper(), std::nextafter(r.lower(), kInf));
    // 3·lo < 1 < 3·hi, decided exactly by MPFR.
    mpfr_t t;
    mpfr_init2(t, 128);
    mpfr_set_d(t, r.lower(), MPFR_RNDN);
    mpfr_mul_ui(t, t, 3, MPFR_RNDN);  // exact at 128 bits
    EXPECT_LT(mpfr_cmp_ui(t, 1), 0);
    mpfr_set_d(t, r.upper(), MPFR_RNDN);
    mpfr_mul_ui(t, t, 3, MPFR_RNDN);
    EXPECT_GT(mpfr_cmp_ui(t, 1), 0);
    mpfr_clear(t);
}

TEST(IntervalCanary, PointOnePlusPointTwoHasPositiveWidth) {
    Interval r = Interval(0.1) + Interval(0.2);
    EXPECT_LT(r.lower(), r.upper());
    EXPECT_TRUE(contains(r, 0.30000000000000004));  // round-to-nearest sum
    EXPECT_TRUE(contains(r, 0.3) || r.lower() > 0.3);
    // The exact sum of the two doubles lies inside.
    MpfrInterval exact = MpfrInterval(0.1) + MpfrInterval(0.2);
    EXPECT_TRUE(encloses(r.lower(), r.upper(), exact)) << describe(exact);
}

TEST(IntervalCanary, UpIntervalInsideScopeMatchesInterval) {
    const int before = std::fegetround();
    Interval safe = Interval(1.0) / Interval(3.0);
    {
        RoundingScope scope;
        UpInterval fast = UpInterval(1.0) / UpInterval(3.0);
        EXPECT_EQ(fast.lower(), safe.lower());
        EXPECT_EQ(fast.upper(), safe.upper());
        UpInterval e = exp(UpInterval(1.0));
        EXPECT_LT(e.lower(), e.upper());
    }
    EXPECT_EQ(std::fegetround(), before);
}

// ---- the caller's floating-point state (tests/support/fp_env.h) ------------------------------
// Whatever a host has set — flush-to-zero and denormals-are-zero, or a directed rounding — the
// library's bounds are those it computes under the default state, and the host's words come back.

TEST(IntervalHostState, FtzDazCallerDoesNotFlushSubnormalBounds) {
    // [-0.5, -0.25] · 2^-1070 = [-2^-1071, -2^-1072] exactly: both bounds are subnormal. With the
    // caller's FTZ|DAZ kept, the product came out [-0, -0], a zero that is not one.
    const testing::FpWords before = testing::read_fp_words();
    {
        testing::HostFpEnv host("ftz-daz");
        const Interval r = (Interval(0, 0.25) - 0.5) * pow(Interval(0.5), 1070);
        EXPECT_EQ(r.lower(), std::ldexp(-1.0, -1071));
        EXPECT_EQ(r.upper(), std::ldexp(-1.0, -1072));
        EXPECT_TRUE(r.defined);
        const testing::FpWords inside = testing::read_fp_words();
        EXPECT_EQ(inside.mxcsr & (testing::kFtz | testing::kDaz), testing::kFtz | testing::kDaz)
            << "the host's words are restored after each operation";
        {
            RoundingScope scope;
            const UpInterval u = UpInterval(std::ldexp(1.0, -1073)) * UpInterval(0.5, 0.5);
            EXPECT_EQ(u.lower(), std::ldexp(1.0, -1074));
            EXPECT_EQ(u.upper(), std::ldexp(1.0, -1074));
            // A subnormal operand is read as itself (DAZ would read it as 0).
            const UpInterval v = UpInterval(std::ldexp(1.0, -1074)) + UpInterval(0.0);
            EXPECT_EQ(v.lower(), std::ldexp(1.0, -1074));
        }
        {
            NearestScope env;
            const double tiny = detail::opaque(std::ldexp(1.0, -1073));
            EXPECT_EQ(detail::opaque(tiny * 0.5), std::ldexp(1.0, -1074));
        }
        EXPECT_TRUE(testing::same_control(testing::read_fp_words(), inside))
            << "scopes restore the host's words";
    }
    EXPECT_TRUE(testing::same_control(testing::read_fp_words(), before));
}

TEST(IntervalHostState, EveryRoundingDirectionGivesTheSameBounds) {
    auto bounds = [] {
        std::vector<double> b;
        for (const Interval& r :
             {Interval(1) / Interval(3), exp(Interval(1)), sqrt(Interval(2)),
              Interval(0.1) + Interval(0.2), sin(Interval(1, 2)), log(Interval(3, 7))}) {
            b.push_back(r.lower());
            b.push_back(r.upper());
        }
        {
            RoundingScope scope;
            const UpInterval u = UpInterval(1) / UpInterval(3) - UpInterval(0.1);
            b.push_back(u.lower());
            b.push_back(u.upper());
        }
        return b;
    };
    const std::vector<double> reference = bounds();
    for (const char* state : {"upward", "downward", "toward-zero", "ftz-daz"}) {
        testing::HostFpEnv host(state);
        const testing::FpWords words = testing::read_fp_words();
        EXPECT_EQ(bounds(), reference) << state;
        EXPECT_TRUE(testing::same_control(testing::read_fp_words(), words)) << state;
    }
}

// The transcendental bounds switch only MXCSR to nearest and leave the x87 control word at the
// scope's upward rounding (WidenedTransc::nearest2): sound only if glibc's binary64 exp, log, sin
// and cos never read that word. They compute in SSE registers; this checks it bit for bit, with the
// x87 word set upward, downward and to 24-bit precision, over values that take every path of
// those functions (tiny, subnormal results, near 1, huge reductions, overflow).
TEST(IntervalHostState, LibmIgnoresTheX87Word) {
#if defined(__GNUC__) && defined(__x86_64__)
    std::vector<double> xs = {0.0,    -0.0,  1.0,    -1.0, 0.5,   1e-300, 5e-324,  709.78,
                              -745.1, 710.0, -746.0, 1e22, -1e22, 1e300,  3.14159, 1.5707963};
    std::uint64_t state = 0x9e3779b97f4a7c15u;
    for (int i = 0; i < 20000; ++i) {  // magnitudes 2^-60 .. 2^60, both signs, and near 1
        state = state * 6364136223846793005u + 1442695040888963407u;
        const double m = static_cast<double>(state >> 11) * 0x1p-53;
        const int e = static_cast<int>((state >> 3) % 121) - 60;
        xs.push_back((state & 1 ? -1 : 1) * std::ldexp(1 + m, e));
        xs.push_back(1 + (m - 0.5) * 0x1p-20);
    }
    auto values = [&] {
        std::vector<double> v;
        for (double x : xs) {
            x = detail::opaque(x);
            v.push_back(detail::opaque(std::exp(x)));
            v.push_back(detail::opaque(std::log(std::fabs(x))));
            v.push_back(detail::opaque(std::sin(x)));
            v.push_back(detail::opaque(std::cos(x)));
        }
        return v;
    };
    const testing::FpWords before = testing::read_fp_words();
    testing::FpWords nearest = before;
    nearest.mxcsr = 0x1f80;
    nearest.x87 = 0x037f;
    testing::write_fp_words(nearest);
    const std::vector<double> reference = values();
    for (const std::uint16_t x87 : {std::uint16_t{0x0b7f}, std::uint16_t{0x077f},
                                    std::uint16_t{0x007f}}) {  // up, down, 24-bit precision
        testing::FpWords w = nearest;
        w.x87 = x87;
        testing::write_fp_words(w);
        const std::vector<double> got = values();
        testing::write_fp_words(nearest);
        ASSERT_EQ(got.size(), reference.size());
        for (std::size_t k = 0; k < got.size(); ++k) {
            ASSERT_EQ(std::bit_cast<std::uint64_t>(got[k]),
                      std::bit_cast<std::uint64_t>(reference[k]))
                << "x87 word 0x" << std::hex << x87 << ": function " << std::dec << k % 4
                << " of x = " << xs[k / 4];
        }
    }
    testing::write_fp_words(before);
#else
    GTEST_SKIP() << "x86-64 only";
#endif
}

TEST(IntervalCases, DivisionIsSetBased) {
    auto check = [](Interval a, Interval b, double lo, double hi) {
        Interval r = a / b;
        EXPECT_EQ(r.lower(), lo) << "[" << a.lower() << "," << a.upper() << "]/[" << b.lower()
                                 << "," << b.upper() << "]";
        EXPECT_EQ(r.upper(), hi);
        EXPECT_FALSE(r.defined);
    };
    check(Interval(1, 2), Interval(0, 1), 1, kInf);
    check(Interval(-30, 0), Interval(-3, 0), 0, kInf);
    check(Interval(-2, -1), Interval(0, 4), -kInf, -0.25);
    check(Interval(-2, 1), Interval(0, 4), -kInf, kInf);
    check(Interval(1, 2), Interval(-1, 1), -kInf, kInf);
    check(Interval(0, 0), Interval(-1, 1), 0, 0);
    EXPECT_TRUE((Interval(1, 2) / Interval(0, 0)).is_empty());
    Interval ok = Interval(1, 2) / Interval(4, 8);
    EXPECT_EQ(ok.lower(), 0.125);
    EXPECT_EQ(ok.upper(), 0.5);
    EXPECT_TRUE(ok.defined);
}

TEST(IntervalCases, DomainsIntersect) {
    Interval s = sqrt(Interval(-5, 25));
    EXPECT_EQ(s.lower(), 0);
    EXPECT_EQ(s.upper(), 5);
    EXPECT_FALSE(s.defined);
    EXPECT_TRUE(sqrt(Interval(4, 9)).defined);
    EXPECT_TRUE(sqrt(Interval(-2, -1)).is_empty());
    Interval l = log(Interval(0, 1));
    EXPECT_EQ(l.lower(), -kInf);
    EXPECT_EQ(l.upper(), 0);
    EXPECT_FALSE(l.defined);
    EXPECT_TRUE(log(Interval(-3, 0)).is_empty());
    EXPECT_TRUE(log(Interval(0.5, 2)).defined);
}

TEST(IntervalCases, ExactValues) {
    EXPECT_EQ(exp(Interval(0.0)).lower(), 1.0);
    EXPECT_EQ(exp(Interval(0.0)).upper(), 1.0);
    EXPECT_EQ(log(Interval(1.0)).lower(), 0.0);
    EXPECT_EQ(log(Interval(1.0)).upper(), 0.0);
    Interval c = cos(Interval(0.0, 7.0));
    EXPECT_EQ(c.lower(), -1.0);
    EXPECT_EQ(c.upper(), 1.0);
    Interval sq = square(Interval(-3, 2));
    EXPECT_EQ(sq.lower(), 0);
    EXPECT_EQ(sq.upper(), 9);
    Interval p = pow(Interval(-2, 1), 3);
    EXPECT_EQ(p.lower(), -8);
    EXPECT_EQ(p.upper(), 1);
    EXPECT_EQ(pow(Interval(-2, 1), 0).lower(), 1);
    EXPECT_EQ(pow(Interval(0, 0), 0).upper(), 1);
    Interval a = abs(Interval(-3, 2));
    EXPECT_EQ(a.lower(), 0);
    EXPECT_EQ(a.upper(), 3);
    Interval mn = min(Interval(0, 5), Interval(1, 2));
    EXPECT_EQ(mn.lower(), 0);
    EXPECT_EQ(mn.upper(), 2);
    Interval z = Interval(0, 0) * Interval::entire();
    EXPECT_EQ(z.lower(), 0);
    EXPECT_EQ(z.upper(), 0);
}

TEST(IntervalCases, SinAndCosReachTheirExtremaExactlyWhereMathematicsPutsThem) {
    // π ∈ [3, 3.3]: cos reaches −1 there; on [3.2, 3.3] (past π, below 2π) cos increases, so the
    // range is [cos 3.2, cos 3.3] (-0.99829… and -0.98747…), with no ±1.
    const Interval c1 = cos(Interval(3, 3.3));
    EXPECT_EQ(c1.lower(), -1.0);
    EXPECT_GT(c1.upper(), -0.98748);
    EXPECT_LT(c1.upper(), -0.98746);
    const Interval c2 = cos(Interval(3.2, 3.3));
    EXPECT_GT(c2.lower(), -0.99830);
    EXPECT_LT(c2.lower(), -0.99829);
    EXPECT_LT(c2.upper(), -0.98746);
    // sin: 1 at π/2 ∈ [1.5, 1.6], −1 at −π/2, 1 again at 5π/2 ∈ [7.8, 7.9], −1 at 3π/2 only.
    EXPECT_EQ(sin(Interval(1.5, 1.6)).upper(), 1.0);
    EXPECT_GT(sin(Interval(1.5, 1.6)).lower(), 0.997);  // sin 1.5 = 0.99749…
    EXPECT_EQ(sin(Interval(-1.6, -1.5)).lower(), -1.0);
    EXPECT_EQ(sin(Interval(7.8, 7.9)).upper(), 1.0);
    const Interval s3 = sin(Interval(4.6, 4.8));  // 3π/2 = 4.712…
    EXPECT_EQ(s3.lower(), -1.0);
    EXPECT_LT(s3.upper(), -0.99);  // sin 4.6 = −0.99369…, sin 4.8 = −0.99616…
    // Both extrema inside, or a whole period: [−1, 1].
    const Interval both = cos(Interval(3, 6.5));
    EXPECT_EQ(both.lower(), -1.0);
    EXPECT_EQ(both.upper(), 1.0);
    // Exact at 0, and the arguments where k is too large to know its parity give [−1, 1].
    EXPECT_EQ(sin(Interval(0.0)).lower(), 0.0);
    EXPECT_EQ(sin(Interval(0.0)).upper(), 0.0);
    EXPECT_EQ(cos(Interval(0.0)).lower(), 1.0);
    const Interval huge = sin(Interval(1e300));
    EXPECT_EQ(huge.lower(), -1.0);
    EXPECT_EQ(huge.upper(), 1.0);
}

TEST(IntervalCases, EmptyAndUnbounded) {
    Interval e = Interval::empty();
    EXPECT_TRUE(e.is_empty());
    EXPECT_FALSE(e.defined);
    EXPECT_TRUE((e + Interval(1)).is_empty());
    EXPECT_TRUE(sin(e).is_empty());
    EXPECT_TRUE(Interval(2, 1).is_empty());
    EXPECT_TRUE(Interval(std::nan("")).is_empty());
    Interval w = Interval::entire();
    EXPECT_TRUE((w + w).lower() == -kInf && (w + w).upper() == kInf);
    EXPECT_TRUE((w - w).lower() == -kInf && (w - w).upper() == kInf);
    Interval s = sin(Interval(1, kInf));
    EXPECT_EQ(s.lower(), -1);
    EXPECT_EQ(s.upper(), 1);
    Interval ex = exp(Interval(-kInf, 0));
    EXPECT_EQ(ex.lower(), 0);
    EXPECT_EQ(ex.upper(), 1);
    Interval big = exp(Interval(710, 720));
    EXPECT_EQ(big.upper(), kInf);
    EXPECT_GT(big.lower(), 1e308);
}

TEST(IntervalCases, Comparisons) {
    Interval a(1, 2), b(3, 4), c(2, 3);
    EXPECT_TRUE(certainly_lt(a, b));
    EXPECT_FALSE(certainly_lt(a, c));
    EXPECT_TRUE(certainly_le(a, c));
    EXPECT_TRUE(possibly_lt(c, a) == false);
    EXPECT_TRUE(possibly_le(c, a));
    EXPECT_TRUE(possibly_gt(c, a));
    EXPECT_TRUE(possibly_zero(Interval(-1, 1)));
    EXPECT_FALSE(possibly_zero(Interval(1e-300, 1)));
}

// ---- properties: the interval result contains the 256-bit MPFR result at points of the box -----

template <class T>
T one(const T&) {
    return T(1.0);
}

using testing::gen_bounds;
using testing::gen_point_in;

template <class IntervalOp, class MpfrOp>
void check_unary(IntervalOp iop, MpfrOp mop) {
    const auto [lo, hi] = *gen_bounds();
    const double p = *gen_point_in(lo, hi);
    const Interval r = testing::as_host([&] { return iop(Interval(lo, hi)); });
    const MpfrInterval exact = mop(MpfrInterval(p));
    RC_ASSERT(encloses(r.lower(), r.upper(), exact));
    // The decoration never claims definedness where the function is undefined at a point.
    if (r.defined) RC_ASSERT(!exact.is_empty());
    // The fast variant gives the same bounds.
    const UpInterval f = testing::as_host([&] {
        RoundingScope scope;
        return iop(UpInterval(lo, hi));
    });
    RC_ASSERT(f.is_empty() == r.is_empty());
    if (!r.is_empty()) RC_ASSERT(f.lower() == r.lower() && f.upper() == r.upper());
}

template <class IntervalOp, class MpfrOp>
void check_binary(IntervalOp iop, MpfrOp mop) {
    const auto [alo, ahi] = *gen_bounds();
    const auto [blo, bhi] = *gen_bounds();
    const double p = *gen_point_in(alo, ahi);
    const double q = *gen_point_in(blo, bhi);
    const Interval r =
        testing::as_host([&] { return iop(Interval(alo, ahi), Interval(blo, bhi)); });
    const MpfrInterval exact = mop(MpfrInterval(p), MpfrInterval(q));
    RC_ASSERT(encloses(r.lower(), r.upper(), exact));
    if (r.defined) RC_ASSERT(!exact.is_empty());
    const UpInterval f = testing::as_host([&] {
        RoundingScope scope;
        return iop(UpInterval(alo, ahi), UpInterval(blo, bhi));
    });
    RC_ASSERT(f.is_empty() == r.is_empty());
    if (!r.is_empty()) RC_ASSERT(f.lower() == r.lower() && f.upper() == r.upper());
}

#define CERTRAY_UNARY_PROP(name, expr)                                                        \
    RC_GTEST_PROP(IntervalProperty, name, ()) {                                               \
        check_unary([](auto x) { return expr; }, [](const MpfrInterval& x) { return expr; }); \
    }
#define CERTRAY_BINARY_PROP(name, expr)                                                  \
    RC_GTEST_PROP(IntervalProperty, name, ()) {                                          \
        check_binary([](auto x, auto y) { return expr; },                                \
                     [](const MpfrInterval& x, const MpfrInterval& y) { return expr; }); \
    }

// The branch-free kernels of + − × give exactly what Boost's own operations give (with the same
// repair for inf − inf and 0·inf): the kernels are an optimisation, not new mathematics. Bounds
// compare with ==, so only the sign of a zero bound may differ.
RC_GTEST_PROP(IntervalProperty, KernelsMatchBoost, ()) {
    const auto [alo, ahi] = *gen_bounds();
    const auto [blo, bhi] = *gen_bounds();
    const Interval a(alo, ahi), b(blo, bhi);
    const auto same = [](const Interval& x, const Interval& y) {
        if (x.is_empty() || y.is_empty()) return x.is_empty() == y.is_empty();
        return x.lower() == y.lower() && x.upper() == y.upper() && x.defined == y.defined;
    };
    RC_ASSERT(same(a + b, detail::boost_add(a, b)));
    RC_ASSERT(same(a - b, detail::boost_sub(a, b)));
    RC_ASSERT(same(a * b, detail::boost_mul(a, b)));
    RoundingScope scope;
    const UpInterval ua(alo, ahi), ub(blo, bhi);
    RC_ASSERT(same(Interval(ua * ub), Interval(detail::boost_mul(ua, ub))));
    RC_ASSERT(same(Interval(ua + ub), Interval(detail::boost_add(ua, ub))));
}

CERTRAY_UNARY_PROP(Neg, -x)
CERTRAY_UNARY_PROP(Abs, abs(x))
CERTRAY_UNARY_PROP(Square, square(x))
CERTRAY_UNARY_PROP(Pow3, pow(x, 3u))
CERTRAY_UNARY_PROP(Pow4, pow(x, 4u))
CERTRAY_UNARY_PROP(Pow7, pow(x, 7u))
CERTRAY_UNARY_PROP(Sqrt, sqrt(x))
CERTRAY_UNARY_PROP(Exp, exp(x))
CERTRAY_UNARY_PROP(Log, log(x))
CERTRAY_UNARY_PROP(Sin, sin(x))
CERTRAY_UNARY_PROP(Cos, cos(x))
CERTRAY_BINARY_PROP(Add, x + y)
CERTRAY_BINARY_PROP(Sub, x - y)
CERTRAY_BINARY_PROP(Mul, x* y)
CERTRAY_BINARY_PROP(Div, x / y)
CERTRAY_BINARY_PROP(Min, min(x, y))
CERTRAY_BINARY_PROP(Max, max(x, y))

// Composite: the decoration of a whole expression, and containment through several roundings.
CERTRAY_BINARY_PROP(Composite,
                    sqrt(square(x) + square(y)) - exp(sin(x) * cos(y)) / (abs(y) + one(y)))

}  // namespace
}  // namespace certray
