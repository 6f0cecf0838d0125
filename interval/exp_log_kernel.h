// interval/exp_log_kernel.h — outward bounds of exp(x) and log(x) in upward rounding mode,
// without libm and without a mode switch, written once for any vector of doubles (the scalar
// UpInterval exp and log and the batched interval walk's lanes use the same operations in the same
// order, so they agree bit for bit).
//
// Contract: inside a RoundingScope (upward mode), for x with exp_kernel_applies(x) (|x| ≤ 708,
// x ≠ 0) and s = −1 or +1 per lane, exp_bound<V>(x, s) returns s·B where B is a lower bound of
// exp(x) for s = −1 and an upper bound for s = +1, both normal binary64 numbers within 6·2⁻⁵² of
// exp(x), relatively; log_bound<V>(x, s) likewise for log(x) where log_kernel_applies(x) (x
// normal, positive, finite, x ≠ 1), within 8·2⁻⁵². Other x (where the value is exact, the extremes,
// NaN) keep interval.h's libm path.
//
// How (docs/theory/exp_log_kernel.md has the proof):
// - k = ⌈x/ln2 − 1 − 2⁻³⁰⌉ (any rounding of the quotient), so that r = x − k·ln2 lies in
//   [6·10⁻¹⁰, 0.6932] whatever the rounding of its computation; exp(x) = 2ᵏ·exp(r), 2ᵏ exact.
// - r is bounded outward from ln2 = C1 + C2 (C1 with 32 bits: k·C1 exact; C2's error times |k|
//   below 2⁻⁷⁰, which is added).
// - exp(r) = Σ_{i ≤ 16} rⁱ/i! + R with 0 ≤ R ≤ r¹⁶·ρe^ρ/17! (ρ = 0.6932, e^ρ < 2.0002): the lower
//   bound drops R, the upper bound adds it to the coefficient of r¹⁶. Every coefficient, r and
//   every partial sum is positive, so the polynomial is increasing in each of them: evaluated with
//   every operation rounded down (lower) or up (upper) from the coefficients' bounds it gives the
//   bounds (any order of evaluation; Estrin's here, for its short dependency chains).
// - A lower bound is carried negated (−lo), so that both are operations rounded up: a sum of two
//   bounds is their sum, a product of two (positive) quantities is ↑(A′·(s·B′)) with A′ = s·A.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <iterator>

#if defined(__GNUC__) && defined(__x86_64__)
#include <emmintrin.h>
#endif

