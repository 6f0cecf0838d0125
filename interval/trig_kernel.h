// interval/trig_kernel.h — outward bounds of sin and cos over an interval in upward rounding mode,
// without libm and without a mode switch, written once for any vector of doubles (the scalar
// UpInterval sin and cos and the batched interval walk's lanes run the same operations in the same
// order, so they agree bit for bit).
//
// Contract: inside a RoundingScope (upward mode), for l ≤ u with trig_kernel_applies(l) and (u)
// (|x| ≤ 2¹⁹), trig_interval<V>(l, u, sine, lo, hi) gives per lane [lo, hi] ⊇ {sin x or cos x :
// x ∈ [l, u]}, within [−1, 1]. Its bounds lie within 3·2⁻⁵² relatively of the function's extreme
// values on [l, u], plus an absolute 2⁻⁶² from the reduction by π/2 (tested against MPFR); at 0
// they are exact. Other intervals keep interval.h's libm path.
//
// How (docs/theory/trig_kernel.md has the proof):
// - The interval: its extrema are placed as interval.h's trig_bounds places them (k0 = ⌈lo/π⌉,
//   k1 = ⌊hi/π⌋ from outward quotients, less ½ for sin). None inside: f is monotone on [l, u],
//   decreasing where k1 is even, so one bound comes from l and the other from u. One inside: ±1
//   on one side, the least (greatest) of the bounds at l and u of the other side. So each
//   interval needs one bound at l and one at u, each of a side chosen per lane.
// - A point x: k = ⌈2x/π − ½⌉ (any rounding of the product), r = x − k·π/2 with |r| < 0.786, and
//   sin(x) (cos(x) = sin(x + π/2): k + 1) is σ·h(r), h = sin or cos by the parity of k, σ = −1
//   where k mod 4 ≥ 2. π/2 = P1 + P2 + ε (P1 with 32 bits, so k·P1 is exact; |ε| < 2⁻⁸⁷): r is
//   bounded outward by [r_lo, r_hi], each end rounded its own way, with |k|·2⁻⁸⁷ for ε.
// - cos r = C(r²) and sin r = r·S(r²), C(w) = Σ (−1)ⁱwⁱ/(2i)! and S(w) = Σ (−1)ⁱwⁱ/(2i + 1)!, both
//   decreasing in w on [0, 0.618] ⊇ [0, r²]; to degree 8, the alternating remainder lies in
//   [−w⁹/18!, 0] (C) and [−w⁹/19!, 0] (S), the coefficient of w⁹. At a point w ≥ 0, Horner's
//   steps c + w·q are increasing in c and q, so with the coefficients' bounds of one side and every
//   operation rounded that way they bound the polynomial on that side.
// - cos(r) is bounded above at the least r² over [r_lo, r_hi] rounded down and below at the
//   greatest rounded up; sin(r), increasing, at r_hi above and r_lo below, S's side then flipped
//   where that end is negative.
// - As in exp_log_kernel.h, a bound B of side s = ±1 is carried as s·B, so that every operation is
//   rounded up; sign flips are xors with sign bits.
#pragma once

#include "interval/exp_log_kernel.h"

