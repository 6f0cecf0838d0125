// interval/exp_log_kernel_f32.h — outward bounds of exp(x) and log(x) in binary32, in upward
// rounding mode, without libm and without a mode switch, for the binary32 lane walk
// (expr/eval_interval_batch.h): the constants of interval/exp_log_kernel.h's exp_bound and
// log_bound for vectors of floats, with fewer terms.
//
// Contract: inside a RoundingScope (upward mode), for binary32 x with exp_f32_kernel_applies(x)
// (−87 ≤ x ≤ 88) and s = −1 or +1 per lane, exp_bound<V, ExpKernelF32>(x, s, coef) returns s·B
// where B is a lower bound of exp(x) for s = −1 and an upper bound for s = +1, both normal
// binary32 numbers within 2⁻¹⁸ of exp(x), relatively. coef[i] holds per lane the bound of 1/i! of
// the same side: ExpKernelF32::kLo[i] where s = −1, kHi[i] where s = +1.
//
// How: interval/exp_log_kernel.h's argument (docs/theory/exp_log_kernel.md), in binary32:
// - k = ⌈x/ln2 − 1 − 2⁻¹²⌉, the quotient and the difference rounded up (their errors are at most
//   127·3·2⁻²⁴ + 2⁻¹⁶ < 5·10⁻⁵, well inside 2⁻¹²), so that r = x − k·ln2 lies in
//   [1.4·10⁻⁴, 0.6935] whatever the rounding; exp(x) = 2ᵏ·exp(r), 2ᵏ exact and normal for
//   k in [−126, 126].
// - r is bounded outward from ln2 = C1 + C2: C1 with 15 significant bits (k·C1 exact for
//   |k| ≤ 2⁹), C2's error times |k| ≤ 127 below 2⁻³⁶, the slack added.
// - exp(r) = Σ_{i ≤ 9} rⁱ/i! + R with 0 ≤ R ≤ r⁹·ρe^ρ/10! (ρ = 0.6935, e^ρ < 2.001): the lower
//   bound drops R, the upper bound adds it to the coefficient of r⁹ (R ≤ 1.4·10⁻⁸ relatively).
//   Every coefficient, r and partial sum is positive, so the polynomial is increasing in each:
//   evaluated with every operation rounded down (lower) or up (upper) from the coefficients'
//   bounds it gives the bounds; the ten roundings of the evaluation keep it within 2⁻¹⁸.
// - A lower bound is carried negated (−lo), so that both are operations rounded up.
//
// log_bound<V, LogKernelF32>(x, s), for x with log_f32_kernel_applies(x) (normal, positive,
// finite), returns s·B likewise, B within 2⁻¹⁸ of log(x) absolutely where |log x| < 1 and
// relatively elsewhere, by exp_log_kernel.h's log argument in binary32: x = m·2^e with m in
// [0.7071067, 1.4142134) (the split at the binary32 number below √2), log x = e·ln2 + σ·g(v),
// v = |m − 1|/(m + 1) ≤ 0.1716 and g(v) = 2v·Σ v²ⁱ/(2i + 1), six terms, the remainder
// Σ_{i ≥ 6} w^i/(2i + 1) ≤ w⁵·w/(13(1 − w)) (w = v² ≤ 0.1716²) added to the last coefficient's
// upper bound.
#pragma once

#include <bit>
#include <cstdint>

#include "interval/exp_log_kernel.h"

