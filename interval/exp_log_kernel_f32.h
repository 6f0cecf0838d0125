// interval/exp_log_kernel_f32.h — outward bounds of exp(x) and log(x) in binary32, in upward
// rounding mode,
// without libm and without a mode switch, for the binary32 lane walk
// (expr/eval_interval_batch.h), written once for any vector of floats.
//
// Contract: inside a RoundingScope (upward mode), for binary32 x with exp_f32_kernel_applies(x)
// (−87 ≤ x ≤ 88) and s = −1 or +1 per lane, exp_bound_f32<V>(x, s, coef) returns s·B where B is a
// lower bound of exp(x) for s = −1 and an upper bound for s = +1, both normal binary32 numbers
// within 2⁻¹⁸ of exp(x), relatively. coef[i] holds per lane the bound of 1/i! of the same side:
// ExpKernelF32::kLo[i] where s = −1, kHi[i] where s = +1.
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
// log_bound_f32<V>(x, s), for x with log_f32_kernel_applies(x) (normal, positive, finite),
// returns s·B likewise, B within 2⁻¹⁸ of log(x) absolutely where |log x| < 1 and relatively
// elsewhere, by exp_log_kernel.h's log argument in binary32: x = m·2^e with m in
// [0.7071067, 1.4142134) (the split at the binary32 number below √2), log x = e·ln2 + σ·g(v),
// v = |m − 1|/(m + 1) ≤ 0.1716 and g(v) = 2v·Σ v²ⁱ/(2i + 1), six terms, the remainder
// Σ_{i ≥ 6} w^i/(2i + 1) ≤ w⁵·w/(13(1 − w)) (w = v² ≤ 0.1716²) added to the last coefficient's
// upper bound.
#pragma once

#include <bit>
#include <cstdint>

#if defined(__GNUC__) && defined(__x86_64__)
#include <emmintrin.h>
#endif

namespace certray::detail {

/// Whether exp_bound_f32 applies to x (NaN: no).
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

/// Whether log_bound_f32 applies to x (NaN: no).
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

// The kernels take and return vectors of any width; it is always inlined into code built for
// the width's instruction set, so no call passes an AVX vector by value.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
/// s·B for each lane (see the file contract). V provides R (binary32 lanes), set1, add, sub, mul
/// (IEEE, in the current mode), sign_of(a) (a's sign bit alone), flip(a, m) (a's bits xor m's)
/// and pow2(kd) = 2^kd for integral kd in [−126, 127] (exact).
template <class V>
[[gnu::always_inline]] inline typename V::R exp_bound_f32(typename V::R x, typename V::R s,
                                                          const typename V::R* coef) {
    using R = typename V::R;
    using K = ExpKernelF32;
    const R y = V::mul(x, V::set1(K::kInvLn2));
    const R z = V::sub(y, V::set1(K::kShift));
    const R kd = V::sub(V::add(z, V::set1(K::kMagic)), V::set1(K::kMagic));  // ⌈z⌉ (upward mode)
    const R sm = V::sign_of(s);
    const R nsm = V::flip(sm, V::set1(-0.0f));
    // s·r rounded up: s·(x − k·C1) (k·C1 exact) − s·k·C2 + slack.
    const R kc1 = V::mul(kd, V::set1(K::kC1));
    const R d = V::sub(V::flip(x, sm), V::flip(kc1, sm));
    const R e = V::mul(V::flip(kd, nsm), V::set1(K::kC2));
    const R r = V::add(d, V::add(e, V::set1(K::kSlack)));
    // Estrin: pairs c(2i) + c(2i+1)·r, joined by r², r⁴, r⁸.
    const auto pair = [&](int i) { return V::add(V::flip(coef[i], sm), V::mul(coef[i + 1], r)); };
    const auto times = [&](R a, R b) { return V::mul(a, V::flip(b, sm)); };  // (a·b)′
    const R r2 = times(r, r);
    const R r4 = times(r2, r2);
    const R r8 = times(r4, r4);
    const R q0 = V::add(pair(0), times(pair(2), r2));
    const R q1 = V::add(pair(4), times(pair(6), r2));
    const R o0 = V::add(q0, times(q1, r4));
    const R p = V::add(o0, times(pair(8), r8));
    return V::mul(p, V::pow2(kd));
}
/// s·B for log (see the file contract), where log_f32_kernel_applies(x) in every lane. V provides
/// what exp_bound_f32 needs and div, max and log_split(x, e, m): x = m·2^e with e integral and m in
/// [kSqrt2/2, kSqrt2), both exact.
template <class V>
[[gnu::always_inline]] inline typename V::R log_bound_f32(typename V::R x, typename V::R s) {
    using R = typename V::R;
    using K = LogKernelF32;
    R e, m;
    V::log_split(x, e, m);
    const R sm = V::sign_of(s);
    // s·(e·ln2) rounded up: the larger of the two products with ln2's bounds.
    const R se = V::flip(e, sm);
    const R el = V::max(V::mul(se, V::set1(K::kLn2Lo)), V::mul(se, V::set1(K::kLn2Hi)));
    const R dm = V::sub(m, V::set1(1.0f));  // exact; σ = its sign (+ at 0)
    const R dsm = V::sign_of(dm);
    const R tm = V::flip(sm, dsm);
    const R ntm = V::flip(tm, V::set1(-0.0f));
    // t·v: v = |m − 1|/(m + 1) with the denominator rounded against the side t.
    const R den = V::flip(V::add(V::flip(m, ntm), V::flip(V::set1(1.0f), ntm)), ntm);
    const R v = V::div(V::flip(V::flip(dm, dsm), tm), den);
    const auto coef = [&](int i) {
        return V::max(V::flip(V::set1(K::kLo[i]), tm), V::flip(V::set1(K::kHi[i]), tm));
    };
    const auto times = [&](R a, R b) { return V::mul(a, V::flip(b, tm)); };  // (a·b)′
    const R w = times(v, v);
    const auto pair2 = [&](int i) { return V::add(coef(i), times(coef(i + 1), w)); };
    const R w2 = times(w, w);
    const R w4 = times(w2, w2);
    const R q = V::add(V::add(pair2(0), times(pair2(2), w2)), times(pair2(4), w4));
    const R g = V::mul(V::set1(2.0f), times(v, q));
    return V::add(el, g);
}

#pragma GCC diagnostic pop

#if defined(__GNUC__) && defined(__x86_64__)
/// Four binary32 lanes of SSE (the baseline of x86-64): the operations exp_bound_f32 needs.
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
    __m128 r = exp_bound_f32<KernelSse2F>(x, s, coef);
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
    __m128 r = log_bound_f32<KernelSse2F>(x, _mm_set_ps(1.0f, 1.0f, 1.0f, -1.0f));
    asm volatile("" : "+x"(r));
    alignas(16) float v[4];
    _mm_store_ps(v, r);
    out[0] = -v[0];
    out[1] = v[1];
}
#endif

}  // namespace certray::detail
