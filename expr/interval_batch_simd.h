// expr/interval_batch_simd.h — internal to the interval batch walk (eval_interval_batch.cpp): one
// vector type per instruction set, with the operations the UpInterval kernels are made of.
//
// Contract: each type is expr/batch_simd.h's type of its instruction set (R, kWidth, load/store,
// set1, the IEEE + − × ÷ √ rounded in the current MXCSR mode, as the scalar SSE instructions of
// the kernels are, neg), with max and min by the x86 instruction's rule instead of Batch's — max(a,
// b) = (a > b) ? a : b, min(a, b) = (a < b) ? a : b, NaN and equal operands giving b, exactly
// interval.h's max2/min2 and the MAXPD of its two-lane product kernel — and M (a mask of kWidth
// lanes), ordered comparisons (false for NaN), and/or of masks, select, the mask as kWidth bits,
// same (the lanes whose two operands have the same bits, as kWidth bits), and prev (the double
// whose bits are one less); and what interval/exp_log_kernel.h's and
// interval/trig_kernel.h's kernels need: pow2 (2^kd for integral kd in [−1022, 1021], exactly),
// sign_of, flip and log_split, each the same bits as KernelSse2's on its lanes. The AVX types'
// functions carry target attributes: they inline only into functions compiled for that target (no
// -march anywhere).
#pragma once

#include "expr/batch_simd.h"
#include "interval/exp_log_kernel.h"
#include "interval/exp_log_kernel_f32.h"
#include "interval/trig_kernel.h"
#include "interval/trig_kernel_f32.h"