namespace certray::detail {

/// Whether the trig kernel applies to x (NaN: no).
inline bool trig_kernel_applies(double x) { return x >= -0x1p19 && x <= 0x1p19; }

/// The trig kernel's constants (docs/theory/trig_kernel.md; tests/interval/trig_kernel_test.cpp
/// checks them against MPFR).
struct TrigKernel {
    static constexpr double kMagic = ExpKernel::kMagic;  ///< 1.5·2⁵²: ⌈a⌉ in upward mode
    static constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;  ///< ≈ 2/π (any double near it)
    static constexpr double kP1 = 0x1.921fb544p+0;              ///< π/2 to 32 bits, below π/2
    static constexpr double kP2 = 0x1.0b4611a626331p-34;        ///< ≈ π/2 − P1
    static constexpr double kSlack = 0x1p-87;                   ///< ≥ |π/2 − P1 − P2|
    static constexpr double kPiLo = 0x1.921fb54442d18p+1;       ///< RD(π)
    static constexpr double kPiHi = 0x1.921fb54442d19p+1;       ///< RU(π)
    /// Bounds of (−1)ⁱ/(2i)!, i = 0 … 8, and [−1/18!, 0] for the remainder's w⁹.
    static constexpr double kCosLo[10] = {
        1.0,
        -0.5,
        0x1.5555555555555p-5,
        -0x1.6c16c16c16c17p-10,
        0x1.a01a01a01a01ap-16,
        -0x1.27e4fb7789f5dp-22,
        0x1.1eed8eff8d897p-29,
        -0x1.93974a8c07c9ep-37,
        0x1.ae7f3e733b81fp-45,
        -0x1.6827863b97d98p-53,
    };
    static constexpr double kCosHi[10] = {
        1.0,
        -0.5,
        0x1.5555555555556p-5,
        -0x1.6c16c16c16c16p-10,
        0x1.a01a01a01a01bp-16,
        -0x1.27e4fb7789f5cp-22,
        0x1.1eed8eff8d898p-29,
        -0x1.93974a8c07c9dp-37,
        0x1.ae7f3e733b820p-45,
        0.0,
    };
    /// Bounds of (−1)ⁱ/(2i + 1)!, i = 0 … 8, and [−1/19!, 0] for the remainder's w⁹.
    static constexpr double kSinLo[10] = {
        1.0,
        -0x1.5555555555556p-3,
        0x1.1111111111111p-7,
        -0x1.a01a01a01a01bp-13,
        0x1.71de3a556c733p-19,
        -0x1.ae64567f544e4p-26,
        0x1.6124613a86d09p-33,
        -0x1.ae7f3e733b820p-41,
        0x1.952c77030ad4ap-49,
        -0x1.2f49b46814158p-57,
    };
    static constexpr double kSinHi[10] = {
        1.0,
        -0x1.5555555555555p-3,
        0x1.1111111111112p-7,
        -0x1.a01a01a01a01ap-13,
        0x1.71de3a556c734p-19,
        -0x1.ae64567f544e3p-26,
        0x1.6124613a86d0ap-33,
        -0x1.ae7f3e733b81fp-41,
        0x1.952c77030ad4bp-49,
        0.0,
    };
};

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

/// Whether V selects lanes by a sign bit in one instruction (V::by_sign(a, b, m): b where m's sign
/// bit is set, a where it is not; AVX2's blendv).
template <class V>
concept SelectsBySign = requires(typename V::R r) {
    V::by_sign(r, r, r);
};

/// Whether side_coef's blend gives the bits of max(t·lo, t·hi) for each pair of a table: lo ≤ hi
/// and not both zero (where the max would take the sign of −hi's zero).
template <class T>
constexpr bool blend_gives_max(const T* lo, const T* hi, int n) {
    for (int i = 0; i < n; ++i) {
        if (!(lo[i] <= hi[i]) || (lo[i] == 0 && hi[i] == 0)) return false;
    }
    return true;
}
static_assert(blend_gives_max(TrigKernel::kCosLo, TrigKernel::kCosHi, 10));
static_assert(blend_gives_max(TrigKernel::kSinLo, TrigKernel::kSinHi, 10));

/// t·c for the bound of side t of a coefficient lo ≤ c ≤ hi (tm: t's sign bit): max(t·lo, t·hi),
/// that is hi where t = +1 and −lo where t = −1 (by V::by_sign where V has it: the same bits for
/// the tables blend_gives_max accepts).
template <class V, class T>
[[gnu::always_inline]] inline typename V::R side_coef(T lo, T hi, typename V::R tm) {
    if constexpr (SelectsBySign<V>) {
        return V::by_sign(V::set1(hi), V::set1(-lo), tm);
    } else {
        return V::max(V::flip(V::set1(lo), tm), V::flip(V::set1(hi), tm));
    }
}

/// flip(max(flip(a, m), flip(b, m)), m) for a ≤ b: a where m's sign bit is set, b where it is not
/// (a select by a sign without a mask). Not V::by_sign: for a = −0 and b = +0 this gives +0 on
/// both sides, the scalar walk's bits.
template <class V>
[[gnu::always_inline]] inline typename V::R pick(typename V::R a, typename V::R b,
                                                 typename V::R m) {
    return V::flip(V::max(V::flip(a, m), V::flip(b, m)), m);
}

/// t·P where P is the bound of side t of the polynomial Σ cᵢwⁱ (i < N) at w ≥ 0, the coefficients
/// bounded by lo[i] ≤ cᵢ ≤ hi[i]; tm holds t's sign bit, w ≥ 0 per lane.
template <class V, class T, int N>
[[gnu::always_inline]] inline typename V::R trig_horner(typename V::R w, typename V::R tm,
                                                        const T (&lo)[N], const T (&hi)[N]) {
    const auto coef = [&](int i) { return side_coef<V>(lo[i], hi[i], tm); };
    typename V::R acc = coef(N - 1);
    for (int i = N - 2; i >= 0; --i) acc = V::add(coef(i), V::mul(w, acc));  // t·(cᵢ + w·q), up
    return acc;
}

/// s·B per lane, B the bound of side s (−1.0: lower, +1.0: upper) of sin(x) (cosine = false) or
/// cos(x), for |x| ≤ 2¹⁹ (see the file contract; K = TrigKernelF32 in binary32 lanes: |x| ≤ 2⁹,
/// interval/trig_kernel_f32.h). V provides what exp_bound needs and max, le, eq, either and
/// select.
template <class V, class K = TrigKernel>
[[gnu::always_inline]] inline typename V::R trig_point(typename V::R x, typename V::R s,
                                                       bool cosine) {
    using R = typename V::R;
    const R mz = V::set1(-0.0);
    const R magic = V::set1(K::kMagic);
    const auto ceil = [&](R a) { return V::sub(V::add(a, magic), magic); };  // upward mode
    // k = ⌈2x/π − ½⌉; the quadrant of sin's argument, k (+ 1 for cos) mod 4, from its floor / 4.
    const R kd = ceil(V::sub(V::mul(x, V::set1(K::kTwoOverPi)), V::set1(0.5)));
    const R kq = cosine ? V::add(kd, V::set1(1.0)) : kd;
    const R quarter = V::flip(ceil(V::mul(V::flip(kq, mz), V::set1(0.25))), mz);  // ⌊kq/4⌋
    const R q = V::sub(kq, V::mul(quarter, V::set1(4.0)));                        // 0, 1, 2, 3
    const auto odd = V::either(V::eq(q, V::set1(1.0)), V::eq(q, V::set1(3.0)));   // h = cos
    // t = s·σ (σ = −1 for q ≥ 2): the side of h's bound.
    const R tm = V::flip(V::sign_of(s), V::select(V::le(V::set1(2.0), q), mz, V::set1(0.0)));
    const R ntm = V::flip(tm, mz);
    // r = x − k·P1 − k·P2 − k·ε bounded outward (k·P1 exact): r_hi and −r_lo, rounded up.
    const R a = V::mul(kd, V::set1(K::kP1));
    const R slack = V::mul(V::flip(kd, V::sign_of(kd)), V::set1(K::kSlack));
    const R r_hi = V::add(V::add(V::sub(x, a), V::mul(V::flip(kd, mz), V::set1(K::kP2))), slack);
    const R r_lo = V::flip(V::add(V::add(V::sub(a, x), V::mul(kd, V::set1(K::kP2))), slack), mz);
    // cos r, decreasing in r²: side t at the least r² rounded down (t = +1) or the greatest rounded
    // up (t = −1).
    const auto cos_r = [&] {
        const R most = V::max(V::flip(r_lo, mz), r_hi);
        const R least = V::max(V::set1(0.0), V::max(r_lo, V::flip(r_hi, mz)));
        const R w_hi = V::mul(most, most);
        const R w_lo = V::flip(V::mul(V::flip(least, mz), least), mz);
        return trig_horner<V>(pick<V>(w_lo, w_hi, ntm), tm, K::kCosLo, K::kCosHi);
    };
    // sin r, increasing: side t at r_hi (t = +1) or r_lo, = sign(r_t)·|r_t|·S(r_t²), so S's side is
    // t′ = t·sign(r_t): at r_t² rounded down (t′ = +1) or up.
    const auto sin_r = [&] {
        const R rt = pick<V>(r_lo, r_hi, tm);
        const R rsign = V::sign_of(rt);
        const R abs_rt = V::flip(rt, rsign);
        const R tpm = V::flip(tm, rsign);
        const R v_hi = V::mul(abs_rt, abs_rt);
        const R v_lo = V::flip(V::mul(V::flip(abs_rt, mz), abs_rt), mz);
        const R sin_s =
            trig_horner<V>(pick<V>(v_lo, v_hi, V::flip(tpm, mz)), tpm, K::kSinLo, K::kSinHi);
        return V::mul(sin_s, abs_rt);  // t′·S·|r_t| = t·sin-bound, rounded up
    };
    // Lanes of one parity (near points, the usual case) need one of the two polynomials; each
    // lane's value is the same either way.
    const unsigned h = V::bits(odd);
    if (h == (1u << V::kWidth) - 1) return cos_r();
    if (h == 0) return sin_r();
    return V::select(odd, cos_r(), sin_r());
}

/// [lo, hi] per lane ⊇ sin([l, u]) (sine) or cos([l, u]), for l ≤ u with trig_kernel_applies (see
/// the file contract; K's constants, as trig_point's). `points(x1, s1, x2, s2, r1, r2)` computes
/// r = trig_point<V, K>(x, s, !sine) at the two (x, s) pairs (the scalar caller packs them into
/// one vector).
template <class V, class K = TrigKernel, class Points>
[[gnu::always_inline]] inline void trig_interval(typename V::R l, typename V::R u, bool sine,
                                                 typename V::R& lo, typename V::R& hi,
                                                 Points points) {
    using R = typename V::R;
    const R mz = V::set1(-0.0), one = V::set1(1.0), minus_one = V::set1(-1.0);
    const R magic = V::set1(K::kMagic);
    const auto ceil = [&](R a) { return V::sub(V::add(a, magic), magic); };  // upward mode
    // Outward bounds of l/π and u/π (a quotient rounded down is −((−a)/b)), less ½ for sin: the
    // extrema kπ (+ π/2) inside [l, u] have k in [⌈qlo⌉, ⌊qhi⌋]; 1 for even k, −1 for odd k.
    const R zero = V::set1(0.0);
    const R pi_lo = V::set1(K::kPiLo), pi_hi = V::set1(K::kPiHi);
    R qlo = V::flip(V::div(V::flip(l, mz), V::select(V::le(zero, l), pi_hi, pi_lo)), mz);
    R qhi = V::div(u, V::select(V::le(zero, u), pi_lo, pi_hi));
    if (sine) {
        qlo = V::flip(V::sub(V::set1(0.5), qlo), mz);
        qhi = V::sub(qhi, V::set1(0.5));
    }
    const R k0 = ceil(qlo);
    const R k1 = V::flip(ceil(V::flip(qhi, mz)), mz);  // ⌊qhi⌋
    const R half = V::mul(k1, V::set1(0.5));
    const auto even = V::eq(ceil(half), half);  // k1 even
    const auto one_inside = V::eq(k0, k1);
    // Sides: monotone (k0 > k1), decreasing where k1 is even: l gives the upper bound, u the
    // lower; increasing: the reverse. An extremum inside: both sides −1 (a maximum, k even) or +1.
    const R s1 =
        V::select(one_inside, V::select(even, minus_one, one), V::select(even, one, minus_one));
    const R s2 = V::select(even, minus_one, one);
    R r1, r2;
    points(l, s1, u, s2, r1, r2);
    const R b1 = V::flip(r1, V::sign_of(s1)), b2 = V::flip(r2, V::sign_of(s2));
    const R least = V::min(b1, b2), most = V::max(b1, b2);
    lo = V::select(one_inside, V::select(even, least, minus_one), least);
    hi = V::select(one_inside, V::select(even, one, most), most);
    // Two extrema inside, or a whole period (the width rounded up): [−1, 1].
    const auto whole = V::either(V::lt(k0, k1), V::le(V::set1(2 * K::kPiLo), V::sub(u, l)));
    lo = V::max(minus_one, V::select(whole, minus_one, lo));
    hi = V::min(one, V::select(whole, one, hi));
}

#pragma GCC diagnostic pop

#if defined(__GNUC__) && defined(__x86_64__)
/// [lo, hi] in place: sin (sine) or cos over [lo, hi] (lo ≤ hi, both applying; upward mode held),
/// on SSE2 with the two points in one vector. The operands and results pass register barriers, so
/// that the computation stays inside the caller's rounding scope.
inline void trig_kernel_bounds(bool sine, double& lo, double& hi) {
    using V = KernelSse2;
    __m128d l = _mm_set1_pd(lo), u = _mm_set1_pd(hi);
    asm volatile("" : "+x"(l), "+x"(u));
    __m128d rlo, rhi;
    trig_interval<V>(l, u, sine, rlo, rhi,
                     [&](__m128d x1, __m128d s1, __m128d x2, __m128d s2, __m128d& r1, __m128d& r2) {
                         const __m128d r =
                             trig_point<V>(_mm_unpacklo_pd(x1, x2), _mm_unpacklo_pd(s1, s2), !sine);
                         r1 = _mm_unpacklo_pd(r, r);
                         r2 = _mm_unpackhi_pd(r, r);
                     });
    asm volatile("" : "+x"(rlo), "+x"(rhi));
    lo = _mm_cvtsd_f64(rlo);
    hi = _mm_cvtsd_f64(rhi);
}
#endif

}  // namespace certray::detail
