// tests/interval/trig_kernel_test.cpp — interval/trig_kernel.h: its constants against MPFR, its
// point bounds against MPFR's sin and cos at random and chosen points (both sides, within a few
// ulps plus the reduction's absolute error), and the interval sin and cos built on it (enclosing
// MPFR's range over random intervals, as tight, exact at 0, the libm path past 2¹⁹). The binary32
// kernel (interval/trig_kernel_f32.h) likewise: constants, point bounds within 2⁻¹⁸·|f| + 2⁻²⁶,
// intervals enclosing MPFR's range.
#include "interval/trig_kernel.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "interval/trig_kernel_f32.h"
#include "tests/support/mpfr_oracle.h"

namespace certray {
namespace {

#ifdef CERTRAY_X86_64_ROUNDING

using Big = testing::Mpfr256;

/// How far a bound may lie from the value it bounds: relative·|value| + absolute.
struct Tolerance {
    double relative, absolute;
};
/// The double kernel: 3·2⁻⁵² relatively, plus the reduction's |k|·2⁻⁸⁷ and the roundings of
/// x − k·P1 and k·P2, below 2⁻⁶² for |x| ≤ 2¹⁹.
constexpr Tolerance kDouble{3 * 0x1p-52, 0x1p-62};
/// The binary32 kernel: its roundings within 2⁻¹⁸ relatively, the reduction's below 2⁻²⁶.
constexpr Tolerance kBinary32{0x1p-18, 0x1p-26};

/// K's coefficient tables against MPFR: N − 1 bounds of (−1)ⁱ/(2i)! (cos) and (−1)ⁱ/(2i + 1)!
/// (sin), equal or adjacent numbers of K's type, and the remainder's coefficient [−1/(2N − 2)!, 0]
/// and [−1/(2N − 1)!, 0] (the alternating series' terms decrease for w ≤ 0.618).
template <class K>
void check_coefficients() {
    constexpr unsigned n = std::size(K::kCosLo);
    using T = std::remove_cvref_t<decltype(K::kCosLo[0])>;
    for (unsigned i = 0; i + 1 < n; ++i) {
        for (const bool cosine : {true, false}) {
            Big f, lo, hi;
            mpfr_fac_ui(f.v, cosine ? 2 * i : 2 * i + 1, MPFR_RNDN);  // exact
            mpfr_si_div(lo.v, i % 2 == 0 ? 1 : -1, f.v, MPFR_RNDD);
            mpfr_si_div(hi.v, i % 2 == 0 ? 1 : -1, f.v, MPFR_RNDU);
            const T l = cosine ? K::kCosLo[i] : K::kSinLo[i];
            const T h = cosine ? K::kCosHi[i] : K::kSinHi[i];
            EXPECT_GE(mpfr_cmp_d(lo.v, l), 0) << i << " " << cosine;  // l ≤ cᵢ
            EXPECT_LE(mpfr_cmp_d(hi.v, h), 0) << i << " " << cosine;  // cᵢ ≤ h
            EXPECT_TRUE(l == h || std::nextafter(l, T{1}) == h) << i << " " << cosine;
        }
    }
    for (const bool cosine : {true, false}) {
        Big f, lo;
        mpfr_fac_ui(f.v, cosine ? 2 * n - 2 : 2 * n - 1, MPFR_RNDN);
        mpfr_si_div(lo.v, -1, f.v, MPFR_RNDD);
        EXPECT_GE(mpfr_cmp_d(lo.v, cosine ? K::kCosLo[n - 1] : K::kSinLo[n - 1]), 0);
        EXPECT_EQ(cosine ? K::kCosHi[n - 1] : K::kSinHi[n - 1], T{0});
    }
}

/// K's split of π/2 against MPFR: P1 below π/2 with at most `p1_bits` significant bits, P2's error
/// (with room for MPFR's own) below the slack, π's bounds adjacent numbers of K's type either side
/// of π, and 2/π within `two_over_pi_error`.
template <class K>
void check_split_of_half_pi(int p1_bits, double two_over_pi_error) {
    using T = std::remove_cvref_t<decltype(K::kP1)>;
    Big pi, half, rest, err;
    mpfr_const_pi(pi.v, MPFR_RNDN);  // within 2⁻²⁵⁵ of π
    mpfr_div_2ui(half.v, pi.v, 1, MPFR_RNDN);
    EXPECT_GT(mpfr_cmp_d(half.v, K::kP1), 0);
    const double scaled = std::ldexp(static_cast<double>(K::kP1), p1_bits - 1);
    EXPECT_EQ(scaled, std::floor(scaled));
    mpfr_sub_d(rest.v, half.v, K::kP1, MPFR_RNDN);
    mpfr_sub_d(err.v, rest.v, K::kP2, MPFR_RNDN);
    mpfr_abs(err.v, err.v, MPFR_RNDN);
    mpfr_mul_d(err.v, err.v, 1.5, MPFR_RNDU);
    EXPECT_LT(mpfr_cmp_d(err.v, K::kSlack), 0);
    EXPECT_LT(mpfr_cmp_d(pi.v, K::kPiHi), 0);
    EXPECT_GT(mpfr_cmp_d(pi.v, K::kPiLo), 0);
    EXPECT_EQ(std::nextafter(K::kPiLo, T{4}), K::kPiHi);
    Big two_over_pi;
    mpfr_ui_div(two_over_pi.v, 2, pi.v, MPFR_RNDN);
    mpfr_sub_d(err.v, two_over_pi.v, K::kTwoOverPi, MPFR_RNDN);
    mpfr_abs(err.v, err.v, MPFR_RNDN);
    EXPECT_LT(mpfr_cmp_d(err.v, two_over_pi_error), 0);
}

TEST(TrigKernel, Coefficients) { check_coefficients<detail::TrigKernel>(); }

TEST(TrigKernel, SplitOfHalfPi) {
    // P1 has at most 32 significant bits, so k·P1 is exact for |k| < 2²¹; 2/π near enough that
    // |r| < 0.786 for |x| ≤ 2¹⁹: |k − 2x/π| ≤ ½ + 2⁻³².
    check_split_of_half_pi<detail::TrigKernel>(32, 0x1p-53);
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

/// Empty when [lo, hi] encloses `exact` and lies within the tolerance `tol` of it; otherwise what
/// failed.
std::string within(double lo, double hi, const MpfrInterval& exact, const std::string& what,
                   Tolerance tol) {
    std::ostringstream out;
    out.precision(17);
    out << what << ": [" << lo << ", " << hi << "] against " << testing::describe(exact);
    if (!testing::encloses(lo, hi, exact)) return out.str() + ": not enclosed";
    const double elo = exact.lower(), ehi = exact.upper();  // rounded outward
    if (elo - lo > tol.relative * std::fabs(elo) + tol.absolute ||
        hi - ehi > tol.relative * std::fabs(ehi) + tol.absolute) {
        return out.str() + ": wider than the tolerance";
    }
    return "";
}

/// The binary32 point kernel's lower and upper bound of sin(x) or cos(x).
std::array<double, 2> point(float x, bool cosine) {
    float b[2];
    RoundingScope up;
    detail::trig_f32_point_bounds(x, cosine, b);
    return {b[0], b[1]};
}

/// The double or (x a float) the binary32 kernel's kind, for messages, and its tolerance.
template <class T>
constexpr const char* kind_of = std::is_same_v<T, float> ? "binary32 " : "";
template <class T>
constexpr Tolerance tolerance_of = std::is_same_v<T, float> ? kBinary32 : kDouble;

/// Empty when the point kernel of x's type bounds sin(x) and cos(x) within its tolerance of MPFR.
template <class T>
std::string check_point(T x) {
    std::string m;
    for (const bool cosine : {false, true}) {
        const std::array<double, 2> b = point(x, cosine);
        const MpfrInterval v(static_cast<double>(x));
        std::ostringstream what;
        what.precision(17);
        what << kind_of<T> << (cosine ? "cos " : "sin ") << x;
        m += within(b[0], b[1], cosine ? cos(v) : sin(v), what.str(), tolerance_of<T>);
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

/// sin (sine) or cos of [l, u]: by the scalar Interval (its double kernel, or libm past 2¹⁹), or
/// (l and u floats) by the binary32 kernel.
std::array<double, 2> interval_bounds(double l, double u, bool sine) {
    const Interval v = sine ? sin(Interval(l, u)) : cos(Interval(l, u));
    return {v.lower(), v.upper()};
}
std::array<double, 2> interval_bounds(float l, float u, bool sine) {
    float b[2];
    RoundingScope up;
    detail::trig_f32_interval_bounds(l, u, sine, b);
    return {b[0], b[1]};
}

/// Empty when sin and cos of [l, u] (by interval_bounds of their type) enclose MPFR's range and
/// lie within the tolerance of it.
template <class T>
std::string check_interval(T l, T u) {
    std::string m;
    for (const bool sine : {true, false}) {
        const std::array<double, 2> b = interval_bounds(l, u, sine);
        const MpfrInterval range(static_cast<double>(l), static_cast<double>(u));
        const MpfrInterval exact = sine ? sin(range) : cos(range);
        std::ostringstream what;
        what.precision(17);
        what << kind_of<T> << (sine ? "sin [" : "cos [") << l << ", " << u << "]";
        m += within(b[0], b[1], exact, what.str(), tolerance_of<T>);
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

// ---- the binary32 kernel (interval/trig_kernel_f32.h) -------------------------------------------

TEST(TrigKernelF32, Coefficients) { check_coefficients<detail::TrigKernelF32>(); }

TEST(TrigKernelF32, SplitOfHalfPi) {
    // P1 has at most 15 significant bits, so k·P1 is exact in binary32 for |k| < 2⁹ (|x| ≤ 2⁹
    // gives |k| ≤ 327); 2/π within 2⁻²⁵: with |x| ≤ 2⁹ the quotient is off by less than 10⁻⁴.
    check_split_of_half_pi<detail::TrigKernelF32>(15, 0x1p-25);
    EXPECT_TRUE(detail::trig_f32_kernel_applies(0x1p9f));
    EXPECT_TRUE(detail::trig_f32_kernel_applies(-0x1p9f));
    EXPECT_FALSE(detail::trig_f32_kernel_applies(std::nextafter(0x1p9f, 1e30f)));
    EXPECT_FALSE(detail::trig_f32_kernel_applies(std::nanf("")));
}

TEST(TrigKernelF32, PointBoundsAtChosenPoints) {
    std::vector<float> xs = {0.0f,  -0.0f,   1e-45f, -1e-45f, 1e-30f, 1e-8f,  0.5f,
                             0.78f, 0.7854f, 1.0f,   -1.0f,   2.0f,   3.0f,   3.1416f,
                             10.0f, -100.0f, 355.0f, 511.0f,  0x1p9f, -0x1p9f};  // 355 lies near a
                                                                                 // multiple of π
    // Next to multiples of π/4 (where k and the branch change), a few ulps either side.
    for (int k = -651; k <= 651; k += 7) {
        float x = static_cast<float>(k * 0.7853981633974483);
        for (int s = 0; s < 3; ++s) x = std::nextafter(x, -INFINITY);
        for (int s = 0; s < 6; ++s, x = std::nextafter(x, INFINITY)) {
            if (detail::trig_f32_kernel_applies(x)) xs.push_back(x);
        }
    }
    for (float x : xs) EXPECT_EQ(check_point(x), "");
}

RC_GTEST_PROP(TrigKernelF32, PointBoundsAtRandomPoints, ()) {
    const int kind = *rc::gen::inRange(0, 3);
    float x = 0;
    if (kind == 0) {
        x = static_cast<float>(*rc::gen::inRange(-10000000, 10000001) * 1e-6);
    } else if (kind == 1) {  // small magnitudes, down to the subnormals
        x = std::ldexp(static_cast<float>(*rc::gen::inRange(1, 1 << 23)) * 0x1p-23f,
                       *rc::gen::inRange(-149, 1)) *
            (*rc::gen::arbitrary<bool>() ? 1.0f : -1.0f);
    } else {  // the whole domain
        x = std::bit_cast<float>(*rc::gen::inRange(0u, 0x44000001u)) *
            (*rc::gen::arbitrary<bool>() ? 1.0f : -1.0f);
    }
    RC_PRE(detail::trig_f32_kernel_applies(x));
    RC_ASSERT(check_point(x) == "");
}

RC_GTEST_PROP(TrigKernelF32, IntervalsEncloseTheRange, ()) {
    const int kind = *rc::gen::inRange(0, 3);
    float l = 0, width = 0;
    if (kind == 0) {  // around the first periods, any width up to beyond 2π
        l = static_cast<float>(*rc::gen::inRange(-20000000, 20000001) * 1e-6);
        width = static_cast<float>(*rc::gen::inRange(0, 7000001) * 1e-6);
    } else if (kind == 1) {  // narrow, anywhere in the domain
        l = static_cast<float>(*rc::gen::inRange(-512, 512) +
                               *rc::gen::inRange(0, 1 << 20) * 0x1p-20);
        width = std::ldexp(static_cast<float>(*rc::gen::inRange(0, 1 << 20)) * 0x1p-20f,
                           *rc::gen::inRange(-40, 3));
    } else {  // an extremum kπ/2 near an end
        const int k = *rc::gen::inRange(-300, 301);
        l = static_cast<float>(k * 1.5707963267948966 +
                               *rc::gen::inRange(-1000, 1001) *
                                   std::ldexp(1.0, *rc::gen::inRange(-30, -2)));
        width = std::ldexp(static_cast<float>(*rc::gen::inRange(1, 1 << 20)) * 0x1p-20f,
                           *rc::gen::inRange(-23, 1));
    }
    const float u = l + width;  // rounded to nearest: any u ≥ l
    RC_PRE(detail::trig_f32_kernel_applies(l) && detail::trig_f32_kernel_applies(u));
    RC_ASSERT(check_interval(l, u) == "");
}

TEST(TrigKernelF32, IntervalsAtTheEdges) {
    const float pi = 3.14159265f;
    const float cases[][2] = {{0, 0},           {-0.0f, 0.0f},     {-1, 1},          {0, pi},
                              {-pi, pi},        {pi / 2, pi / 2},  {1, 1 + 2 * pi},  {1, 1 + 6.28f},
                              {0x1p9f, 0x1p9f}, {-0x1p9f, 0x1p9f}, {1e-45f, 1e-30f}, {2, 2}};
    for (const auto& c : cases) EXPECT_EQ(check_interval(c[0], c[1]), "");
    float b[2];
    {
        RoundingScope up;
        detail::trig_f32_interval_bounds(0.0f, 0.0f, true, b);  // exact at 0
        EXPECT_EQ(b[0], 0.0f);
        EXPECT_EQ(b[1], 0.0f);
        detail::trig_f32_interval_bounds(0.0f, 0.0f, false, b);
        EXPECT_EQ(b[0], 1.0f);
        EXPECT_EQ(b[1], 1.0f);
        detail::trig_f32_interval_bounds(1.0f, 2.0f, true, b);  // sin's maximum at π/2 inside
        EXPECT_EQ(b[1], 1.0f);
        EXPECT_GT(b[0], 0.84f);  // sin 1 = 0.8414…, sin 2 = 0.9092…
        detail::trig_f32_interval_bounds(1.0f, 2.0f, false, b);  // monotone: no extremum
        EXPECT_GT(b[0], -0.42f);                                 // cos 2 = −0.4161…
        EXPECT_LT(b[1], 0.55f);                                  // cos 1 = 0.5403…
    }
}

#endif

}  // namespace
}  // namespace certray
