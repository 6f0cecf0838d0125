// interval/trig_kernel_f32.h — outward bounds of sin and cos over an interval in binary32, in
// upward rounding mode, without libm and without a mode switch, for the binary32 lane walk
// (expr/eval_interval_batch.h): the constants of interval/trig_kernel.h's trig_point and
// trig_interval for vectors of floats, with fewer terms.
//
// Contract: inside a RoundingScope (upward mode), for binary32 l ≤ u with trig_f32_kernel_applies
// (|x| ≤ 2⁹), trig_interval<V, TrigKernelF32>(l, u, sine, lo, hi, points) gives per lane
// [lo, hi] ⊇ {sin x or cos x : x ∈ [l, u]}, within [−1, 1]; trig_point<V, TrigKernelF32>(x, s,
// cosine) gives s·B, B a lower (s = −1) or upper (s = +1) bound of sin(x) or cos(x) within
// 2⁻¹⁸·|f(x)| + 2⁻²⁶ of it (tested against MPFR).
//
// How: interval/trig_kernel.h's argument (docs/theory/trig_kernel.md), in binary32:
// - k = ⌈2x/π − ½⌉ from a binary32 2/π; for |x| ≤ 2⁹ the quotient's and the difference's errors
//   stay below 10⁻⁴ of a quadrant, so |r| = |x − k·π/2| < 0.786 as in double.
// - π/2 = P1 + P2 + ε: P1 with 15 significant bits (k·P1 exact for |k| < 2⁹), |ε| < 2⁻³⁹; r is
//   bounded outward as in double, with |k|·2⁻³⁹ for ε.
// - cos r = C(r²), sin r = r·S(r²) to degree 4 in w = r², the alternating remainder in the
//   coefficient of w⁵: [−1/10!, 0] (C) and [−1/11!, 0] (S); at w ≤ 0.618 the remainder is below
//   2.5·10⁻⁸ (C) and 2.3·10⁻⁹ (S), inside the bound's 2⁻¹⁸.
#pragma once

#include "interval/exp_log_kernel_f32.h"
#include "interval/trig_kernel.h"

namespace certray::detail {

/// Whether the binary32 trig kernel applies to x (NaN: no).
inline bool trig_f32_kernel_applies(float x) { return x >= -0x1p9f && x <= 0x1p9f; }

/// The binary32 trig kernel's constants (tests/interval/trig_kernel_test.cpp checks them against
/// MPFR).
struct TrigKernelF32 {
    static constexpr float kMagic = ExpKernelF32::kMagic;  ///< 1.5·2²³: ⌈a⌉ in upward mode
    static constexpr float kTwoOverPi = 0x1.45f306p-1f;    ///< ≈ 2/π (any float near it)
    static constexpr float kP1 = 0x1.921cp+0f;             ///< π/2 to 15 bits, below π/2
    static constexpr float kP2 = 0x1.daa222p-15f;          ///< ≈ π/2 − P1
    static constexpr float kSlack = 0x1p-39f;              ///< ≥ |π/2 − P1 − P2|
    static constexpr float kPiLo = 0x1.921fb4p+1f;         ///< RD(π)
    static constexpr float kPiHi = 0x1.921fb6p+1f;         ///< RU(π)
    static constexpr float kBound = 0x1p9f;  ///< where the kernel applies: |x| ≤ 2⁹
    /// Bounds of (−1)ⁱ/(2i)!, i = 0 … 4, and [−1/10!, 0] for the remainder's w⁵.
    static constexpr float kCosLo[6] = {
        1.0f, -0.5f, 0x1.555554p-5f, -0x1.6c16c2p-10f, 0x1.a01ap-16f, -0x1.27e4fcp-22f};
    static constexpr float kCosHi[6] = {
        1.0f, -0.5f, 0x1.555556p-5f, -0x1.6c16cp-10f, 0x1.a01a02p-16f, 0.0f};
    /// Bounds of (−1)ⁱ/(2i + 1)!, i = 0 … 4, and [−1/11!, 0] for the remainder's w⁵.
    static constexpr float kSinLo[6] = {
        1.0f, -0x1.555556p-3f, 0x1.11111p-7f, -0x1.a01a02p-13f, 0x1.71de3ap-19f, -0x1.ae6458p-26f};
    static constexpr float kSinHi[6] = {1.0f,           -0x1.555554p-3f, 0x1.111112p-7f,
                                        -0x1.a01ap-13f, 0x1.71de3cp-19f, 0.0f};
};
static_assert(blend_gives_max(TrigKernelF32::kCosLo, TrigKernelF32::kCosHi, 6));
static_assert(blend_gives_max(TrigKernelF32::kSinLo, TrigKernelF32::kSinHi, 6));

#if defined(__GNUC__) && defined(__x86_64__)
/// Lane 0: a lower bound, lane 1: an upper bound of sin(x) (cosine = false) or cos(x), into
/// out[0], out[1] (upward mode held; trig_f32_kernel_applies(x)). For the tests; the walk inlines
/// the kernel.
inline void trig_f32_point_bounds(float x, bool cosine, float* out) {
    __m128 xv = _mm_set1_ps(x);
    asm volatile("" : "+x"(xv));
    __m128 r =
        trig_point<KernelSse2F, TrigKernelF32>(xv, _mm_set_ps(1.0f, 1.0f, 1.0f, -1.0f), cosine);
    asm volatile("" : "+x"(r));
    alignas(16) float v[4];
    _mm_store_ps(v, r);
    out[0] = -v[0];
    out[1] = v[1];
}

/// [lo, hi] ⊇ sin([l, u]) (sine) or cos([l, u]) by the binary32 kernel, into out[0], out[1]
/// (upward mode held; l ≤ u, both applying). For the tests.
inline void trig_f32_interval_bounds(float l, float u, bool sine, float* out) {
    using V = KernelSse2F;
    __m128 lv = _mm_set1_ps(l), uv = _mm_set1_ps(u);
    asm volatile("" : "+x"(lv), "+x"(uv));
    __m128 lo, hi;
    trig_interval<V, TrigKernelF32>(
        lv, uv, sine, lo, hi,
        [&](__m128 x1, __m128 s1, __m128 x2, __m128 s2, __m128& r1, __m128& r2) {
            r1 = trig_point<V, TrigKernelF32>(x1, s1, !sine);
            r2 = trig_point<V, TrigKernelF32>(x2, s2, !sine);
        });
    asm volatile("" : "+x"(lo), "+x"(hi));
    out[0] = _mm_cvtss_f32(lo);
    out[1] = _mm_cvtss_f32(hi);
}
#endif

}  // namespace certray::detail