namespace certray::detail {

/// Whether exp_bound applies to x (NaN: no).
inline bool exp_kernel_applies(double x) { return x >= -708.0 && x <= 708.0 && x != 0.0; }
/// Whether log_bound applies to x (NaN: no).
inline bool log_kernel_applies(double x) {
    return x >= 0x1p-1022 && x <= 0x1.fffffffffffffp+1023 && x != 1.0;
}

/// The kernel's constants (docs/theory/exp_log_kernel.md; tests/interval/exp_log_kernel_test.cpp
/// checks them against MPFR).
struct ExpKernel {
    static constexpr double kInvLn2 = 0x1.71547652b82fep+0;  ///< ≈ 1/ln2 (any double near it)
    static constexpr double kShift = 0x1.0000000400000p+0;   ///< 1 + 2⁻³⁰
    static constexpr double kMagic = 0x1.8p+52;           ///< 1.5·2⁵²: integers in the mantissa
    static constexpr double kC1 = 0x1.62e42feep-1;        ///< ln2 to 32 bits, below ln2
    static constexpr double kC2 = 0x1.a39ef35793c76p-33;  ///< ≈ ln2 − C1, within 1.2·10⁻²⁶
    static constexpr double kSlack = 0x1p-70;             ///< ≥ 1100·|C2 − (ln2 − C1)|
    /// The bits of kMagic less 1023: bits(kd + kMagic) − kPow2Bias = kd + 1023, 2^kd's exponent.
    static constexpr std::int64_t kPow2Bias = std::bit_cast<std::int64_t>(kMagic) - 1023;
    /// Bounds of 1/i!, i = 0 … 16; the last upper bound also holds the remainder ρe^ρ/17!.
    static constexpr double kLo[17] = {
        1.0,
        1.0,
        0.5,
        0x1.5555555555555p-3,
        0x1.5555555555555p-5,
        0x1.1111111111111p-7,
        0x1.6c16c16c16c16p-10,
        0x1.a01a01a01a01ap-13,
        0x1.a01a01a01a01ap-16,
        0x1.71de3a556c733p-19,
        0x1.27e4fb7789f5cp-22,
        0x1.ae64567f544e3p-26,
        0x1.1eed8eff8d897p-29,
        0x1.6124613a86d09p-33,
        0x1.93974a8c07c9dp-37,
        0x1.ae7f3e733b81fp-41,
        0x1.ae7f3e733b81fp-45,
    };
    static constexpr double kHi[17] = {
        1.0,
        1.0,
        0.5,
        0x1.5555555555556p-3,
        0x1.5555555555556p-5,
        0x1.1111111111112p-7,
        0x1.6c16c16c16c17p-10,
        0x1.a01a01a01a01bp-13,
        0x1.a01a01a01a01bp-16,
        0x1.71de3a556c734p-19,
        0x1.27e4fb7789f5dp-22,
        0x1.ae64567f544e4p-26,
        0x1.1eed8eff8d898p-29,
        0x1.6124613a86d0ap-33,
        0x1.93974a8c07c9ep-37,
        0x1.ae7f3e733b820p-41,
        0x1.d19bde1b19df0p-45,
    };
};

/// log's constants: ln2 = [kLn2Lo, kLn2Hi] (adjacent doubles), √2 (the split of the mantissa), and
/// the bounds of 1/(2i + 1), i = 0 … 9, the last upper one holding the remainder
/// w_max/(21·(1 − w_max)) with w_max = 0.0295 ≥ ((√2 − 1)/(√2 + 1))².
struct LogKernel {
    static constexpr double kLn2Lo = 0x1.62e42fefa39efp-1;
    static constexpr double kLn2Hi = 0x1.62e42fefa39f0p-1;
    static constexpr double kSqrt2 = 0x1.6a09e667f3bcdp+0;
    static constexpr double kLo[10] = {
        1.0,
        0x1.5555555555555p-2,
        0x1.9999999999999p-3,
        0x1.2492492492492p-3,
        0x1.c71c71c71c71cp-4,
        0x1.745d1745d1745p-4,
        0x1.3b13b13b13b13p-4,
        0x1.1111111111111p-4,
        0x1.e1e1e1e1e1e1ep-5,
        0x1.af286bca1af28p-5,
    };
    static constexpr double kHi[10] = {
        1.0,
        0x1.5555555555556p-2,
        0x1.999999999999ap-3,
        0x1.2492492492493p-3,
        0x1.c71c71c71c71dp-4,
        0x1.745d1745d1746p-4,
        0x1.3b13b13b13b14p-4,
        0x1.1111111111112p-4,
        0x1.e1e1e1e1e1e1fp-5,
        0x1.bb03f80d5b645p-5,
    };
};

/// s·B for each lane (see the file contract). V provides R, set1, add, sub, mul (IEEE, in the
/// current mode), sign_of(a) (a's sign bit alone), flip(a, m) (a's bits xor m's: a with its sign
/// flipped where m is −0) and pow2(kd) = 2^kd for integral kd in [−1022, 1021] (exact). `s` is −1.0
/// (a lower bound, returned negated) or +1.0 (an upper bound) per lane; coef[i] holds per lane the
/// bound of 1/i! of the same side: ExpKernel::kLo[i] where s = −1, kHi[i] where s = +1.
// The kernels take and return vectors of any width; they are always inlined into code built for
// the width's instruction set (the walk's copies), so no call passes an AVX vector by value.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
///
/// K: the constants, ExpKernel (binary64, 17 coefficients) or ExpKernelF32
/// (interval/exp_log_kernel_f32.h: binary32 lanes, 10 coefficients); the same argument with
/// K's reduction constants and K's number of terms.
template <class V, class K = ExpKernel>
[[gnu::always_inline]] inline typename V::R exp_bound(typename V::R x, typename V::R s,
                                                      const typename V::R* coef) {
    using R = typename V::R;
    constexpr std::size_t kTerms = std::size(K::kLo);
    static_assert(kTerms == 17 || kTerms == 10, "Estrin's scheme below is written for these");
    const R y = V::mul(x, V::set1(K::kInvLn2));
    const R z = V::sub(y, V::set1(K::kShift));
    const R kd = V::sub(V::add(z, V::set1(K::kMagic)), V::set1(K::kMagic));  // ⌈z⌉ (upward mode)
    // Products by s = ±1 are sign flips: xor with s's sign bit (sm).
    const R sm = V::sign_of(s);
    const R nsm = V::flip(sm, V::set1(-0.0f));  // −s's
    // s·r rounded up: s·(x − k·C1) (k·C1 exact) − s·k·C2 + slack.
    const R kc1 = V::mul(kd, V::set1(K::kC1));
    const R d = V::sub(V::flip(x, sm), V::flip(kc1, sm));
    const R e = V::mul(V::flip(kd, nsm), V::set1(K::kC2));
    const R r = V::add(d, V::add(e, V::set1(K::kSlack)));  // r′ = s·(bound of r), bound > 0
    // Estrin: pairs c(2i) + c(2i+1)·r, then the powers r², r⁴, r⁸ (and r¹⁶) join them.
    const auto pair = [&](int i) {
        return V::add(V::flip(coef[i], sm), V::mul(coef[i + 1], r));  // s·c(i) + c(i+1)·r′
    };
    const auto times = [&](R a, R b) { return V::mul(a, V::flip(b, sm)); };  // (a·b)′
    const R r2 = times(r, r);
    const R r4 = times(r2, r2);
    const R r8 = times(r4, r4);
    const R q0 = V::add(pair(0), times(pair(2), r2));
    const R q1 = V::add(pair(4), times(pair(6), r2));
    const R o0 = V::add(q0, times(q1, r4));
    R p;
    if constexpr (kTerms == 17) {
        const R r16 = times(r8, r8);
        const R q2 = V::add(pair(8), times(pair(10), r2));
        const R q3 = V::add(pair(12), times(pair(14), r2));
        const R o1 = V::add(q2, times(q3, r4));
        const R h = V::add(o0, times(o1, r8));
        p = V::add(h, V::mul(coef[16], r16));  // + c(16)·r¹⁶′
    } else {
        p = V::add(o0, times(pair(8), r8));  // + (c(8) + c(9)·r)·r⁸′
    }
    return V::mul(p, V::pow2(kd));
}

/// s·B for log (see the file contract), where log_kernel_applies(x) in every lane. V provides what
/// exp_bound needs and div, max and log_split(x, e, m):
/// x = m·2^e with e integral and m in [√2/2, √2), both exact.
/// How (docs/theory/exp_log_kernel.md): log x = e·ln2 + σ·g(v), σ the sign of m − 1,
/// v = |m − 1|/(m + 1) ≤ 0.1716 and g(v) = 2v·Σ v²ⁱ/(2i + 1), increasing in v and in its positive
/// coefficients; s·(e·ln2) and the bound of σ·g of the same side, which is g's bound of side
/// t = s·σ, each rounded up, then summed.
///
/// K: LogKernel (binary64, 10 coefficients) or LogKernelF32 (interval/exp_log_kernel_f32.h:
/// binary32 lanes, 6 coefficients, the split at K::kSqrt2).
template <class V, class K = LogKernel>
[[gnu::always_inline]] inline typename V::R log_bound(typename V::R x, typename V::R s) {
    using R = typename V::R;
    constexpr std::size_t kTerms = std::size(K::kLo);
    static_assert(kTerms == 10 || kTerms == 6, "Estrin's scheme below is written for these");
    R e, m;
    V::log_split(x, e, m);
    // Products by ±1 are sign flips: xor with the sign bits of s (sm), of t = s·σ (tm) and −t.
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
    // The coefficients of side t as t·c: max(t·lo, t·hi). (A blend by tm's sign bit, as the trig
    // kernel's side_coef, measured 8% slower here on AVX2.)
    const auto coef = [&](int i) {
        return V::max(V::flip(V::set1(K::kLo[i]), tm), V::flip(V::set1(K::kHi[i]), tm));
    };
    const auto times = [&](R a, R b) { return V::mul(a, V::flip(b, tm)); };  // (a·b)′
    const R w = times(v, v);
    const auto pair2 = [&](int i) { return V::add(coef(i), times(coef(i + 1), w)); };
    const R w2 = times(w, w);
    const R w4 = times(w2, w2);
    const R q0 = V::add(pair2(0), times(pair2(2), w2));
    R q;
    if constexpr (kTerms == 10) {
        const R w8 = times(w4, w4);
        const R q1 = V::add(pair2(4), times(pair2(6), w2));
        q = V::add(V::add(q0, times(q1, w4)), times(pair2(8), w8));
    } else {
        q = V::add(q0, times(pair2(4), w4));
    }
    const R g = V::mul(V::set1(2.0f), times(v, q));
    return V::add(el, g);
}

#pragma GCC diagnostic pop

#if defined(__GNUC__) && defined(__x86_64__)
/// Two lanes of SSE2 (the baseline of x86-64): the scalar interval exp and log, the lower bound
/// in lane 0 and the upper bound in lane 1 (and interval/trig_kernel.h's sin and cos, a point in
/// each lane).
struct KernelSse2 {
    using R = __m128d;
    static R set1(double c) { return _mm_set1_pd(c); }
    static R add(R a, R b) { return _mm_add_pd(a, b); }
    static R sub(R a, R b) { return _mm_sub_pd(a, b); }
    static R mul(R a, R b) { return _mm_mul_pd(a, b); }
    static R div(R a, R b) { return _mm_div_pd(a, b); }
    static R max(R a, R b) { return _mm_max_pd(a, b); }
    static R min(R a, R b) { return _mm_min_pd(a, b); }
    using M = __m128d;  ///< a mask: all bits set in the lanes where a comparison holds
    static M le(R a, R b) { return _mm_cmple_pd(a, b); }
    static M lt(R a, R b) { return _mm_cmplt_pd(a, b); }
    static M eq(R a, R b) { return _mm_cmpeq_pd(a, b); }
    static M either(M a, M b) { return _mm_or_pd(a, b); }
    static R select(M m, R t, R f) { return _mm_or_pd(_mm_and_pd(m, t), _mm_andnot_pd(m, f)); }
    static constexpr int kWidth = 2;
    static unsigned bits(M m) { return static_cast<unsigned>(_mm_movemask_pd(m)); }
    static R sign_of(R a) { return _mm_and_pd(a, set1(-0.0)); }
    static R flip(R a, R m) { return _mm_xor_pd(a, m); }
    static void log_split(R x, R& e, R& m) {
        // x = f·2^E, f in [1, 2): E from the exponent bits (E + 1023 added to the bits of
        // 1.5·2⁵², then 1.5·2⁵² taken off, exactly), f with the exponent bits of 1; f ≥ √2 is
        // halved and E raised by one.
        const __m128i b = _mm_castpd_si128(x);
        const __m128i eb =
            _mm_add_epi64(_mm_srli_epi64(b, 52), _mm_set1_epi64x(ExpKernel::kPow2Bias));
        const R big_e = _mm_sub_pd(_mm_castsi128_pd(eb), set1(ExpKernel::kMagic));
        const R f =
            _mm_castsi128_pd(_mm_or_si128(_mm_and_si128(b, _mm_set1_epi64x(0x000fffffffffffffLL)),
                                          _mm_set1_epi64x(0x3ff0000000000000LL)));
        const R big = _mm_cmpge_pd(f, set1(LogKernel::kSqrt2));
        e = _mm_add_pd(big_e, _mm_and_pd(big, set1(1.0)));
        m = _mm_or_pd(_mm_and_pd(big, _mm_mul_pd(f, set1(0.5))), _mm_andnot_pd(big, f));
    }
    static R pow2(R kd) {
        // kd + 1.5·2⁵² (exact) has the bits of 1.5·2⁵² plus kd: (kd + 1023) << 52 is 2^kd.
        const __m128i b = _mm_castpd_si128(_mm_add_pd(kd, _mm_set1_pd(ExpKernel::kMagic)));
        const __m128i bias = _mm_set1_epi64x(ExpKernel::kPow2Bias);
        return _mm_castsi128_pd(_mm_slli_epi64(_mm_sub_epi64(b, bias), 52));
    }
};

/// Lane 0: a lower bound of exp(a), lane 1: an upper bound of exp(b), into out[0], out[1] (upward
/// mode held; exp_kernel_applies(a) and (b)). The operands and results pass register barriers, so
/// that the computation stays inside the caller's rounding scope.
inline void exp_kernel_bounds(double a, double b, double* out) {
    __m128d x = _mm_set_pd(b, a);
    asm volatile("" : "+x"(x));
    const __m128d s = _mm_set_pd(1.0, -1.0);
    __m128d coef[17];
    for (int i = 0; i < 17; ++i) coef[i] = _mm_set_pd(ExpKernel::kHi[i], ExpKernel::kLo[i]);
    __m128d r = exp_bound<KernelSse2>(x, s, coef);
    asm volatile("" : "+x"(r));
    out[0] = -_mm_cvtsd_f64(r);
    out[1] = _mm_cvtsd_f64(_mm_unpackhi_pd(r, r));
}

/// Lane 0: a lower bound of log(a), lane 1: an upper bound of log(b), into out[0], out[1] (upward
/// mode held; log_kernel_applies(a) and (b)), as exp_kernel_bounds.
inline void log_kernel_bounds(double a, double b, double* out) {
    __m128d x = _mm_set_pd(b, a);
    asm volatile("" : "+x"(x));
    __m128d r = log_bound<KernelSse2>(x, _mm_set_pd(1.0, -1.0));
    asm volatile("" : "+x"(r));
    out[0] = -_mm_cvtsd_f64(r);
    out[1] = _mm_cvtsd_f64(_mm_unpackhi_pd(r, r));
}

/// [lo, hi] in place for exp or log (lo ≤ hi, not NaN; upward mode held): `kernel`'s bounds
/// (exp_kernel_bounds, log_kernel_bounds) on the bounds where `applies`, `libm`'s (interval.h's
/// exp_bounds, log_bounds) on the others.
template <class Applies, class Kernel, class Libm>
void kernel_or_libm(double& lo, double& hi, Applies applies, Kernel kernel, Libm libm) {
    const bool kernel_lo = applies(lo), kernel_hi = applies(hi);
    if (!kernel_lo && !kernel_hi) return libm(lo, hi);
    double b[2];
    kernel(kernel_lo ? lo : hi, kernel_hi ? hi : lo, b);  // an operand the kernel takes
    if (!kernel_lo || !kernel_hi) libm(lo, hi);
    if (kernel_lo) lo = b[0];
    if (kernel_hi) hi = b[1];
}
#endif

}  // namespace certray::detail
