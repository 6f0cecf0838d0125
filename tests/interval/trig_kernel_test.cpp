// tests/interval/trig_kernel_test.cpp — interval/trig_kernel.h: its constants against MPFR, its
// point bounds against MPFR's sin and cos at random and chosen points (both sides, within a few
// ulps plus the reduction's absolute error), and the interval sin and cos built on it (enclosing
// MPFR's range over random intervals, as tight, exact at 0, the libm path past 2¹⁹).
#include "interval/trig_kernel.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "tests/support/mpfr_oracle.h"

namespace certray {
namespace {

#ifdef CERTRAY_X86_64_ROUNDING

using Big = testing::Mpfr256;

/// How far a bound may lie from the value it bounds: kRelative·2⁻⁵²·|value| + kAbsolute (the
/// reduction: |k|·2⁻⁸⁷ and the roundings of x − k·P1 and k·P2, below 2⁻⁶² for |x| ≤ 2¹⁹).
constexpr double kRelative = 3, kAbsolute = 0x1p-62;

TEST(TrigKernel, Coefficients) {
    using K = detail::TrigKernel;
    for (unsigned i = 0; i < 9; ++i) {
        for (const bool cosine : {true, false}) {
            Big f, lo, hi;
            mpfr_fac_ui(f.v, cosine ? 2 * i : 2 * i + 1, MPFR_RNDN);  // exact
            mpfr_si_div(lo.v, i % 2 == 0 ? 1 : -1, f.v, MPFR_RNDD);
            mpfr_si_div(hi.v, i % 2 == 0 ? 1 : -1, f.v, MPFR_RNDU);
            const double l = cosine ? K::kCosLo[i] : K::kSinLo[i];
            const double h = cosine ? K::kCosHi[i] : K::kSinHi[i];
            EXPECT_GE(mpfr_cmp_d(lo.v, l), 0) << i << " " << cosine;  // l ≤ cᵢ
            EXPECT_LE(mpfr_cmp_d(hi.v, h), 0) << i << " " << cosine;  // cᵢ ≤ h
            EXPECT_TRUE(l == h || std::nextafter(l, 1.0) == h) << i << " " << cosine;
        }
    }
    // The remainder's coefficient: [−1/18!, 0] and [−1/19!, 0], the alternating series' terms
    // decreasing for w ≤ 0.618 (w/((2i + 1)(2i + 2)) < 1 from i = 9 on).
    for (const bool cosine : {true, false}) {
        Big f, lo;
        mpfr_fac_ui(f.v, cosine ? 18 : 19, MPFR_RNDN);
        mpfr_si_div(lo.v, -1, f.v, MPFR_RNDD);
        EXPECT_GE(mpfr_cmp_d(lo.v, cosine ? K::kCosLo[9] : K::kSinLo[9]), 0);
        EXPECT_EQ(cosine ? K::kCosHi[9] : K::kSinHi[9], 0.0);
    }
}

TEST(TrigKernel, SplitOfHalfPi) {
    using K = detail::TrigKernel;
    Big pi, half, rest, err;
    mpfr_const_pi(pi.v, MPFR_RNDN);  // within 2⁻²⁵⁵ of π
    mpfr_div_2ui(half.v, pi.v, 1, MPFR_RNDN);
    EXPECT_GT(mpfr_cmp_d(half.v, K::kP1), 0);
    // P1 has at most 32 significant bits, so k·P1 is exact for |k| < 2²¹.
    const double scaled = std::ldexp(K::kP1, 31);
    EXPECT_EQ(scaled, std::floor(scaled));
    mpfr_sub_d(rest.v, half.v, K::kP1, MPFR_RNDN);
    mpfr_sub_d(err.v, rest.v, K::kP2, MPFR_RNDN);
    mpfr_abs(err.v, err.v, MPFR_RNDN);
    mpfr_mul_d(err.v, err.v, 1.5, MPFR_RNDU);  // room for MPFR's own error
    EXPECT_LT(mpfr_cmp_d(err.v, K::kSlack), 0);
    // π's bounds, and 2/π near enough that |r| < 0.786 for |x| ≤ 2¹⁹: |k − 2x/π| ≤ ½ + 2⁻³².
    EXPECT_LT(mpfr_cmp_d(pi.v, K::kPiHi), 0);
    EXPECT_GT(mpfr_cmp_d(pi.v, K::kPiLo), 0);
    EXPECT_EQ(std::nextafter(K::kPiLo, 4.0), K::kPiHi);
    Big two_over_pi;
    mpfr_ui_div(two_over_pi.v, 2, pi.v, MPFR_RNDN);
    mpfr_sub_d(err.v, two_over_pi.v, K::kTwoOverPi, MPFR_RNDN);
    mpfr_abs(err.v, err.v, MPFR_RNDN);
    EXPECT_LT(mpfr_cmp_d(err.v, 0x1p-53), 0);
    EXPECT_TRUE(detail::trig_kernel_applies(0x1p19));
    EXPECT_FALSE(detail::trig_kernel_applies(std::nextafter(0x1p19, 1e300)));
    EXPECT_FALSE(detail::trig_kernel_applies(std::nan("")));
}

/// The point kernel's lower and upper bound of sin(x) or cos(x) (lane 0 side −1, lane 1 side +1).
std::array<double, 2> point(double x, bool cosine) {
    RoundingScope up;
    __m128d xv = _mm_set1_pd(x);
    asm volatile("" : "+x"(xv));
    __m128d r = detail::trig_point<detail::KernelSse2>(xv, _mm_set_pd(1.0, -1.0), cosine);
    asm volatile("" : "+x"(r));
    return {-_mm_cvtsd_f64(r), _mm_cvtsd_f64(_mm_unpackhi_pd(r, r))};
}

/// Empty when [lo, hi] encloses `exact` and lies within the tolerance of it; otherwise what failed.
std::string within(double lo, double hi, const MpfrInterval& exact, const std::string& what) {
    std::ostringstream out;
    out.precision(17);
    out << what << ": [" << lo << ", " << hi << "] against " << testing::describe(exact);
    if (!testing::encloses(lo, hi, exact)) return out.str() + ": not enclosed";
    const double elo = exact.lower(), ehi = exact.upper();  // rounded outward
    if (elo - lo > kRelative * 0x1p-52 * std::fabs(elo) + kAbsolute ||
        hi - ehi > kRelative * 0x1p-52 * std::fabs(ehi) + kAbsolute) {
        return out.str() + ": wider than the tolerance";
    }
    return "";
}

std::string check_point(double x) {
    std::string m;
    for (const bool cosine : {false, true}) {
        const std::array<double, 2> b = point(x, cosine);
        const MpfrInterval v(x);
        std::ostringstream what;
        what.precision(17);
        what << (cosine ? "cos " : "sin ") << x;
        m += within(b[0], b[1], cosine ? cos(v) : sin(v), what.str());
    }
    return m;
}

TEST(TrigKernel, PointBoundsAtChosenPoints) {
    std::vector<double>
        xs = {0.0, -0.0, 5e-324, -5e-324, 1e-300,  -1e-310, 1e-17,   1e-8,
              0.5, 0.78, 0.7854, 1,       -1,      2,       3,       3.1416,
              10,  -100, 1e4,    0x1p19,  -0x1p19, 355.0,   103993.0};  // 355 and 103993 lie near
                                                                        // multiples of π
    // Next to multiples of π/4 (where k and the branch change), a few ulps either side; near
    // kπ the values are small and the reduction's absolute error shows.
    for (int k = -667544; k <= 667544; k += 4099) {
        double x = k * 0.7853981633974483;
        for (int s = 0; s < 3; ++s) x = std::nextafter(x, -INFINITY);
        for (int s = 0; s < 6; ++s, x = std::nextafter(x, INFINITY)) {
            if (detail::trig_kernel_applies(x)) xs.push_back(x);
        }
    }
    for (double x : xs) EXPECT_EQ(check_point(x), "");
}

RC_GTEST_PROP(TrigKernel, PointBoundsAtRandomPoints, ()) {
    const int kind = *rc::gen::inRange(0, 3);
    double x = 0;
    if (kind == 0) {
        x = *rc::gen::inRange(-10000000, 10000001) * 1e-6;
    } else if (kind == 1) {  // small magnitudes, down to the subnormals
        x = std::ldexp(*rc::gen::inRange(1, 1 << 30) * 0x1p-30, *rc::gen::inRange(-1074, 1)) *
            (*rc::gen::arbitrary<bool>() ? 1 : -1);
    } else {  // the whole domain
        x = *rc::gen::inRange(-(1 << 19), 1 << 19) + *rc::gen::inRange(0, 1 << 30) * 0x1p-30;
    }
    RC_PRE(detail::trig_kernel_applies(x));
    RC_ASSERT(check_point(x) == "");
}

/// Empty when sin and cos of [l, u] enclose MPFR's range and lie within the tolerance of it.
std::string check_interval(double l, double u) {
    std::string m;
    for (const bool sine : {true, false}) {
        const Interval v = sine ? sin(Interval(l, u)) : cos(Interval(l, u));
        const MpfrInterval exact = sine ? sin(MpfrInterval(l, u)) : cos(MpfrInterval(l, u));
        std::ostringstream what;
        what.precision(17);
        what << (sine ? "sin [" : "cos [") << l << ", " << u << "]";
        m += within(v.lower(), v.upper(), exact, what.str());
    }
    return m;
}

RC_GTEST_PROP(TrigKernel, IntervalsEncloseTheRange, ()) {
    const int kind = *rc::gen::inRange(0, 3);
    double l = 0, width = 0;
    if (kind == 0) {  // around the first periods, any width up to beyond 2π
        l = *rc::gen::inRange(-20000000, 20000001) * 1e-6;
        width = *rc::gen::inRange(0, 7000001) * 1e-6;
    } else if (kind == 1) {  // narrow, anywhere in the domain
        l = *rc::gen::inRange(-(1 << 19), 1 << 19) + *rc::gen::inRange(0, 1 << 30) * 0x1p-30;
        width = std::ldexp(*rc::gen::inRange(0, 1 << 20) * 0x1p-20, *rc::gen::inRange(-60, 3));
    } else {  // an extremum kπ/2 near an end
        const int k = *rc::gen::inRange(-1000, 1001);
        l = k * 1.5707963267948966 +
            *rc::gen::inRange(-1000, 1001) * std::ldexp(1.0, *rc::gen::inRange(-52, -2));
        width = std::ldexp(*rc::gen::inRange(1, 1 << 20) * 0x1p-20, *rc::gen::inRange(-52, 1));
    }
    const double u = l + width;  // rounded to nearest: any u ≥ l
    RC_PRE(detail::trig_kernel_applies(l) && detail::trig_kernel_applies(u));
    RC_ASSERT(check_interval(l, u) == "");
}

TEST(TrigKernel, IntervalsAtTheEdges) {
    const double inf = std::numeric_limits<double>::infinity();
    const double pi = 3.141592653589793;
    const double cases[][2] = {{0, 0},
                               {-0.0, 0.0},
                               {-1, 1},
                               {0, pi},
                               {-pi, pi},
                               {pi / 2, pi / 2},
                               {1, 1 + 2 * pi},
                               {1, 1 + 6.28},
                               {0x1p19, 0x1p19},
                               {0x1p19 - 1, 0x1p19 + 1},  // past the kernel's domain: libm
                               {-0x1p20, -0x1p19},
                               {5e-324, 1e-300},
                               {-inf, 0},
                               {2, 2}};
    for (const auto& c : cases) EXPECT_EQ(check_interval(c[0], c[1]), "");
    // Exact at 0 and where an extremum is certainly inside.
    EXPECT_EQ(sin(Interval(0.0)).lower(), 0.0);
    EXPECT_EQ(sin(Interval(0.0)).upper(), 0.0);
    EXPECT_EQ(cos(Interval(0.0)).lower(), 1.0);
    EXPECT_EQ(cos(Interval(0.0)).upper(), 1.0);
    EXPECT_EQ(cos(Interval(-1.0, 1.0)).upper(), 1.0);
    EXPECT_EQ(sin(Interval(1.0, 2.0)).upper(), 1.0);
    EXPECT_EQ(sin(Interval(4.0, 5.0)).lower(), -1.0);
    // Monotone pieces: no extremum claimed (cos 1 = 0.5403…, cos 2 = −0.4161…).
    const Interval c = cos(Interval(1.0, 2.0));
    EXPECT_GT(c.lower(), -0.42);
    EXPECT_LT(c.upper(), 0.55);
    const Interval s = sin(Interval(2.0, 4.0));  // sin 2 = 0.9092…, sin 4 = −0.7568…
    EXPECT_GT(s.lower(), -0.76);
    EXPECT_LT(s.upper(), 0.91);
}

#endif

}  // namespace
}  // namespace certray