namespace certray::detail {

/// Whether exp_bound<V, ExpKernelF32> applies to x (NaN: no).
inline bool exp_f32_kernel_applies(float x) { return x >= -87.0f && x <= 88.0f; }

/// The binary32 kernel's constants (tests/interval/exp_log_kernel_test.cpp checks them against
/// MPFR).
struct ExpKernelF32 {
    static constexpr float kInvLn2 = 0x1.715476p+0f;  ///< ≈ 1/ln2 (any float near it)
    static constexpr float kShift = 0x1.001p+0f;      ///< 1 + 2⁻¹²
    static constexpr float kMagic = 0x1.8p+23f;       ///< 1.5·2²³: integers in the mantissa
    static constexpr float kC1 = 0x1.62e4p-1f;        ///< ln2 to 15 bits, below ln2
    static constexpr float kC2 = 0x1.7f7d1cp-20f;     ///< ≈ ln2 − C1
    static constexpr float kSlack = 0x1p-36f;         ///< ≥ 127·|C2 − (ln2 − C1)|
    static constexpr float kLower = -87.0f;           ///< where the kernel applies
    static constexpr float kUpper = 88.0f;
    /// The bits of kMagic less 127: bits(kd + kMagic) − kPow2Bias = kd + 127, 2^kd's exponent.
    static constexpr std::int32_t kPow2Bias = std::bit_cast<std::int32_t>(kMagic) - 127;
    /// Bounds of 1/i!, i = 0 … 9; the last upper bound also holds the remainder ρe^ρ/10!.
    static constexpr float kLo[10] = {
        1.0f,          1.0f,           0.5f,          0x1.555554p-3f, 0x1.555554p-5f,
        0x1.11111p-7f, 0x1.6c16cp-10f, 0x1.a01ap-13f, 0x1.a01ap-16f,  0x1.71de3ap-19f};
    static constexpr float kHi[10] = {1.0f,
                                      1.0f,
                                      0.5f,
                                      0x1.555556p-3f,
                                      0x1.555556p-5f,
                                      0x1.111112p-7f,
                                      0x1.6c16c2p-10f,
                                      0x1.a01a02p-13f,
                                      0x1.a01a02p-16f,
                                      0x1.a531c8p-19f};
};

/// Whether log_bound<V, LogKernelF32> applies to x (NaN: no).
inline bool log_f32_kernel_applies(float x) { return x >= 0x1p-126f && x <= 0x1.fffffep+127f; }

/// The binary32 log kernel's constants (checked against MPFR as ExpKernelF32's).
struct LogKernelF32 {
    static constexpr float kLn2Lo = 0x1.62e42ep-1f;  ///< ln2 rounded down
    static constexpr float kLn2Hi = 0x1.62e430p-1f;  ///< ln2 rounded up
    static constexpr float kSqrt2 = 0x1.6a09e6p+0f;  ///< the binary32 number below √2
    static constexpr float kMinNormal = 0x1p-126f;   ///< where the kernel applies
    static constexpr float kMax = 0x1.fffffep+127f;
    /// Bounds of 1/(2i + 1), i = 0 … 5; the last upper bound also holds the remainder.
    static constexpr float kLo[6] = {1.0f,           0x1.555554p-2f, 0x1.999998p-3f,
                                     0x1.249248p-3f, 0x1.c71c7p-4f,  0x1.745d16p-4f};
    static constexpr float kHi[6] = {1.0f,           0x1.555556p-2f, 0x1.99999ap-3f,
                                     0x1.24924ap-3f, 0x1.c71c72p-4f, 0x1.7dec4ep-4f};
};

#if defined(__GNUC__) && defined(__x86_64__)
/// Four binary32 lanes of SSE (the baseline of x86-64): the operations exp_bound and log_bound
/// need, and interval/trig_kernel.h's trig_point and trig_interval.
struct KernelSse2F {
    using R = __m128;
    static R set1(float c) { return _mm_set1_ps(c); }
    static R add(R a, R b) { return _mm_add_ps(a, b); }
    static R sub(R a, R b) { return _mm_sub_ps(a, b); }
    static R mul(R a, R b) { return _mm_mul_ps(a, b); }
    static R sign_of(R a) { return _mm_and_ps(a, _mm_set1_ps(-0.0f)); }
    static R flip(R a, R m) { return _mm_xor_ps(a, m); }
    static R div(R a, R b) { return _mm_div_ps(a, b); }
    static R max(R a, R b) { return _mm_max_ps(a, b); }
    static R min(R a, R b) { return _mm_min_ps(a, b); }
    using M = __m128;  ///< a mask: all bits set in the lanes where a comparison holds
    static M le(R a, R b) { return _mm_cmple_ps(a, b); }
    static M lt(R a, R b) { return _mm_cmplt_ps(a, b); }
    static M eq(R a, R b) { return _mm_cmpeq_ps(a, b); }
    static M either(M a, M b) { return _mm_or_ps(a, b); }
    static R select(M m, R t, R f) { return _mm_or_ps(_mm_and_ps(m, t), _mm_andnot_ps(m, f)); }
    static constexpr int kWidth = 4;
    static unsigned bits(M m) { return static_cast<unsigned>(_mm_movemask_ps(m)); }
    static void log_split(R x, R& e, R& m) {
        // x = f·2^E, f in [1, 2): E from the exponent bits (E + 127 added to the bits of
        // 1.5·2²³, then 1.5·2²³ taken off, exactly), f with the exponent bits of 1; f ≥ kSqrt2 is
        // halved and E raised by one.
        const __m128i b = _mm_castps_si128(x);
        const __m128i eb =
            _mm_add_epi32(_mm_srli_epi32(b, 23), _mm_set1_epi32(ExpKernelF32::kPow2Bias));
        const R big_e = _mm_sub_ps(_mm_castsi128_ps(eb), set1(ExpKernelF32::kMagic));
        const R f = _mm_castsi128_ps(
            _mm_or_si128(_mm_and_si128(b, _mm_set1_epi32(0x007fffff)), _mm_set1_epi32(0x3f800000)));
        const R big = _mm_cmpge_ps(f, set1(LogKernelF32::kSqrt2));
        e = _mm_add_ps(big_e, _mm_and_ps(big, set1(1.0f)));
        m = _mm_or_ps(_mm_and_ps(big, _mm_mul_ps(f, set1(0.5f))), _mm_andnot_ps(big, f));
    }
    static R pow2(R kd) {
        // kd + 1.5·2²³ (exact) has the bits of 1.5·2²³ plus kd: (kd + 127) << 23 is 2^kd.
        const __m128i b = _mm_castps_si128(_mm_add_ps(kd, _mm_set1_ps(ExpKernelF32::kMagic)));
        const __m128i bias = _mm_set1_epi32(ExpKernelF32::kPow2Bias);
        return _mm_castsi128_ps(_mm_slli_epi32(_mm_sub_epi32(b, bias), 23));
    }
};

/// Lane 0: a lower bound of exp(a), lane 1: an upper bound of exp(b), into out[0], out[1] (upward
/// mode held; exp_f32_kernel_applies(a) and (b)). For the tests; the walk inlines the kernel.
inline void exp_f32_kernel_bounds(float a, float b, float* out) {
    __m128 x = _mm_set_ps(0.0f, 0.0f, b, a);
    asm volatile("" : "+x"(x));
    const __m128 s = _mm_set_ps(1.0f, 1.0f, 1.0f, -1.0f);
    __m128 coef[10];
    for (int i = 0; i < 10; ++i) {
        coef[i] = _mm_set_ps(ExpKernelF32::kHi[i], ExpKernelF32::kHi[i], ExpKernelF32::kHi[i],
                             ExpKernelF32::kLo[i]);
    }
    __m128 r = exp_bound<KernelSse2F, ExpKernelF32>(x, s, coef);
    asm volatile("" : "+x"(r));
    alignas(16) float v[4];
    _mm_store_ps(v, r);
    out[0] = -v[0];
    out[1] = v[1];
}

/// Lane 0: a lower bound of log(a), lane 1: an upper bound of log(b), into out[0], out[1] (upward
/// mode held; log_f32_kernel_applies(a) and (b)), as exp_f32_kernel_bounds.
inline void log_f32_kernel_bounds(float a, float b, float* out) {
    __m128 x = _mm_set_ps(1.0f, 1.0f, b, a);
    asm volatile("" : "+x"(x));
    __m128 r = log_bound<KernelSse2F, LogKernelF32>(x, _mm_set_ps(1.0f, 1.0f, 1.0f, -1.0f));
    asm volatile("" : "+x"(r));
    alignas(16) float v[4];
    _mm_store_ps(v, r);
    out[0] = -v[0];
    out[1] = v[1];
}
#endif

}  // namespace certray::detail