namespace certray::expr::detail {
// Internal linkage, as if written in eval_interval_batch.cpp, the one file that includes this
// header: the AVX types' functions must never be shared with code built for another target.
namespace {

#if CERTRAY_BATCH_X86
struct IvSse2 : Sse2 {
    using M = __m128d;
    static R pow2(R kd) { return certray::detail::KernelSse2::pow2(kd); }
    static R sign_of(R a) { return certray::detail::KernelSse2::sign_of(a); }
    static R flip(R a, R m) { return certray::detail::KernelSse2::flip(a, m); }
    static void log_split(R x, R& e, R& m) { certray::detail::KernelSse2::log_split(x, e, m); }
    static R max(R a, R b) { return _mm_max_pd(a, b); }
    static R min(R a, R b) { return _mm_min_pd(a, b); }
    static R prev(R a) {
        return _mm_castsi128_pd(_mm_sub_epi64(_mm_castpd_si128(a), _mm_set1_epi64x(1)));
    }
    static M le(R a, R b) { return _mm_cmple_pd(a, b); }
    static M lt(R a, R b) { return _mm_cmplt_pd(a, b); }
    static M eq(R a, R b) { return _mm_cmpeq_pd(a, b); }
    static M ord(R a, R b) { return _mm_cmpord_pd(a, b); }
    static M both(M a, M b) { return _mm_and_pd(a, b); }
    static M either(M a, M b) { return _mm_or_pd(a, b); }
    static R select(M m, R t, R f) { return _mm_or_pd(_mm_and_pd(m, t), _mm_andnot_pd(m, f)); }
    static unsigned bits(M m) { return static_cast<unsigned>(_mm_movemask_pd(m)); }
    /// The lanes whose a and b have the same bits, as kWidth bits (both halves of each equal).
    static unsigned same(R a, R b) {
        const __m128i e = _mm_cmpeq_epi32(_mm_castpd_si128(a), _mm_castpd_si128(b));
        const __m128i swapped = _mm_shuffle_epi32(e, _MM_SHUFFLE(2, 3, 0, 1));
        return static_cast<unsigned>(_mm_movemask_pd(_mm_castsi128_pd(_mm_and_si128(e, swapped))));
    }
};

#define CERTRAY_AVX2 [[gnu::target("avx2")]]
struct IvAvx2 : Avx2 {
    using M = __m256d;
    CERTRAY_AVX2 static R sign_of(R a) { return _mm256_and_pd(a, _mm256_set1_pd(-0.0)); }
    CERTRAY_AVX2 static R flip(R a, R m) { return _mm256_xor_pd(a, m); }
    CERTRAY_AVX2 static void log_split(R x, R& e, R& m) {  // as KernelSse2's, four lanes
        using K = certray::detail::ExpKernel;
        const __m256i b = _mm256_castpd_si256(x);
        const __m256i eb =
            _mm256_add_epi64(_mm256_srli_epi64(b, 52), _mm256_set1_epi64x(K::kPow2Bias));
        const R big_e = _mm256_sub_pd(_mm256_castsi256_pd(eb), _mm256_set1_pd(K::kMagic));
        const R f = _mm256_castsi256_pd(
            _mm256_or_si256(_mm256_and_si256(b, _mm256_set1_epi64x(0x000fffffffffffffLL)),
                            _mm256_set1_epi64x(0x3ff0000000000000LL)));
        const R big =
            _mm256_cmp_pd(f, _mm256_set1_pd(certray::detail::LogKernel::kSqrt2), _CMP_GE_OQ);
        e = _mm256_add_pd(big_e, _mm256_and_pd(big, _mm256_set1_pd(1.0)));
        m = _mm256_blendv_pd(f, _mm256_mul_pd(f, _mm256_set1_pd(0.5)), big);
    }
    CERTRAY_AVX2 static R pow2(R kd) {  // as KernelSse2::pow2, four lanes
        using K = certray::detail::ExpKernel;
        const __m256i b = _mm256_castpd_si256(_mm256_add_pd(kd, _mm256_set1_pd(K::kMagic)));
        return _mm256_castsi256_pd(
            _mm256_slli_epi64(_mm256_sub_epi64(b, _mm256_set1_epi64x(K::kPow2Bias)), 52));
    }
    CERTRAY_AVX2 static R max(R a, R b) { return _mm256_max_pd(a, b); }
    CERTRAY_AVX2 static R min(R a, R b) { return _mm256_min_pd(a, b); }
    CERTRAY_AVX2 static R prev(R a) {
        return _mm256_castsi256_pd(_mm256_sub_epi64(_mm256_castpd_si256(a), _mm256_set1_epi64x(1)));
    }
    CERTRAY_AVX2 static M le(R a, R b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
    CERTRAY_AVX2 static M lt(R a, R b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
    CERTRAY_AVX2 static M eq(R a, R b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
    CERTRAY_AVX2 static M ord(R a, R b) { return _mm256_cmp_pd(a, b, _CMP_ORD_Q); }
    CERTRAY_AVX2 static M both(M a, M b) { return _mm256_and_pd(a, b); }
    CERTRAY_AVX2 static M either(M a, M b) { return _mm256_or_pd(a, b); }
    CERTRAY_AVX2 static R select(M m, R t, R f) { return _mm256_blendv_pd(f, t, m); }
    /// b where m's sign bit is set, else a (the kernels' selects by a sign).
    CERTRAY_AVX2 static R by_sign(R a, R b, R m) { return _mm256_blendv_pd(a, b, m); }
    CERTRAY_AVX2 static unsigned bits(M m) { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
    CERTRAY_AVX2 static unsigned same(R a, R b) {
        return bits(_mm256_castsi256_pd(
            _mm256_cmpeq_epi64(_mm256_castpd_si256(a), _mm256_castpd_si256(b))));
    }
};
#undef CERTRAY_AVX2

// Binary32 lanes for the float walk: the operations the kernels of + − × ÷ square √ neg abs min
// max take, as IvSse2's and IvAvx2's on four and eight binary32 lanes (set1 of a double that is a
// binary32 number: the constants 0, −0, 1 and NaN of the kernels), and what
// interval/exp_log_kernel_f32.h's needs (sign_of, flip, pow2 as its KernelSse2F's).
struct IvSse2F {
    using R = __m128;
    using M = __m128;
    static constexpr int kWidth = 4;
    static R load(const float* p) { return _mm_loadu_ps(p); }
    static void store(float* p, R x) { _mm_storeu_ps(p, x); }
    static R set1(double c) { return _mm_set1_ps(static_cast<float>(c)); }
    static R add(R a, R b) { return _mm_add_ps(a, b); }
    static R sub(R a, R b) { return _mm_sub_ps(a, b); }
    static R mul(R a, R b) { return _mm_mul_ps(a, b); }
    static R div(R a, R b) { return _mm_div_ps(a, b); }
    static R sqrt(R a) { return _mm_sqrt_ps(a); }
    static R neg(R a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
    static R sign_of(R a) { return certray::detail::KernelSse2F::sign_of(a); }
    static R flip(R a, R m) { return certray::detail::KernelSse2F::flip(a, m); }
    static R pow2(R kd) { return certray::detail::KernelSse2F::pow2(kd); }
    static void log_split(R x, R& e, R& m) { certray::detail::KernelSse2F::log_split(x, e, m); }
    static R max(R a, R b) { return _mm_max_ps(a, b); }
    static R min(R a, R b) { return _mm_min_ps(a, b); }
    static R prev(R a) {
        return _mm_castsi128_ps(_mm_sub_epi32(_mm_castps_si128(a), _mm_set1_epi32(1)));
    }
    static M le(R a, R b) { return _mm_cmple_ps(a, b); }
    static M lt(R a, R b) { return _mm_cmplt_ps(a, b); }
    static M eq(R a, R b) { return _mm_cmpeq_ps(a, b); }
    static M ord(R a, R b) { return _mm_cmpord_ps(a, b); }
    static M both(M a, M b) { return _mm_and_ps(a, b); }
    static M either(M a, M b) { return _mm_or_ps(a, b); }
    static R select(M m, R t, R f) { return _mm_or_ps(_mm_and_ps(m, t), _mm_andnot_ps(m, f)); }
    static unsigned bits(M m) { return static_cast<unsigned>(_mm_movemask_ps(m)); }
    static unsigned same(R a, R b) {
        return bits(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_castps_si128(a), _mm_castps_si128(b))));
    }
};

#define CERTRAY_AVX2 [[gnu::target("avx2")]]
struct IvAvx2F {
    using R = __m256;
    using M = __m256;
    static constexpr int kWidth = 8;
    CERTRAY_AVX2 static R load(const float* p) { return _mm256_loadu_ps(p); }
    CERTRAY_AVX2 static void store(float* p, R x) { _mm256_storeu_ps(p, x); }
    CERTRAY_AVX2 static R set1(double c) { return _mm256_set1_ps(static_cast<float>(c)); }
    CERTRAY_AVX2 static R add(R a, R b) { return _mm256_add_ps(a, b); }
    CERTRAY_AVX2 static R sub(R a, R b) { return _mm256_sub_ps(a, b); }
    CERTRAY_AVX2 static R mul(R a, R b) { return _mm256_mul_ps(a, b); }
    CERTRAY_AVX2 static R div(R a, R b) { return _mm256_div_ps(a, b); }
    CERTRAY_AVX2 static R sqrt(R a) { return _mm256_sqrt_ps(a); }
    CERTRAY_AVX2 static R neg(R a) { return _mm256_xor_ps(a, _mm256_set1_ps(-0.0f)); }
    CERTRAY_AVX2 static R sign_of(R a) { return _mm256_and_ps(a, _mm256_set1_ps(-0.0f)); }
    CERTRAY_AVX2 static R flip(R a, R m) { return _mm256_xor_ps(a, m); }
    CERTRAY_AVX2 static void log_split(R x, R& e, R& m) {  // as KernelSse2F's, eight lanes
        using K = certray::detail::ExpKernelF32;
        const __m256i b = _mm256_castps_si256(x);
        const __m256i eb =
            _mm256_add_epi32(_mm256_srli_epi32(b, 23), _mm256_set1_epi32(K::kPow2Bias));
        const R big_e = _mm256_sub_ps(_mm256_castsi256_ps(eb), _mm256_set1_ps(K::kMagic));
        const R f = _mm256_castsi256_ps(_mm256_or_si256(
            _mm256_and_si256(b, _mm256_set1_epi32(0x007fffff)), _mm256_set1_epi32(0x3f800000)));
        const R big =
            _mm256_cmp_ps(f, _mm256_set1_ps(certray::detail::LogKernelF32::kSqrt2), _CMP_GE_OQ);
        e = _mm256_add_ps(big_e, _mm256_and_ps(big, _mm256_set1_ps(1.0f)));
        m = _mm256_blendv_ps(f, _mm256_mul_ps(f, _mm256_set1_ps(0.5f)), big);
    }
    CERTRAY_AVX2 static R pow2(R kd) {  // as KernelSse2F::pow2, eight lanes
        using K = certray::detail::ExpKernelF32;
        const __m256i b = _mm256_castps_si256(_mm256_add_ps(kd, _mm256_set1_ps(K::kMagic)));
        return _mm256_castsi256_ps(
            _mm256_slli_epi32(_mm256_sub_epi32(b, _mm256_set1_epi32(K::kPow2Bias)), 23));
    }
    CERTRAY_AVX2 static R max(R a, R b) { return _mm256_max_ps(a, b); }
    CERTRAY_AVX2 static R min(R a, R b) { return _mm256_min_ps(a, b); }
    CERTRAY_AVX2 static R prev(R a) {
        return _mm256_castsi256_ps(_mm256_sub_epi32(_mm256_castps_si256(a), _mm256_set1_epi32(1)));
    }
    CERTRAY_AVX2 static M le(R a, R b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
    CERTRAY_AVX2 static M lt(R a, R b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
    CERTRAY_AVX2 static M eq(R a, R b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
    CERTRAY_AVX2 static M ord(R a, R b) { return _mm256_cmp_ps(a, b, _CMP_ORD_Q); }
    CERTRAY_AVX2 static M both(M a, M b) { return _mm256_and_ps(a, b); }
    CERTRAY_AVX2 static M either(M a, M b) { return _mm256_or_ps(a, b); }
    CERTRAY_AVX2 static R select(M m, R t, R f) { return _mm256_blendv_ps(f, t, m); }
    /// b where m's sign bit is set, else a (the kernels' selects by a sign).
    CERTRAY_AVX2 static R by_sign(R a, R b, R m) { return _mm256_blendv_ps(a, b, m); }
    CERTRAY_AVX2 static unsigned bits(M m) { return static_cast<unsigned>(_mm256_movemask_ps(m)); }
    CERTRAY_AVX2 static unsigned same(R a, R b) {
        return bits(_mm256_castsi256_ps(
            _mm256_cmpeq_epi32(_mm256_castps_si256(a), _mm256_castps_si256(b))));
    }
};
#undef CERTRAY_AVX2

#define CERTRAY_AVX512 [[gnu::target("avx512f")]]
struct IvAvx512 : Avx512 {
    using M = __mmask8;
    CERTRAY_AVX512 static R sign_of(R a) {  // as KernelSse2's (integer and: none for FP in F)
        return _mm512_castsi512_pd(_mm512_and_epi64(
            _mm512_castpd_si512(a), _mm512_set1_epi64(static_cast<long long>(1ull << 63))));
    }
    CERTRAY_AVX512 static R flip(R a, R m) {
        return _mm512_castsi512_pd(
            _mm512_xor_epi64(_mm512_castpd_si512(a), _mm512_castpd_si512(m)));
    }
    CERTRAY_AVX512 static void log_split(R x, R& e, R& m) {  // as KernelSse2's, eight lanes
        using K = certray::detail::ExpKernel;
        const __m512i b = _mm512_castpd_si512(x);
        const __m512i eb =
            _mm512_add_epi64(_mm512_srli_epi64(b, 52), _mm512_set1_epi64(K::kPow2Bias));
        const R big_e = _mm512_sub_pd(_mm512_castsi512_pd(eb), _mm512_set1_pd(K::kMagic));
        const R f = _mm512_castsi512_pd(
            _mm512_or_epi64(_mm512_and_epi64(b, _mm512_set1_epi64(0x000fffffffffffffLL)),
                            _mm512_set1_epi64(0x3ff0000000000000LL)));
        const __mmask8 big =
            _mm512_cmp_pd_mask(f, _mm512_set1_pd(certray::detail::LogKernel::kSqrt2), _CMP_GE_OQ);
        e = _mm512_mask_add_pd(big_e, big, big_e, _mm512_set1_pd(1.0));
        m = _mm512_mask_mul_pd(f, big, f, _mm512_set1_pd(0.5));
    }
    CERTRAY_AVX512 static R pow2(R kd) {  // as KernelSse2::pow2, eight lanes
        using K = certray::detail::ExpKernel;
        const __m512i b = _mm512_castpd_si512(_mm512_add_pd(kd, _mm512_set1_pd(K::kMagic)));
        return _mm512_castsi512_pd(
            _mm512_slli_epi64(_mm512_sub_epi64(b, _mm512_set1_epi64(K::kPow2Bias)), 52));
    }
    CERTRAY_AVX512 static R max(R a, R b) { return _mm512_max_pd(a, b); }
    CERTRAY_AVX512 static R min(R a, R b) { return _mm512_min_pd(a, b); }
    CERTRAY_AVX512 static R prev(R a) {
        return _mm512_castsi512_pd(_mm512_sub_epi64(_mm512_castpd_si512(a), _mm512_set1_epi64(1)));
    }
    CERTRAY_AVX512 static M le(R a, R b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
    CERTRAY_AVX512 static M lt(R a, R b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
    CERTRAY_AVX512 static M eq(R a, R b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
    CERTRAY_AVX512 static M ord(R a, R b) { return _mm512_cmp_pd_mask(a, b, _CMP_ORD_Q); }
    CERTRAY_AVX512 static M both(M a, M b) { return static_cast<M>(a & b); }
    CERTRAY_AVX512 static M either(M a, M b) { return static_cast<M>(a | b); }
    CERTRAY_AVX512 static R select(M m, R t, R f) { return _mm512_mask_blend_pd(m, f, t); }
    CERTRAY_AVX512 static unsigned bits(M m) { return m; }
    CERTRAY_AVX512 static unsigned same(R a, R b) {
        return _mm512_cmpeq_epi64_mask(_mm512_castpd_si512(a), _mm512_castpd_si512(b));
    }
};

// IvAvx2F's operations on sixteen binary32 lanes (AVX-512F: masks in k registers, the sign
// operations by integer instructions, as IvAvx512's). No by_sign: a select by a sign bit takes two
// instructions here, and the kernels' other path gives the same bits.
struct IvAvx512F {
    using R = __m512;
    using M = __mmask16;
    static constexpr int kWidth = 16;
    CERTRAY_AVX512 static __m512i bits_of(R a) { return _mm512_castps_si512(a); }
    CERTRAY_AVX512 static R of_bits(__m512i a) { return _mm512_castsi512_ps(a); }
    CERTRAY_AVX512 static __m512i sign_bit() {
        return _mm512_set1_epi32(static_cast<int>(0x80000000u));
    }
    CERTRAY_AVX512 static R load(const float* p) { return _mm512_loadu_ps(p); }
    CERTRAY_AVX512 static void store(float* p, R x) { _mm512_storeu_ps(p, x); }
    CERTRAY_AVX512 static R set1(double c) { return _mm512_set1_ps(static_cast<float>(c)); }
    CERTRAY_AVX512 static R add(R a, R b) { return _mm512_add_ps(a, b); }
    CERTRAY_AVX512 static R sub(R a, R b) { return _mm512_sub_ps(a, b); }
    CERTRAY_AVX512 static R mul(R a, R b) { return _mm512_mul_ps(a, b); }
    CERTRAY_AVX512 static R div(R a, R b) { return _mm512_div_ps(a, b); }
    CERTRAY_AVX512 static R sqrt(R a) { return _mm512_sqrt_ps(a); }
    CERTRAY_AVX512 static R neg(R a) { return of_bits(_mm512_xor_si512(bits_of(a), sign_bit())); }
    CERTRAY_AVX512 static R sign_of(R a) {
        return of_bits(_mm512_and_si512(bits_of(a), sign_bit()));
    }
    CERTRAY_AVX512 static R flip(R a, R m) {
        return of_bits(_mm512_xor_si512(bits_of(a), bits_of(m)));
    }
    CERTRAY_AVX512 static void log_split(R x, R& e, R& m) {  // as KernelSse2F's, sixteen lanes
        using K = certray::detail::ExpKernelF32;
        const __m512i b = bits_of(x);
        const __m512i eb =
            _mm512_add_epi32(_mm512_srli_epi32(b, 23), _mm512_set1_epi32(K::kPow2Bias));
        const R big_e = _mm512_sub_ps(of_bits(eb), _mm512_set1_ps(K::kMagic));
        const R f = of_bits(_mm512_or_si512(_mm512_and_si512(b, _mm512_set1_epi32(0x007fffff)),
                                            _mm512_set1_epi32(0x3f800000)));
        const __mmask16 big = _mm512_cmp_ps_mask(
            f, _mm512_set1_ps(certray::detail::LogKernelF32::kSqrt2), _CMP_GE_OQ);
        e = _mm512_mask_add_ps(big_e, big, big_e, _mm512_set1_ps(1.0f));
        m = _mm512_mask_mul_ps(f, big, f, _mm512_set1_ps(0.5f));
    }
    CERTRAY_AVX512 static R pow2(R kd) {  // as KernelSse2F::pow2, sixteen lanes
        using K = certray::detail::ExpKernelF32;
        const __m512i b = bits_of(_mm512_add_ps(kd, _mm512_set1_ps(K::kMagic)));
        return of_bits(_mm512_slli_epi32(_mm512_sub_epi32(b, _mm512_set1_epi32(K::kPow2Bias)), 23));
    }
    CERTRAY_AVX512 static R max(R a, R b) { return _mm512_max_ps(a, b); }
    CERTRAY_AVX512 static R min(R a, R b) { return _mm512_min_ps(a, b); }
    CERTRAY_AVX512 static R prev(R a) {
        return of_bits(_mm512_sub_epi32(bits_of(a), _mm512_set1_epi32(1)));
    }
    CERTRAY_AVX512 static M le(R a, R b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
    CERTRAY_AVX512 static M lt(R a, R b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
    CERTRAY_AVX512 static M eq(R a, R b) { return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
    CERTRAY_AVX512 static M ord(R a, R b) { return _mm512_cmp_ps_mask(a, b, _CMP_ORD_Q); }
    CERTRAY_AVX512 static M both(M a, M b) { return static_cast<M>(a & b); }
    CERTRAY_AVX512 static M either(M a, M b) { return static_cast<M>(a | b); }
    CERTRAY_AVX512 static R select(M m, R t, R f) { return _mm512_mask_blend_ps(m, f, t); }
    CERTRAY_AVX512 static unsigned bits(M m) { return m; }
    CERTRAY_AVX512 static unsigned same(R a, R b) {
        return _mm512_cmpeq_epi32_mask(bits_of(a), bits_of(b));
    }
};
#undef CERTRAY_AVX512
#endif

}  // namespace
}  // namespace certray::expr::detail
