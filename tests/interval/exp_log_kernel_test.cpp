// tests/interval/exp_log_kernel_test.cpp — interval/exp_log_kernel.h: its constants against MPFR,
// its bounds against MPFR's exp and log at random and chosen points (both sides, within a few
// ulps), and the interval exp and log built on it at the edges of where the kernels apply.
#include "interval/exp_log_kernel.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "interval/exp_log_kernel_f32.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "tests/support/mpfr_oracle.h"

namespace certray {
namespace {

#ifdef CERTRAY_X86_64_ROUNDING

using Big = testing::Mpfr256;

TEST(ExpKernel, CoefficientsBoundTheReciprocalFactorials) {
    using K = detail::ExpKernel;
    for (unsigned i = 0; i <= 16; ++i) {
        Big f, lo, hi;
        mpfr_fac_ui(f.v, i, MPFR_RNDN);  // exact: i! has far fewer than 256 bits
        mpfr_ui_div(lo.v, 1, f.v, MPFR_RNDD);
        mpfr_ui_div(hi.v, 1, f.v, MPFR_RNDU);
        EXPECT_GE(mpfr_cmp_d(lo.v, K::kLo[i]), 0) << i;  // kLo ≤ 1/i! rounded down ≤ 1/i!
        EXPECT_LE(mpfr_cmp_d(hi.v, K::kHi[i]), 0) << i;  // kHi ≥ 1/i! rounded up ≥ 1/i!
        if (i < 16) {
            EXPECT_TRUE(std::nextafter(K::kLo[i], 1.0) == K::kHi[i] || K::kLo[i] == K::kHi[i])
                << i << ": the bounds are equal or adjacent doubles";
        }
    }
    // The last upper bound holds the remainder: 1/16! + ρ·e^ρ/17! with ρ = 0.6932.
    Big rho, e, t, f;
    mpfr_set_str(rho.v, "0.6932", 10, MPFR_RNDU);
    mpfr_exp(e.v, rho.v, MPFR_RNDU);
    mpfr_mul(t.v, rho.v, e.v, MPFR_RNDU);
    mpfr_fac_ui(f.v, 17, MPFR_RNDN);
    mpfr_div(t.v, t.v, f.v, MPFR_RNDU);
    mpfr_fac_ui(f.v, 16, MPFR_RNDN);
    mpfr_ui_div(f.v, 1, f.v, MPFR_RNDU);
    mpfr_add(t.v, t.v, f.v, MPFR_RNDU);
    EXPECT_LE(mpfr_cmp_d(t.v, K::kHi[16]), 0);
    // e^ρ < 2.0002, and ρ exceeds ln2·(1 + 2⁻²⁹), the most r can be.
    EXPECT_LT(mpfr_cmp_d(e.v, 2.0002), 0);
    Big ln2, top;
    mpfr_const_log2(ln2.v, MPFR_RNDU);
    mpfr_mul_d(top.v, ln2.v, 1 + std::ldexp(1.0, -29), MPFR_RNDU);
    EXPECT_LT(mpfr_cmp(top.v, rho.v), 0);
}

TEST(ExpKernel, SplitOfLn2) {
    using K = detail::ExpKernel;
    Big ln2, c2, err;
    mpfr_const_log2(ln2.v, MPFR_RNDN);  // within 2⁻²⁵⁶ of ln2
    EXPECT_GT(mpfr_cmp_d(ln2.v, K::kC1), 0);
    // C1 has at most 32 significant bits, so k·C1 is exact for |k| < 2²¹.
    const double scaled = std::ldexp(K::kC1, 32);
    EXPECT_EQ(scaled, std::floor(scaled));
    mpfr_sub_d(c2.v, ln2.v, K::kC1, MPFR_RNDN);
    mpfr_sub_d(err.v, c2.v, K::kC2, MPFR_RNDN);
    mpfr_abs(err.v, err.v, MPFR_RNDN);
    mpfr_mul_ui(err.v, err.v, 1100, MPFR_RNDU);
    EXPECT_LT(mpfr_cmp_d(err.v, K::kSlack), 0);  // with room for MPFR's 2⁻²⁵⁶
}

/// A kernel under test: its two bounds (lower of f(a), upper of f(b)), MPFR's f, and how far
/// each bound may lie from f(x), relatively, in units of 2⁻⁵².
struct Kernel {
    void (*bounds)(double, double, double*);
    MpfrInterval (*exact)(const MpfrInterval&);
    double tolerance;
};
const Kernel kExp{detail::exp_kernel_bounds, [](const MpfrInterval& v) { return exp(v); }, 6};
const Kernel kLog{detail::log_kernel_bounds, [](const MpfrInterval& v) { return log(v); }, 8};

/// Empty when the kernel's bounds at x enclose f(x) (MPFR at 256 bits) and lie within the
/// tolerance of it; otherwise what failed.
std::string check(const Kernel& kernel, double x) {
    double b[2];
    {
        RoundingScope up;
        kernel.bounds(x, x, b);
    }
    const MpfrInterval exact = kernel.exact(MpfrInterval(x));
    std::ostringstream out;
    out.precision(17);
    out << "x = " << x << ": [" << b[0] << ", " << b[1] << "] against " << testing::describe(exact);
    if (!testing::encloses(b[0], b[1], exact)) return out.str() + ": not enclosed";
    const double lo = exact.lower(), hi = exact.upper();  // f(x) rounded down and up
    const double tol = kernel.tolerance * 0x1p-52 * std::max(std::fabs(lo), std::fabs(hi));
    if (lo - b[0] > tol || b[1] - hi > tol) return out.str() + ": wider than the tolerance";
    return "";
}

TEST(ExpKernel, BoundsAtChosenPoints) {
    const double ln2 = 0.6931471805599453;
    std::vector<double> xs = {1e-300,
                              -1e-300,
                              5e-324,
                              1e-17,
                              -1e-17,
                              1e-9,
                              0.5,
                              1,
                              -1,
                              2,
                              ln2,
                              -ln2,
                              0.5 * ln2,
                              708,
                              -708,
                              707.9999999999999,
                              100,
                              -100,
                              std::nextafter(708.0, 0.0),
                              std::nextafter(-708.0, 0.0)};
    // Around multiples of ln2 and of ln2/2 (where k changes), a few ulps either side.
    for (int k = -1021; k <= 1021; k += 97) {
        for (double m : {k * ln2, (k + 0.5) * ln2}) {
            double x = m;
            for (int s = 0; s < 4; ++s) x = std::nextafter(x, -INFINITY);
            for (int s = 0; s < 8; ++s, x = std::nextafter(x, INFINITY)) {
                if (detail::exp_kernel_applies(x)) xs.push_back(x);
            }
        }
    }
    for (double x : xs) EXPECT_EQ(check(kExp, x), "");
}

RC_GTEST_PROP(ExpKernel, EnclosesExpAtRandomPoints, ()) {
    const int kind = *rc::gen::inRange(0, 3);
    double x = 0;
    if (kind == 0) {
        x = *rc::gen::inRange(-708000000, 708000001) * 1e-6;
    } else if (kind == 1) {  // small magnitudes, down to the subnormals
        const int e = *rc::gen::inRange(-1074, 1);
        x = std::ldexp(*rc::gen::inRange(1, 1 << 30) * 0x1p-30, e) *
            (*rc::gen::arbitrary<bool>() ? 1 : -1);
    } else {  // the whole range, bit patterns
        x = *rc::gen::inRange(-708, 709) + *rc::gen::inRange(0, 1 << 30) * 0x1p-30;
    }
    RC_PRE(detail::exp_kernel_applies(x));
    RC_ASSERT(check(kExp, x) == "");
}

// The interval exp: the kernel inside [−708, 708] except 0, libm outside, on each bound alone.
TEST(ExpKernel, IntervalExpAtTheEdges) {
    const double inf = std::numeric_limits<double>::infinity();
    const double cases[][2] = {
        {0, 0},       {-1, 0},      {0, 1},       {-inf, 0},    {-inf, inf},       {700, 709.7},
        {-745, -700}, {-750, -740}, {708, 708.5}, {-709, -708}, {-1e-300, 1e-300}, {1, 2}};
    for (const auto& c : cases) {
        const Interval v = exp(Interval(c[0], c[1]));
        const MpfrInterval exact = exp(MpfrInterval(c[0], c[1]));
        EXPECT_TRUE(testing::encloses(v.lower(), v.upper(), exact))
            << "exp[" << c[0] << ", " << c[1] << "] = [" << v.lower() << ", " << v.upper()
            << "] against " << testing::describe(exact);
    }
    EXPECT_EQ(exp(Interval(0.0)).lower(), 1.0);  // exact where exp is
    EXPECT_EQ(exp(Interval(0.0)).upper(), 1.0);
    EXPECT_EQ(exp(Interval(-inf, 0.0)).lower(), 0.0);
}

// ---- the binary32 exp kernel (interval/exp_log_kernel_f32.h) ----------------------------------

TEST(ExpKernelF32, Constants) {
    using K = detail::ExpKernelF32;
    for (unsigned i = 0; i <= 9; ++i) {
        Big f, lo, hi;
        mpfr_fac_ui(f.v, i, MPFR_RNDN);
        mpfr_ui_div(lo.v, 1, f.v, MPFR_RNDD);
        mpfr_ui_div(hi.v, 1, f.v, MPFR_RNDU);
        EXPECT_GE(mpfr_cmp_d(lo.v, K::kLo[i]), 0) << i;
        EXPECT_LE(mpfr_cmp_d(hi.v, K::kHi[i]), 0) << i;
        if (i < 9) {
            EXPECT_TRUE(std::nextafter(K::kLo[i], 1.0f) == K::kHi[i] || K::kLo[i] == K::kHi[i])
                << i << ": the bounds are equal or adjacent floats";
        }
    }
    // The last upper bound holds the remainder: 1/9! + ρ·e^ρ/10! with ρ = 0.6935.
    Big rho, e, t, f;
    mpfr_set_str(rho.v, "0.6935", 10, MPFR_RNDU);
    mpfr_exp(e.v, rho.v, MPFR_RNDU);
    EXPECT_LT(mpfr_cmp_d(e.v, 2.001), 0);
    mpfr_mul(t.v, rho.v, e.v, MPFR_RNDU);
    mpfr_fac_ui(f.v, 10, MPFR_RNDN);
    mpfr_div(t.v, t.v, f.v, MPFR_RNDU);
    mpfr_fac_ui(f.v, 9, MPFR_RNDN);
    mpfr_ui_div(f.v, 1, f.v, MPFR_RNDU);
    mpfr_add(t.v, t.v, f.v, MPFR_RNDU);
    EXPECT_LE(mpfr_cmp_d(t.v, K::kHi[9]), 0);
    // ρ exceeds ln2·(1 + 2⁻¹² + 5·10⁻⁵), the most r can be.
    Big ln2, top;
    mpfr_const_log2(ln2.v, MPFR_RNDU);
    mpfr_mul_d(top.v, ln2.v, 1 + std::ldexp(1.0, -12) + 5e-5, MPFR_RNDU);
    EXPECT_LT(mpfr_cmp(top.v, rho.v), 0);
    // ln2 = C1 + C2: C1 below ln2 with at most 15 significant bits (k·C1 exact for |k| ≤ 2⁹),
    // C2's error times 127 below the slack.
    Big c2, err;
    mpfr_const_log2(ln2.v, MPFR_RNDN);
    EXPECT_GT(mpfr_cmp_d(ln2.v, K::kC1), 0);
    const double scaled = std::ldexp(static_cast<double>(K::kC1), 15);
    EXPECT_EQ(scaled, std::floor(scaled));
    mpfr_sub_d(c2.v, ln2.v, K::kC1, MPFR_RNDN);
    mpfr_sub_d(err.v, c2.v, K::kC2, MPFR_RNDN);
    mpfr_abs(err.v, err.v, MPFR_RNDN);
    mpfr_mul_ui(err.v, err.v, 127, MPFR_RNDU);
    EXPECT_LT(mpfr_cmp_d(err.v, K::kSlack), 0);
}

/// A binary32 kernel under test: its two bounds (lower of f(a), upper of f(b)), MPFR's f, and
/// whether its 2⁻¹⁸ is relative to f(x) and its bounds normal numbers (exp) or its 2⁻¹⁸ relative to
/// max(1, |f(x)|) (log: absolute near log x = 0, where a bound may be 0).
struct KernelF32 {
    void (*bounds)(float, float, float*);
    MpfrInterval (*exact)(const MpfrInterval&);
    bool relative;
};
const KernelF32 kExpF32{detail::exp_f32_kernel_bounds, [](const MpfrInterval& v) { return exp(v); },
                        true};
const KernelF32 kLogF32{detail::log_f32_kernel_bounds, [](const MpfrInterval& v) { return log(v); },
                        false};

/// Empty when the binary32 kernel's bounds at x enclose f(x) (MPFR at 256 bits) and lie within
/// 2⁻¹⁸ of it, as the kernel measures; otherwise what failed.
std::string check_f32(const KernelF32& kernel, float x) {
    float b[2];
    {
        RoundingScope up;
        kernel.bounds(x, x, b);
    }
    const MpfrInterval exact = kernel.exact(MpfrInterval(static_cast<double>(x)));
    std::ostringstream out;
    out.precision(10);
    out << "x = " << x << ": [" << b[0] << ", " << b[1] << "] against " << testing::describe(exact);
    if (!testing::encloses(b[0], b[1], exact)) return out.str() + ": not enclosed";
    const double scale = std::fabs(exact.upper());
    const double tol = 0x1p-18 * (kernel.relative ? scale : std::max(1.0, scale));
    if (exact.lower() - b[0] > tol || b[1] - exact.upper() > tol) {
        return out.str() + ": wider than 2^-18";
    }
    if (kernel.relative && (!std::isnormal(b[0]) || !std::isnormal(b[1]))) {
        return out.str() + ": not normal";
    }
    return "";
}

TEST(ExpKernelF32, BoundsAtChosenPoints) {
    std::vector<float> xs = {0.0f, -0.0f,  1e-30f, -1e-30f, 1e-45f, 0.5f,  1.0f,  -1.0f,
                             2.0f, -87.0f, 88.0f,  87.5f,   -86.9f, 10.0f, -10.0f};
    // Around multiples of ln2 and of ln2/2 (where k changes), a few ulps either side.
    for (int k = -125; k <= 126; k += 7) {
        for (double m : {k * 0.6931471805599453, (k + 0.5) * 0.6931471805599453}) {
            float x = static_cast<float>(m);
            for (int s = 0; s < 4; ++s) x = std::nextafter(x, -INFINITY);
            for (int s = 0; s < 8; ++s, x = std::nextafter(x, INFINITY)) {
                if (detail::exp_f32_kernel_applies(x)) xs.push_back(x);
            }
        }
    }
    for (float x : xs) EXPECT_EQ(check_f32(kExpF32, x), "");
    EXPECT_FALSE(detail::exp_f32_kernel_applies(std::nextafter(-87.0f, -INFINITY)));
    EXPECT_FALSE(detail::exp_f32_kernel_applies(std::nextafter(88.0f, INFINITY)));
    EXPECT_FALSE(detail::exp_f32_kernel_applies(std::nanf("")));
}

RC_GTEST_PROP(ExpKernelF32, EnclosesExpAtRandomPoints, ()) {
    // Every binary32 number of the kernel's range is as likely as its bits are: a random bit
    // pattern below 88's, either sign.
    const auto b = *rc::gen::inRange<std::uint32_t>(0, std::bit_cast<std::uint32_t>(88.0f) + 1);
    const float x = std::bit_cast<float>(b) * (*rc::gen::arbitrary<bool>() ? 1.0f : -1.0f);
    RC_PRE(detail::exp_f32_kernel_applies(x));
    RC_ASSERT(check_f32(kExpF32, x) == "");
}

TEST(LogKernelF32, Constants) {
    using K = detail::LogKernelF32;
    Big ln2, q, big;
    mpfr_const_log2(ln2.v, MPFR_RNDN);
    EXPECT_LT(mpfr_cmp_d(ln2.v, K::kLn2Hi), 0);
    EXPECT_GT(mpfr_cmp_d(ln2.v, K::kLn2Lo), 0);
    // kSqrt2 < √2, and the largest v the split leaves, (1 − kSqrt2/2)/(1 + kSqrt2/2), is ≤ 0.1716.
    mpfr_sqrt_ui(q.v, 2, MPFR_RNDN);
    EXPECT_GT(mpfr_cmp_d(q.v, K::kSqrt2), 0);
    const double half = 0.5 * K::kSqrt2;  // exact
    mpfr_set_d(q.v, 1 - half, MPFR_RNDU);
    mpfr_set_d(big.v, 1 + half, MPFR_RNDD);
    mpfr_div(q.v, q.v, big.v, MPFR_RNDU);
    EXPECT_LE(mpfr_cmp_d(q.v, 0.1716), 0);
    EXPECT_LE((K::kSqrt2 - 1) / (K::kSqrt2 + 1), 0.1716);
    for (unsigned i = 0; i < 6; ++i) {
        Big lo, hi;
        mpfr_set_ui(lo.v, 1, MPFR_RNDN);
        mpfr_div_ui(lo.v, lo.v, 2 * i + 1, MPFR_RNDD);
        mpfr_set_ui(hi.v, 1, MPFR_RNDN);
        mpfr_div_ui(hi.v, hi.v, 2 * i + 1, MPFR_RNDU);
        EXPECT_GE(mpfr_cmp_d(lo.v, K::kLo[i]), 0) << i;
        EXPECT_LE(mpfr_cmp_d(hi.v, K::kHi[i]), 0) << i;
    }
    // The last upper bound holds the remainder: 1/11 + w/(13(1 − w)), w = 0.1716².
    Big w, t, one;
    mpfr_set_str(w.v, "0.1716", 10, MPFR_RNDU);
    mpfr_sqr(w.v, w.v, MPFR_RNDU);
    mpfr_ui_sub(one.v, 1, w.v, MPFR_RNDD);
    mpfr_mul_ui(one.v, one.v, 13, MPFR_RNDD);
    mpfr_div(t.v, w.v, one.v, MPFR_RNDU);
    mpfr_set_ui(q.v, 1, MPFR_RNDN);
    mpfr_div_ui(q.v, q.v, 11, MPFR_RNDU);
    mpfr_add(t.v, t.v, q.v, MPFR_RNDU);
    EXPECT_LE(mpfr_cmp_d(t.v, K::kHi[5]), 0);
}

TEST(LogKernelF32, BoundsAtChosenPoints) {
    std::vector<float> xs = {1.0f,           2.0f,           0.5f,           3.0f,
                             1e-30f,         1e30f,          0x1p-126f,      0x1.fffffep+127f,
                             0x1.6a09e6p+0f, 0x1.6a09e8p+0f, 0x1.6a09e6p-1f, 0.70710677f};
    // Around 1 and around the split, a few ulps either side, at several exponents.
    for (int e = -126; e <= 127; e += 11) {
        for (float m : {1.0f, 0x1.6a09e6p+0f}) {
            float x = std::ldexp(m, e);
            for (int s = 0; s < 4; ++s) x = std::nextafter(x, 0.0f);
            for (int s = 0; s < 8; ++s, x = std::nextafter(x, INFINITY)) {
                if (detail::log_f32_kernel_applies(x)) xs.push_back(x);
            }
        }
    }
    for (float x : xs) EXPECT_EQ(check_f32(kLogF32, x), "");
    EXPECT_FALSE(detail::log_f32_kernel_applies(0x1p-127f));  // subnormal
    EXPECT_FALSE(detail::log_f32_kernel_applies(0.0f));
    EXPECT_FALSE(detail::log_f32_kernel_applies(-1.0f));
    EXPECT_FALSE(detail::log_f32_kernel_applies(INFINITY));
}

RC_GTEST_PROP(LogKernelF32, EnclosesLogAtRandomPoints, ()) {
    const auto b = *rc::gen::inRange<std::uint32_t>(std::bit_cast<std::uint32_t>(0x1p-126f),
                                                    std::bit_cast<std::uint32_t>(INFINITY));
    const float x = std::bit_cast<float>(b);
    RC_PRE(detail::log_f32_kernel_applies(x));
    RC_ASSERT(check_f32(kLogF32, x) == "");
}

TEST(LogKernel, Constants) {
    using K = detail::LogKernel;
    for (unsigned i = 0; i < 10; ++i) {
        Big lo, hi;
        mpfr_set_ui(lo.v, 1, MPFR_RNDN);
        mpfr_div_ui(lo.v, lo.v, 2 * i + 1, MPFR_RNDD);
        mpfr_set_ui(hi.v, 1, MPFR_RNDN);
        mpfr_div_ui(hi.v, hi.v, 2 * i + 1, MPFR_RNDU);
        EXPECT_GE(mpfr_cmp_d(lo.v, K::kLo[i]), 0) << i;
        EXPECT_LE(mpfr_cmp_d(hi.v, K::kHi[i]), 0) << i;
        if (i < 9) {
            EXPECT_TRUE(std::nextafter(K::kLo[i], 1.0) == K::kHi[i] || K::kLo[i] == K::kHi[i]) << i;
        }
    }
    // The last upper bound holds the tail of the series: 1/19 + w/(21·(1 − w)), w = 0.0295, and w
    // bounds v² = ((m − 1)/(m + 1))² for m in [√2/2, √2) with √2 the kernel's double.
    Big w, t, one;
    mpfr_set_str(w.v, "0.0295", 10, MPFR_RNDU);
    mpfr_ui_sub(t.v, 1, w.v, MPFR_RNDD);
    mpfr_mul_ui(t.v, t.v, 21, MPFR_RNDD);
    mpfr_div(t.v, w.v, t.v, MPFR_RNDU);
    mpfr_set_ui(one.v, 1, MPFR_RNDN);
    mpfr_div_ui(one.v, one.v, 19, MPFR_RNDU);
    mpfr_add(t.v, t.v, one.v, MPFR_RNDU);
    EXPECT_LE(mpfr_cmp_d(t.v, K::kHi[9]), 0);
    for (const double m : {K::kSqrt2, K::kSqrt2 / 2}) {
        Big v;
        mpfr_set_d(v.v, m, MPFR_RNDN);
        mpfr_sub_ui(t.v, v.v, 1, MPFR_RNDN);
        mpfr_add_ui(v.v, v.v, 1, MPFR_RNDN);
        mpfr_div(v.v, t.v, v.v, MPFR_RNDU);
        mpfr_sqr(v.v, v.v, MPFR_RNDU);
        EXPECT_LT(mpfr_cmp(v.v, w.v), 0) << m;
    }
    Big ln2;
    mpfr_const_log2(ln2.v, MPFR_RNDN);
    EXPECT_GT(mpfr_cmp_d(ln2.v, K::kLn2Lo), 0);
    EXPECT_LT(mpfr_cmp_d(ln2.v, K::kLn2Hi), 0);
    EXPECT_EQ(std::nextafter(K::kLn2Lo, 1.0), K::kLn2Hi);
}

TEST(LogKernel, BoundsAtChosenPoints) {
    using K = detail::LogKernel;
    std::vector<double> xs = {2,
                              0.5,
                              4,
                              1e-300,
                              1e300,
                              0x1p-1022,
                              0x1.fffffffffffffp+1023,
                              3,
                              10,
                              0.1,
                              2.718281828459045,
                              K::kSqrt2,
                              K::kSqrt2 / 2};
    // Next to 1 (log x ≈ x − 1, relative accuracy there), next to √2·2ᵏ (the split), powers of 2.
    for (double x = 1, y = 1, s = 0; s < 12; ++s) {
        x = std::nextafter(x, 2.0);
        y = std::nextafter(y, 0.0);
        xs.push_back(x);
        xs.push_back(y);
    }
    for (int k = -1020; k <= 1020; k += 51) {
        double x = std::ldexp(K::kSqrt2, k);
        for (int s = 0; s < 3; ++s) x = std::nextafter(x, 0.0);
        for (int s = 0; s < 6; ++s, x = std::nextafter(x, INFINITY)) xs.push_back(x);
        xs.push_back(std::ldexp(1.0, k));
        xs.push_back(std::ldexp(1.5, k));
    }
    for (double x : xs) EXPECT_EQ(check(kLog, x), "");
}

RC_GTEST_PROP(LogKernel, EnclosesLogAtRandomPoints, ()) {
    const int kind = *rc::gen::inRange(0, 3);
    double x = 0;
    if (kind == 0) {  // any normal double
        x = std::ldexp(1 + *rc::gen::inRange(0, 1 << 30) * 0x1p-30, *rc::gen::inRange(-1022, 1024));
    } else if (kind == 1) {  // close to 1
        x = 1 +
            *rc::gen::inRange(-(1 << 30), 1 << 30) * std::ldexp(1.0, *rc::gen::inRange(-82, -30));
    } else {
        x = *rc::gen::inRange(1, 1000000) * 1e-3;
    }
    RC_PRE(detail::log_kernel_applies(x));
    RC_ASSERT(check(kLog, x) == "");
}

TEST(LogKernel, IntervalLogAtTheEdges) {
    const double inf = std::numeric_limits<double>::infinity();
    const double cases[][2] = {{1, 1},
                               {0.5, 1},
                               {1, 2},
                               {1e-310, 1e-300},
                               {1e-320, 2},
                               {1e300, inf},
                               {0x1p-1022, 0x1p-1022},
                               {0.999, 1.001},
                               {2, 2}};
    for (const auto& c : cases) {
        const Interval v = log(Interval(c[0], c[1]));
        const MpfrInterval exact = log(MpfrInterval(c[0], c[1]));
        EXPECT_TRUE(testing::encloses(v.lower(), v.upper(), exact))
            << "log[" << c[0] << ", " << c[1] << "] = [" << v.lower() << ", " << v.upper()
            << "] against " << testing::describe(exact);
    }
    EXPECT_EQ(log(Interval(1.0)).lower(), 0.0);  // exact where log is
    EXPECT_EQ(log(Interval(1.0)).upper(), 0.0);
}

#endif

}  // namespace
}  // namespace certray
