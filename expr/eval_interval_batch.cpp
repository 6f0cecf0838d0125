// expr/eval_interval_batch.cpp — the interval walk over IntervalLanes, vectorised per instruction
// set.
//
// Contract (expr/eval_interval_batch.h): lane i of every register is bit for bit what
// detail::run<UpInterval> computes for box i. How:
// - Const, VarX/Y/Z: the scalar walk's value, broadcast or copied.
// - Neg, Abs, Square, Sqrt, Add, Sub, Mul, Min, Max: interval.h's branch-free kernels, the same
//   IEEE operations in the same order on kWidth lanes at once (upward mode, the lower bound as
//   −((−a) ∘ b)); the scalar kernel's one test (lo ≤ hi for + −, no NaN product for ×, a non-empty
//   operand for the others) is evaluated per lane. Div and Recip (= [1, 1] / a): Boost's quotient
//   for a divisor without 0 (div_non_zero), its six sign cases as selects of the operands. Where
//   the scalar kernel returns empty() (the unary ops, min, max), the lane gets empty()'s NaN bounds
//   and no decoration; where it calls Boost's case table (+ − × at infinite bounds or on empty
//   operands), the lane calls the scalar operation itself, on the operands as they were before the
//   instruction wrote its register.
// - Exp, Log (x86): interval/exp_log_kernel.h's bounds on kWidth lanes at once, as the scalar exp()
//   and log() take them; lanes with a bound where the kernel does not apply call the scalar one.
//   Sin, Cos (x86): interval/trig_kernel.h's bounds likewise.
// - Pow (x86): Boost's pow_dn and pow_up chains (square and multiply) on the bases of its sign
//   cases, each lane's chain rounded down or up by exact sign flips (pow_kernel).
// - Exp, Log elsewhere: the scalar exp() and log() with their nearest2 batched: one write of
//   MXCSR to round-to-nearest for all lanes of the instruction, libm lane by lane, one write back
//   to upward, then the same widening (exp_below/exp_above, log_below/log_above); the lanes log
//   sends to Boost (a bound ≤ 0, empty) call the scalar log.
// - Every other op: the scalar UpInterval operation lane by lane (the calls of eval.h's switch).
// One template walk over a vector type V (expr/interval_batch_simd.h), compiled for SSE2, AVX2
// and AVX-512 (target attributes, flattened entry points as in expr/eval_batch.cpp) and chosen by
// batch_isa(). Decorations are bit masks, so a lane's decoration costs a bit of a mask register.
// The binary32 walk (IntervalLanesF) is the same template over binary32 vectors (IvSse2F, IvAvx2F,
// IvAvx512F): the kernels of + − × ÷ square √ neg abs min max 1/x xⁿ, their Boost lanes by the
// scalar operation rounded outward, exp and log by interval/exp_log_kernel_f32.h and sin and cos by
// interval/trig_kernel_f32.h (kernel_lanes_f32), every other op through the double walk
// (via_double), so its contract is inclusion, not equality.
// Reference: docs/theory/interval_batch.md; timings in docs/benchmarks.md, "Interval batch walk".
#include "expr/eval_interval_batch.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <type_traits>

#include "expr/eval_batch.h"
#include "expr/interval_batch_simd.h"

#ifndef CERTRAY_BATCH_X86  // an undefined name in #if would silently select the scalar walk
#error "expr/batch_simd.h must define CERTRAY_BATCH_X86"
#endif

namespace certray::expr {
namespace detail {
namespace {

using Lanes = IntervalLanes;
using LanesF = IntervalLanesF;
using certray::detail::IntervalArith;
using certray::detail::opaque;

// ---- the scalar operations, lane by lane --------------------------------------------------------

/// What run<UpInterval> writes for instruction `in` given its operands' values a and b (b unused
/// by unary ops): the calls of eval.h's switch, one by one.
[[gnu::noinline]] UpInterval scalar_op(const Instr& in, const UpInterval& a, const UpInterval& b) {
    using certray::abs, certray::square, certray::pow, certray::sqrt, certray::exp, certray::log,
        certray::sin, certray::cos, certray::min, certray::max, certray::floor, certray::ceil,
        certray::round, certray::tan, certray::asin, certray::acos, certray::atan, certray::atan2,
        certray::compare, certray::mod, certray::logic_and, certray::logic_or, certray::logic_not;
    switch (in.op) {
        case Op::Const:
            return UpInterval(in.imm);
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
            return a;  // never called so: the walk copies the inputs
        case Op::Neg:
            return -a;
        case Op::Abs:
            return abs(a);
        case Op::Square:
            return square(a);
        case Op::Sqrt:
            return sqrt(a);
        case Op::Exp:
            return exp(a);
        case Op::Log:
            return log(a);
        case Op::Sin:
            return sin(a);
        case Op::Cos:
            return cos(a);
        case Op::Pow:
            return pow(a, static_cast<unsigned>(in.b));
        case Op::Add:
            return a + b;
        case Op::Sub:
            return a - b;
        case Op::Mul:
            return a * b;
        case Op::Div:
            return a / b;
        case Op::Min:
            return min(a, b);
        case Op::Max:
            return max(a, b);
        case Op::Floor:
            return floor(a);
        case Op::Ceil:
            return ceil(a);
        case Op::Round:
            return round(a);
        case Op::Tan:
            return tan(a);
        case Op::Asin:
            return asin(a);
        case Op::Acos:
            return acos(a);
        case Op::Atan:
            return atan(a);
        case Op::Not:
            return logic_not(a);
        case Op::Recip:
            return UpInterval(1.0) / a;
        case Op::Atan2:
            return atan2(a, b);
        case Op::Compare:
            return compare(a, b);
        case Op::Mod:
            return mod(a, b);
        case Op::And:
            return logic_and(a, b);
        case Op::Or:
            return logic_or(a, b);
    }
    return UpInterval::empty();  // unreachable for valid codes
}

/// Instruction `in` on lanes 0 … n − 1 with the scalar operation. Each lane is read before it is
/// written, so the output may be an operand's register.
[[gnu::noinline]] void scalar_lanes(const Instr& in, Lanes* r, int n) {
    const Lanes& a = r[in.a];
    const Lanes& b = arity(in.op) == 2 ? r[in.b] : a;
    Lanes& o = r[in.out];
    for (int i = 0; i < n; ++i) set_lane(o, i, scalar_op(in, lane(a, i), lane(b, i)));
}

#if CERTRAY_BATCH_X86
/// The lanes k + j (j a bit of `slow`) of instruction `in` with the scalar operation, into lo[j]
/// and hi[j]; returns their decorations as bits j. The output register is not written.
[[gnu::noinline]] unsigned scalar_chunk(const Instr& in, const Lanes& a, const Lanes& b, int k,
                                        unsigned slow, double* lo, double* hi) {
    unsigned def = 0;
    for (; slow != 0; slow &= slow - 1) {
        const int j = __builtin_ctz(slow);
        const UpInterval v = scalar_op(in, lane(a, k + j), lane(b, k + j));
        lo[j] = v.lower();
        hi[j] = v.upper();
        def |= static_cast<unsigned>(v.defined) << j;
    }
    return def;
}

/// scalar_chunk on binary32 registers: the scalar operation on the lanes widened (exactly), its
/// bounds rounded outward to binary32.
[[gnu::noinline]] unsigned scalar_chunk(const Instr& in, const LanesF& a, const LanesF& b, int k,
                                        unsigned slow, float* lo, float* hi) {
    unsigned def = 0;
    for (; slow != 0; slow &= slow - 1) {
        const int j = __builtin_ctz(slow);
        const UpInterval v = scalar_op(in, lane(a, k + j), lane(b, k + j));
        lo[j] = lower_f32(v.lower());
        hi[j] = upper_f32(v.upper());
        def |= static_cast<unsigned>(v.defined) << j;
    }
    return def;
}
#endif

/// fa[k] = f(fa[k]) and fb[k] = f(fb[k]) for k < n, in round-to-nearest, returning to upward mode:
/// nearest2 of interval.h with one switch for all lanes (the caller's state is a RoundingScope's).
template <class F>
void nearest_lanes(F f, double* fa, double* fb, int n) {
#ifdef CERTRAY_X86_64_ROUNDING
    using certray::detail::X86RoundingControl;
    static constexpr unsigned kNearest = X86RoundingControl::canonical(0).mxcsr;
    static constexpr unsigned kUpward = X86RoundingControl::canonical(2).mxcsr;
    assert((X86RoundingControl::current().mxcsr & ~0x3fu) == kUpward);  // flags aside
    // The operands and results pass through `opaque` (volatile asms, kept in order with the two
    // ldmxcsr): no libm call can move out of the round-to-nearest stretch.
    asm volatile("ldmxcsr %0" : : "m"(kNearest) : "memory");
    for (int k = 0; k < n; ++k) {
        fa[k] = opaque(f(opaque(fa[k])));
        fb[k] = opaque(f(opaque(fb[k])));
    }
    asm volatile("ldmxcsr %0" : : "m"(kUpward) : "memory");
#else
    IntervalArith rnd;
    for (int k = 0; k < n; ++k) rnd.nearest2(f, fa[k], fb[k]);
#endif
}

/// The double whose bits are those of r plus k (k = ±2: two steps along the representation).
inline double bits_plus(double r, std::int64_t k) {
    return std::bit_cast<double>(std::bit_cast<std::uint64_t>(r) + static_cast<std::uint64_t>(k));
}

/// Lane k of exp (is_exp) or log of `a` with the scalar function's own widening: interval.h's
/// exp() and log() given fa = exp or log of the lower bound, fb of the upper, in round-to-nearest.
UpInterval exp_log_lane(bool is_exp, const Lanes& a, int k, double fa, double fb) {
    using Boost = UpInterval::Boost;
    const UpInterval x = lane(a, k);
    const double l = x.lower(), u = x.upper();
    if (is_exp) {
        if (x.is_empty()) return UpInterval::empty();
        return {Boost(IntervalArith::exp_below(l, fa), IntervalArith::exp_above(u, fb)), x.defined};
    }
    if (x.is_empty() || !(u > 0) || !(l > 0)) return log(x);  // Boost's log: [−inf, …] or empty
    return {Boost(IntervalArith::log_below(l, fa), IntervalArith::log_above(u, fb)), x.defined};
}

/// exp (is_exp) or log of lanes 0 … n − 1: interval.h's exp() and log() with the libm calls of
/// all lanes under one switch of the mode. The widening by kTranscUlps = 2 ulps is two steps of
/// the representation where the scalar functions' special cases cannot arise (exp: finite non-zero
/// bounds, results in [+0, +inf], where step_down(r, 2) is bits − 2 clamped at +0 and step_up(r, 2)
/// bits + 2 capped at +inf; log: finite bounds ≠ 1 with 0 < l, normal results, where the steps
/// never cross 0 or reach ±inf); every other lane takes exp_log_lane. The output may be the
/// operand's register.
[[gnu::noinline, maybe_unused]] void exp_log_lanes(bool is_exp, const Lanes& a, Lanes& o, int n) {
    static_assert(certray::detail::kTranscUlps == 2, "exp_log_lanes steps two ulps");
    constexpr double kInf = std::numeric_limits<double>::infinity();
    alignas(64) double fa[kIntervalLanes], fb[kIntervalLanes];
    std::copy(a.lo, a.lo + n, fa);
    std::copy(a.hi, a.hi + n, fb);
    nearest_lanes(is_exp ? IntervalArith::exp_rn : IntervalArith::log_rn, fa, fb, n);
    for (int w = 0; w * 64 < n; ++w) {
        const int begin = w * 64, end = std::min(n, begin + 64);
        std::uint64_t def = a.defined[w], slow = 0;  // read before o is written
        for (int k = begin; k < end; ++k) {
            const double l = a.lo[k], u = a.hi[k], ra = fa[k], rb = fb[k];
            double lo = 0, hi = 0;
            bool fast;
            if (is_exp) {
                fast = l <= u && l != 0 && u != 0 && l > -kInf && u < kInf && !std::signbit(ra) &&
                       !std::signbit(rb) && !std::isnan(ra) && !std::isnan(rb);
                lo = std::bit_cast<std::uint64_t>(ra) >= 2 ? bits_plus(ra, -2) : 0.0;
                hi = std::bit_cast<std::uint64_t>(rb) < std::bit_cast<std::uint64_t>(kInf) - 2
                         ? bits_plus(rb, 2)
                         : kInf;
            } else {
                const auto normal = [](double r) {
                    return std::fabs(r) >= std::numeric_limits<double>::min() &&
                           std::fabs(r) < 0x1p1000;
                };
                fast = 0 < l && l <= u && u < kInf && l != 1 && u != 1 && normal(ra) && normal(rb);
                lo = bits_plus(ra, ra > 0 ? -2 : 2);
                hi = bits_plus(rb, rb > 0 ? 2 : -2);
            }
            fast = fast && lo <= hi;  // Boost(lo, hi) is then [lo, hi]
            const std::uint64_t bit = std::uint64_t{1} << (k - begin);
            if (fast) {
                o.lo[k] = lo;
                o.hi[k] = hi;
            } else {
                slow |= bit;
            }
        }
        // The other lanes, whose operand is intact (o is written only where fast).
        std::uint64_t slow_def = 0;
        for (std::uint64_t m = slow; m != 0; m &= m - 1) {
            const int k = begin + __builtin_ctzll(m);
            const UpInterval v = exp_log_lane(is_exp, a, k, fa[k], fb[k]);
            o.lo[k] = v.lower();
            o.hi[k] = v.upper();
            slow_def |= std::uint64_t{v.defined} << (k - begin);
        }
        o.defined[w] = (def & ~slow) | slow_def;
    }
}

#if CERTRAY_BATCH_X86

// ---- the vector kernels -------------------------------------------------------------------------

/// One op on kWidth lanes: the bounds, the lanes computed here (`ok`; the others take the scalar
/// operation), and their decoration before the operands' is and-ed in.
template <class V>
struct Chunk {
    typename V::R lo, hi;
    unsigned ok, def;
};

/// interval.h's kernel for OP on lanes [alo, ahi] (and [blo, bhi] for binary ops), in upward mode.
template <class V, Op OP>
[[gnu::always_inline]] inline Chunk<V> kernel(typename V::R alo, typename V::R ahi,
                                              typename V::R blo, typename V::R bhi) {
    using R = typename V::R;
    constexpr unsigned kAll = (1u << V::kWidth) - 1;
    const R nan = V::set1(std::numeric_limits<double>::quiet_NaN());  // empty()'s bounds
    const R zero = V::set1(0.0);
    if constexpr (OP == Op::Add || OP == Op::Sub) {
        // [RD(alo + blo), RU(ahi + bhi)] / [RD(alo − bhi), RU(ahi − blo)]; Boost's if not lo ≤ hi.
        const R lo = OP == Op::Add ? V::neg(V::sub(V::neg(alo), blo)) : V::neg(V::sub(bhi, alo));
        const R hi = OP == Op::Add ? V::add(ahi, bhi) : V::sub(ahi, blo);
        return {lo, hi, V::bits(V::le(lo, hi)), kAll};
    } else if constexpr (OP == Op::Mul) {
        // mul_bounds' two-lane form, lane by lane: hi = max(max(al·blo, ah·blo), max(al·bhi,
        // ah·bhi)), −lo the same on −al, −ah; Boost's if a product al·b or ah·b is NaN.
        const R p1l = V::mul(alo, blo), p2l = V::mul(ahi, blo);
        const R p1h = V::mul(alo, bhi), p2h = V::mul(ahi, bhi);
        const R nal = V::neg(alo), nah = V::neg(ahi);
        const R n1l = V::mul(nal, blo), n2l = V::mul(nah, blo);
        const R n1h = V::mul(nal, bhi), n2h = V::mul(nah, bhi);
        const R hi = V::max(V::max(p1l, p2l), V::max(p1h, p2h));
        const R lo = V::neg(V::max(V::max(n1l, n2l), V::max(n1h, n2h)));
        return {lo, hi, V::bits(V::both(V::ord(p1l, p2l), V::ord(p1h, p2h))), kAll};
    } else if constexpr (OP == Op::Div || OP == Op::Recip) {
        // Boost's div_non_zero for 0 ∉ [c, d] (c > 0 or d < 0), its sign cases as selects:
        // lo = −(x / −y) and hi = x' / y' with x = d < 0 ? xu : xl, x' = d < 0 ? xl : xu,
        // y = xu < 0 ? c : xl < 0 ? (d < 0 ? d : c) : d, y' = xu < 0 ? d : xl < 0 ? (d < 0 ? d :
        // c) : c. Recip is [1, 1] / a. The scalar operation for empty operands, 0 ∈ [c, d], and
        // NaN quotients (∞ / ∞, which it repairs).
        R xl = alo, xu = ahi, c = blo, d = bhi;
        if constexpr (OP == Op::Recip) {
            xl = xu = V::set1(1.0);
            c = alo;
            d = ahi;
        }
        const typename V::M nxu = V::lt(xu, zero), nxl = V::lt(xl, zero), nd = V::lt(d, zero);
        const R mixed = V::select(nd, d, c);  // the denominator when xl < 0 ≤ xu
        const R lo_den = V::select(nxu, c, V::select(nxl, mixed, d));
        const R hi_den = V::select(nxu, d, V::select(nxl, mixed, c));
        const R lo = V::neg(V::div(V::select(nd, xu, xl), V::neg(lo_den)));
        const R hi = V::div(V::select(nd, xl, xu), hi_den);
        const typename V::M nonzero = V::either(V::lt(zero, c), nd);
        const typename V::M ok =
            V::both(V::both(V::le(xl, xu), V::le(c, d)), V::both(nonzero, V::le(lo, hi)));
        return {lo, hi, V::bits(ok), kAll};
    } else {
        // The rest return empty() for an empty operand (not lo ≤ hi), and are exact elsewhere.
        typename V::M e = V::le(alo, ahi);
        if constexpr (OP == Op::Min || OP == Op::Max) e = V::both(e, V::le(blo, bhi));
        if constexpr (OP == Op::Sqrt) e = V::both(e, V::le(zero, ahi));  // not u < 0
        R lo, hi;
        unsigned def = V::bits(e);
        if constexpr (OP == Op::Neg) {
            lo = V::neg(ahi);
            hi = V::neg(alo);
        } else if constexpr (OP == Op::Abs) {
            lo = V::max(V::max(alo, V::neg(ahi)), zero);
            hi = V::max(V::neg(alo), ahi);
        } else if constexpr (OP == Op::Square) {  // square_bounds
            const R m = V::max(V::max(alo, V::neg(ahi)), zero);
            const R big = V::max(V::neg(alo), ahi);
            lo = V::neg(V::mul(V::neg(m), m));
            hi = V::mul(big, big);
        } else if constexpr (OP == Op::Sqrt) {
            // [l > 0 ? sqrt_rd(l) : 0, RU(√u)], defined where l ≥ 0; sqrt_rd: RU(√l), or its
            // predecessor unless its square is l.
            const R s = V::sqrt(alo);
            const R rd = V::select(V::eq(V::mul(s, s), alo), s, V::prev(s));
            lo = V::select(V::lt(zero, alo), rd, zero);
            hi = V::sqrt(ahi);
            def &= V::bits(V::le(zero, alo));
        } else if constexpr (OP == Op::Min) {
            lo = V::min(alo, blo);
            hi = V::min(ahi, bhi);
        } else if constexpr (OP == Op::Max) {
            lo = V::max(alo, blo);
            hi = V::max(ahi, bhi);
        }
        return {V::select(e, lo, nan), V::select(e, hi, nan), kAll, def};
    }
}

/// pow(x, p) of interval.h (Boost's pow) on lanes [alo, ahi], in upward mode: x⁰ = [1, 1]; for
/// p ≥ 1 the chains of pow_dn and pow_up (square-and-multiply, x·x then y·x per bit of p, each
/// product RU(x·y) or RD(x·y) = −RU(x·(−y))) on the bases Boost's sign cases take:
///   odd p:  lo = a < 0 ? −up(−a) : dn(a),  hi = b < 0 ? −dn(−b) : up(b);
///   even p: b < 0: [dn(−b), up(−a)];  a < 0 ≤ b: [0, up(max(−a, b))];  else [dn(a), up(b)].
/// Each chain rounds down or up lane by lane by the sign flips of the operand and the product
/// (exact), so every lane sees the scalar's products in its order: the same bits. Empty operands
/// give empty(); a NaN bound (which Boost's pow does not make from a non-empty operand) leaves its
/// lane to the scalar operation.
template <class V>
[[gnu::always_inline]] inline Chunk<V> pow_kernel(typename V::R alo, typename V::R ahi,
                                                  unsigned p) {
    using R = typename V::R;
    const R nan = V::set1(std::numeric_limits<double>::quiet_NaN());
    const R zero = V::set1(0.0), one = V::set1(1.0), sign = V::set1(-0.0);
    const typename V::M e = V::le(alo, ahi);
    const unsigned def = V::bits(e);
    if (p == 0) return {V::select(e, one, nan), V::select(e, one, nan), (1u << V::kWidth) - 1, def};
    const typename V::M na = V::lt(alo, zero), nb = V::lt(ahi, zero);
    const bool odd = (p & 1) != 0;
    R base_lo, base_hi, flip_lo, flip_hi;  // flip: −0.0 where the chain rounds down, else +0.0
    if (odd) {
        base_lo = V::select(na, V::neg(alo), alo);
        base_hi = V::select(nb, V::neg(ahi), ahi);
        flip_lo = V::select(na, zero, sign);
        flip_hi = V::select(nb, sign, zero);
    } else {
        base_lo = V::select(nb, V::neg(ahi), alo);
        base_hi = V::select(nb, V::neg(alo), V::select(na, V::max(V::neg(alo), ahi), ahi));
        flip_lo = sign;
        flip_hi = zero;
    }
    const auto chain = [p, one](R x, R m) {
        const auto mul = [m](R u, R v) { return V::flip(V::mul(u, V::flip(v, m)), m); };
        R y = (p & 1) != 0 ? x : one;
        for (unsigned q = p >> 1; q > 0; q >>= 1) {
            x = mul(x, x);
            if ((q & 1) != 0) y = mul(x, y);
        }
        return y;
    };
    const R clo = chain(base_lo, flip_lo), chi = chain(base_hi, flip_hi);
    R lo, hi;
    if (odd) {
        lo = V::select(na, V::neg(clo), clo);
        hi = V::select(nb, V::neg(chi), chi);
    } else {
        lo = V::select(V::both(na, V::le(zero, ahi)), zero, clo);
        hi = chi;
    }
    const unsigned ok = V::bits(V::le(lo, hi)) | ~def;
    return {V::select(e, lo, nan), V::select(e, hi, nan), ok, def};
}

/// kernel<V, Op::Mul> where one operand is a point in every lane ([c, c], the same bits: a
/// constant's lanes), with the products that repeat taken once: over b = [c, c] the kernel's
/// al·bhi and ah·bhi are its al·blo and ah·blo, bit for bit, so its hi = max(m, m) = m with
/// m = max(al·blo, ah·blo), and its lo alike; over a = [c, c] its ah·blo and ah·bhi are al·blo
/// and al·bhi, so hi = max(al·blo, al·bhi). The same bits as the kernel (and the same lanes left
/// to the scalar operation), with four products and two maxima instead of eight and six.
template <class V>
[[gnu::always_inline]] inline Chunk<V> mul_by_point(typename V::R alo, typename V::R ahi,
                                                    typename V::R blo, typename V::R bhi,
                                                    bool b_point) {
    using R = typename V::R;
    constexpr unsigned kAll = (1u << V::kWidth) - 1;
    // The kernel's al·blo, and its ah·blo (b a point) or al·bhi (a a point), as it takes them.
    const R x = b_point ? ahi : alo, y = b_point ? blo : bhi;
    const R p1 = V::mul(alo, blo), p2 = V::mul(x, y);
    const R n1 = V::mul(V::neg(alo), blo), n2 = V::mul(V::neg(x), y);
    const R hi = V::max(p1, p2);
    const R lo = V::neg(V::max(n1, n2));
    return {lo, hi, V::bits(V::ord(p1, p2)), kAll};
}

/// The bound type of registers L: double (IntervalLanes) or float (IntervalLanesF).
template <class L>
using Bound = std::remove_cvref_t<decltype(L::lo[0])>;

/// Instruction `in` (op OP) on lanes 0 … n − 1 (rounded up to kWidth), kWidth lanes at a time;
/// each block of lanes is read before it is written, so the output may be an operand's register.
/// L: the registers, IntervalLanes (V of doubles) or IntervalLanesF (V of floats). K > 0: n lies in
/// ((K − 1)·kWidth, K·kWidth], the lanes of K vectors in one word of decorations, with `last` the
/// live lanes of the last one (the loops' bounds known when compiled: a walk of one vector, the
/// most frequent in the coherent renderer, costs about 0.8 of one with the bounds counted at run
/// time, docs/benchmarks.md, session 25); K = 0: any n.
template <class V, Op OP, int K, class L>
[[gnu::always_inline]] inline void vector_step(const Instr& in, L* r, int n, unsigned last) {
    constexpr int W = V::kWidth;
    constexpr unsigned kAll = (1u << W) - 1;
    static_assert(K * W <= 64, "K vectors in one word of decorations");
    const L& a = r[in.a];
    const L& b = arity(OP) == 2 ? r[in.b] : a;
    L& o = r[in.out];
    for (int w = 0; K > 0 ? w == 0 : w * 64 < n; ++w) {
        const int begin = w * 64, end = K > 0 ? K * W : std::min(n, begin + 64);
        const std::uint64_t operands = a.defined[w] & b.defined[w];  // read before o is written
        std::uint64_t def = 0, scalar_def = 0;
        for (int k = begin; k < end; k += W) {
            const typename V::R alo = V::load(a.lo + k), ahi = V::load(a.hi + k);
            const typename V::R blo = V::load(b.lo + k), bhi = V::load(b.hi + k);
            Chunk<V> c;
            if constexpr (OP == Op::Pow) {
                c = pow_kernel<V>(alo, ahi, in.b);
            } else if constexpr (OP == Op::Mul) {
                if (V::same(blo, bhi) == kAll) {
                    c = mul_by_point<V>(alo, ahi, blo, bhi, true);
                } else if (V::same(alo, ahi) == kAll) {
                    c = mul_by_point<V>(alo, ahi, blo, bhi, false);
                } else {
                    c = kernel<V, OP>(alo, ahi, blo, bhi);
                }
            } else {
                c = kernel<V, OP>(alo, ahi, blo, bhi);
            }
            const unsigned live = K > 0          ? (k + W == end ? last : kAll)
                                  : end - k >= W ? kAll
                                                 : (1u << (end - k)) - 1;
            if (const unsigned slow = ~c.ok & live; slow != 0) [[unlikely]] {
                alignas(64) Bound<L> lo[W], hi[W];
                V::store(lo, c.lo);
                V::store(hi, c.hi);
                scalar_def |= std::uint64_t{scalar_chunk(in, a, b, k, slow, lo, hi)} << (k - begin);
                c.lo = V::load(lo);
                c.hi = V::load(hi);
            }
            V::store(o.lo + k, c.lo);
            V::store(o.hi + k, c.hi);
            def |= std::uint64_t{c.def & c.ok} << (k - begin);
        }
        o.defined[w] = (def & operands) | scalar_def;
    }
}

/// Const: UpInterval(imm) in every lane (rounded outward in binary32 registers).
template <class V, class L>
[[gnu::always_inline]] inline void const_step(const Instr& in, L& o, int n) {
    const UpInterval c(in.imm);
    typename V::R lo, hi;
    if constexpr (std::is_same_v<L, LanesF>) {
        lo = V::set1(lower_f32(c.lower()));
        hi = V::set1(upper_f32(c.upper()));
    } else {
        lo = V::set1(c.lower());
        hi = V::set1(c.upper());
    }
    for (int k = 0; k < n; k += V::kWidth) {
        V::store(o.lo + k, lo);
        V::store(o.hi + k, hi);
    }
    for (int w = 0; w * 64 < n; ++w) o.defined[w] = c.defined ? ~std::uint64_t{0} : 0;
}

/// VarX, VarY, VarZ: the input's lanes.
template <class V, class L>
[[gnu::always_inline]] inline void copy_step(const L& x, L& o, int n) {
    for (int k = 0; k < n; k += V::kWidth) {
        V::store(o.lo + k, V::load(x.lo + k));
        V::store(o.hi + k, V::load(x.hi + k));
    }
    for (int w = 0; w * 64 < n; ++w) o.defined[w] = x.defined[w];
}

/// The output of exp_lanes, log_lanes and trig_lanes: lo[k], hi[k] (the kernel's bounds) where
/// both bounds of lane k of `a` take the kernel and lo ≤ hi, with a's decoration; the scalar
/// function `f` on the operand as it was elsewhere (the output may be the operand's register).
/// `applies(x)` gives the bits of the lanes of the vector x where the kernel applies (the scalar
/// *_kernel_applies, lane by lane). lo and hi are overwritten where f is taken.
template <class V, class Applies, class F>
[[gnu::always_inline]] inline void kernel_or_scalar(const Lanes& a, Lanes& o, int n, double* lo,
                                                    double* hi, Applies applies, F f) {
    constexpr int W = V::kWidth;
    constexpr unsigned kAll = (1u << W) - 1;
    for (int w = 0; w * 64 < n; ++w) {
        const int begin = w * 64, end = std::min(n, begin + 64);
        const std::uint64_t def = a.defined[w];  // read before o is written
        std::uint64_t slow = 0;
        for (int k = begin; k < end; k += W) {
            const typename V::R l = V::load(a.lo + k), u = V::load(a.hi + k);
            const unsigned live = end - k >= W ? kAll : (1u << (end - k)) - 1;
            const unsigned ok = V::bits(V::le(l, u)) & applies(l) & applies(u);
            slow |= std::uint64_t{~ok & live} << (k - begin);
        }
        std::uint64_t slow_def = 0;
        for (std::uint64_t m = slow; m != 0; m &= m - 1) {  // before o is written
            const int k = begin + __builtin_ctzll(m);
            const UpInterval v = f(lane(a, k));
            lo[k] = v.lower();
            hi[k] = v.upper();
            slow_def |= std::uint64_t{v.defined} << (k - begin);
        }
        for (int k = begin; k < end; k += W) {
            V::store(o.lo + k, V::load(lo + k));
            V::store(o.hi + k, V::load(hi + k));
        }
        o.defined[w] = (def & ~slow) | slow_def;
    }
}

/// exp of lanes 0 … n − 1, as interval.h's exp() computes it: the bounds of
/// interval/exp_log_kernel.h, V::kWidth lanes at a time, where both bounds of a lane take it
/// (finite, non-zero, within ±708, lo ≤ hi); exp() itself for the others (libm's bounds on the
/// bounds the kernel leaves; an empty operand), on the operand as it was (the output may be the
/// operand's register).
template <class V>
[[gnu::always_inline]] inline void exp_lanes(const Lanes& a, Lanes& o, int n) {
    using R = typename V::R;
    using K = certray::detail::ExpKernel;
    R lo_coef[17], hi_coef[17];
    for (int i = 0; i < 17; ++i) {
        lo_coef[i] = V::set1(K::kLo[i]);
        hi_coef[i] = V::set1(K::kHi[i]);
    }
    alignas(64) double lo[kIntervalLanes], hi[kIntervalLanes];
    for (int k = 0; k < n; k += V::kWidth) {
        const R below = certray::detail::exp_bound<V>(V::load(a.lo + k), V::set1(-1.0), lo_coef);
        V::store(lo + k, V::neg(below));
        V::store(hi + k, certray::detail::exp_bound<V>(V::load(a.hi + k), V::set1(1.0), hi_coef));
    }
    // As exp_kernel_applies: −708 ≤ x ≤ 708, x ≠ 0.
    const auto applies = [](typename V::R x) {
        return V::bits(V::le(V::set1(-708.0), x)) & V::bits(V::le(x, V::set1(708.0))) &
               ~V::bits(V::eq(x, V::set1(0.0)));
    };
    kernel_or_scalar<V>(a, o, n, lo, hi, applies, [](const UpInterval& x) { return exp(x); });
}

/// log of lanes 0 … n − 1, as interval.h's log() computes it: the kernel's bounds where both
/// bounds of a lane take it (normal, positive, finite, not 1, lo ≤ hi), log() itself for the
/// others, as exp_lanes.
template <class V>
[[gnu::always_inline]] inline void log_lanes(const Lanes& a, Lanes& o, int n) {
    alignas(64) double lo[kIntervalLanes], hi[kIntervalLanes];
    for (int k = 0; k < n; k += V::kWidth) {
        V::store(lo + k, V::neg(certray::detail::log_bound<V>(V::load(a.lo + k), V::set1(-1.0))));
        V::store(hi + k, certray::detail::log_bound<V>(V::load(a.hi + k), V::set1(1.0)));
    }
    // As log_kernel_applies: x normal, positive, finite, x ≠ 1.
    const auto applies = [](typename V::R x) {
        return V::bits(V::le(V::set1(0x1p-1022), x)) &
               V::bits(V::le(x, V::set1(0x1.fffffffffffffp+1023))) &
               ~V::bits(V::eq(x, V::set1(1.0)));
    };
    kernel_or_scalar<V>(a, o, n, lo, hi, applies, [](const UpInterval& x) { return log(x); });
}

/// sin (sine) or cos of lanes 0 … n − 1, as interval.h's sin() and cos() compute them: the bounds
/// of interval/trig_kernel.h, V::kWidth lanes at a time, where both bounds of a lane take it
/// (|x| ≤ 2¹⁹, lo ≤ hi); sin() or cos() itself for the others, as exp_lanes.
template <class V>
[[gnu::always_inline]] inline void trig_lanes(bool sine, const Lanes& a, Lanes& o, int n) {
    using R = typename V::R;
    alignas(64) double lo[kIntervalLanes], hi[kIntervalLanes];
    for (int k = 0; k < n; k += V::kWidth) {
        R l, h;
        certray::detail::trig_interval<V>(V::load(a.lo + k), V::load(a.hi + k), sine, l, h,
                                          [&](R x1, R s1, R x2, R s2, R& r1, R& r2) {
                                              r1 = certray::detail::trig_point<V>(x1, s1, !sine);
                                              r2 = certray::detail::trig_point<V>(x2, s2, !sine);
                                          });
        V::store(lo + k, l);
        V::store(hi + k, h);
    }
    // As trig_kernel_applies: |x| ≤ 2¹⁹.
    const auto applies = [](typename V::R x) {
        return V::bits(V::le(V::set1(-0x1p19), x)) & V::bits(V::le(x, V::set1(0x1p19)));
    };
    kernel_or_scalar<V>(a, o, n, lo, hi, applies,
                        [sine](const UpInterval& x) { return sine ? sin(x) : cos(x); });
}

using WalkFn = void (*)(const Instr*, const Instr*, const Lanes*, Lanes*, int);
WalkFn walk_for(BatchIsa isa) noexcept;

/// Instruction `in` on lanes 0 … n − 1 of binary32 registers by the double walk `walk`: the
/// operands widened into double registers (exactly), the instruction run there, its bounds rounded
/// outward to binary32 (upward mode held: RU(hi) and −RU(−lo)). The output may be an operand's
/// register.
[[gnu::noinline]] void via_double(const Instr& in, LanesF* r, int n, WalkFn walk) {
    static thread_local Lanes d[3];
    const int k = arity(in.op);
    const auto widen = [n](const LanesF& x, Lanes& y) {
        for (int i = 0; i < n; ++i) {
            y.lo[i] = x.lo[i];
            y.hi[i] = x.hi[i];
        }
        y.defined[0] = x.defined[0];
    };
    Instr one = in;
    if (k >= 1) {
        widen(r[in.a], d[0]);
        one.a = 0;
    }
    if (k == 2) {
        widen(r[in.b], d[1]);
        one.b = 1;
    }
    one.out = 2;
    walk(&one, &one + 1, d, d, n);
    LanesF& o = r[in.out];
    for (int i = 0; i < n; ++i) {
        o.lo[i] = -static_cast<float>(opaque(-d[2].lo[i]));
        o.hi[i] = static_cast<float>(opaque(d[2].hi[i]));
    }
    o.defined[0] = d[2].defined[0];
}

/// exp, log, sin or cos (`op`) of lanes 0 … n − 1 of binary32 registers: the binary32 kernels'
/// bounds (interval/exp_log_kernel_f32.h, interval/trig_kernel_f32.h) where both bounds of a lane
/// take it (exp: −87 ≤ lo ≤ hi ≤ 88; log: normal positive finite lo ≤ hi; sin, cos: −2⁹ ≤ lo ≤
/// hi ≤ 2⁹), with the operand's decoration (each is defined and continuous there); elsewhere the
/// scalar exp(), log(), sin() or cos() on the lane widened, rounded outward. Each block of lanes
/// is read before it is written (the output may be the operand's register).
template <class V>
[[gnu::always_inline]] inline void kernel_lanes_f32(Op op, const LanesF& a, LanesF& o, int n) {
    using R = typename V::R;
    using K = certray::detail::ExpKernelF32;
    using KL = certray::detail::LogKernelF32;
    using KT = certray::detail::TrigKernelF32;
    constexpr int W = V::kWidth;
    constexpr unsigned kAll = (1u << W) - 1;
    R lo_coef[std::size(K::kLo)], hi_coef[std::size(K::kHi)];
    if (op == Op::Exp) {
        for (std::size_t i = 0; i < std::size(K::kLo); ++i) {
            lo_coef[i] = V::set1(K::kLo[i]);
            hi_coef[i] = V::set1(K::kHi[i]);
        }
    }
    const R low = V::set1(op == Op::Exp ? K::kLower : op == Op::Log ? KL::kMinNormal : -KT::kBound);
    const R high = V::set1(op == Op::Exp ? K::kUpper : op == Op::Log ? KL::kMax : KT::kBound);
    const std::uint64_t def = a.defined[0];  // read before o is written
    std::uint64_t slow = 0, slow_def = 0;
    for (int k = 0; k < n; k += W) {
        const R l = V::load(a.lo + k), u = V::load(a.hi + k);
        const unsigned live = n - k >= W ? kAll : (1u << (n - k)) - 1;
        const unsigned ok = V::bits(V::both(V::le(l, u), V::both(V::le(low, l), V::le(u, high))));
        R lo, hi;
        if (op == Op::Exp) {
            lo = V::neg(certray::detail::exp_bound<V, K>(l, V::set1(-1.0), lo_coef));
            hi = certray::detail::exp_bound<V, K>(u, V::set1(1.0), hi_coef);
        } else if (op == Op::Log) {
            lo = V::neg(certray::detail::log_bound<V, KL>(l, V::set1(-1.0)));
            hi = certray::detail::log_bound<V, KL>(u, V::set1(1.0));
        } else {
            const bool sine = op == Op::Sin;
            certray::detail::trig_interval<V, KT>(
                l, u, sine, lo, hi, [&](R x1, R s1, R x2, R s2, R& r1, R& r2) {
                    r1 = certray::detail::trig_point<V, KT>(x1, s1, !sine);
                    r2 = certray::detail::trig_point<V, KT>(x2, s2, !sine);
                });
        }
        if (const unsigned s = ~ok & live; s != 0) [[unlikely]] {
            alignas(64) float bl[W], bh[W];
            V::store(bl, lo);
            V::store(bh, hi);
            for (unsigned m = s; m != 0; m &= m - 1) {
                const int j = __builtin_ctz(m);
                const UpInterval x = lane(a, k + j);
                const UpInterval v = op == Op::Exp   ? exp(x)
                                     : op == Op::Log ? log(x)
                                     : op == Op::Sin ? sin(x)
                                                     : cos(x);
                bl[j] = lower_f32(v.lower());
                bh[j] = upper_f32(v.upper());
                slow_def |= std::uint64_t{v.defined} << (k + j);
            }
            slow |= std::uint64_t{s} << k;
            lo = V::load(bl);
            hi = V::load(bh);
        }
        V::store(o.lo + k, lo);
        V::store(o.hi + k, hi);
    }
    o.defined[0] = (def & ~slow) | slow_def;
}

/// The walk over vectors of V on registers L: IntervalLanes (V of doubles) or IntervalLanesF (V
/// of floats; the ops without a vector kernel through via_double on the double walk `dwalk`), on
/// K vectors (vector_step; 0: any n).
template <class V, class L, int K>
inline void walk_k(const Instr* in, const Instr* const end, const L* p, L* r, int n, WalkFn dwalk) {
    static_assert(kIntervalLanes % V::kWidth == 0);
    static_assert(kIntervalLanes <= 64, "one word of decorations per register");
    constexpr bool kF32 = std::is_same_v<L, LanesF>;
    // The live lanes of the last vector (K > 0).
    const int rest = n - (K > 0 ? K - 1 : 0) * V::kWidth;
    const unsigned last = rest >= V::kWidth ? (1u << V::kWidth) - 1 : (1u << rest) - 1;
    for (; in != end; ++in) {
        switch (in->op) {
            case Op::Const:
                const_step<V, L>(*in, r[in->out], n);
                break;
            case Op::VarX:
            case Op::VarY:
            case Op::VarZ:
                copy_step<V, L>(p[static_cast<int>(in->op) - static_cast<int>(Op::VarX)],
                                r[in->out], n);
                break;
#define CERTRAY_VECTOR_CASE(OP)                     \
    case Op::OP:                                    \
        vector_step<V, Op::OP, K>(*in, r, n, last); \
        break;
                CERTRAY_VECTOR_CASE(Neg)
                CERTRAY_VECTOR_CASE(Abs)
                CERTRAY_VECTOR_CASE(Square)
                CERTRAY_VECTOR_CASE(Sqrt)
                CERTRAY_VECTOR_CASE(Add)
                CERTRAY_VECTOR_CASE(Sub)
                CERTRAY_VECTOR_CASE(Mul)
                CERTRAY_VECTOR_CASE(Div)
                CERTRAY_VECTOR_CASE(Recip)
                CERTRAY_VECTOR_CASE(Min)
                CERTRAY_VECTOR_CASE(Max)
                CERTRAY_VECTOR_CASE(Pow)
#undef CERTRAY_VECTOR_CASE
            case Op::Exp:
            case Op::Log:
            case Op::Sin:
            case Op::Cos:
                if constexpr (kF32) {
                    kernel_lanes_f32<V>(in->op, r[in->a], r[in->out], n);
                } else if (in->op == Op::Exp) {
                    exp_lanes<V>(r[in->a], r[in->out], n);
                } else if (in->op == Op::Log) {
                    log_lanes<V>(r[in->a], r[in->out], n);
                } else {
                    trig_lanes<V>(in->op == Op::Sin, r[in->a], r[in->out], n);
                }
                break;
            case Op::Floor:
            case Op::Ceil:
            case Op::Round:
            case Op::Tan:
            case Op::Asin:
            case Op::Acos:
            case Op::Atan:
            case Op::Not:
            case Op::Atan2:
            case Op::Compare:
            case Op::Mod:
            case Op::And:
            case Op::Or:
                if constexpr (kF32) {
                    via_double(*in, r, n, dwalk);
                } else {
                    scalar_lanes(*in, r, n);
                }
                break;
        }
    }
}

/// walk_k with the count of vectors known when compiled for one to four vectors (the walks of the
/// coherent renderer's nodes, forms, scans and points), else counted at run time.
template <class V, class L = Lanes>
inline void walk(const Instr* in, const Instr* const end, const L* p, L* r, int n,
                 WalkFn dwalk = nullptr) {
    constexpr int W = V::kWidth;
    static_assert(4 * W <= 64);
    switch ((n + W - 1) / W) {
        case 1:
            return walk_k<V, L, 1>(in, end, p, r, n, dwalk);
        case 2:
            return walk_k<V, L, 2>(in, end, p, r, n, dwalk);
        case 3:
            return walk_k<V, L, 3>(in, end, p, r, n, dwalk);
        case 4:
            return walk_k<V, L, 4>(in, end, p, r, n, dwalk);
        default:
            return walk_k<V, L, 0>(in, end, p, r, n, dwalk);
    }
}

[[gnu::flatten]] void walk_baseline(const Instr* in, const Instr* end, const Lanes* p, Lanes* r,
                                    int n) {
    walk<IvSse2>(in, end, p, r, n);
}
[[gnu::target("avx2"), gnu::flatten]] void walk_avx2(const Instr* in, const Instr* end,
                                                     const Lanes* p, Lanes* r, int n) {
    walk<IvAvx2>(in, end, p, r, n);
}
[[gnu::target("avx512f"), gnu::flatten]] void walk_avx512(const Instr* in, const Instr* end,
                                                          const Lanes* p, Lanes* r, int n) {
    walk<IvAvx512>(in, end, p, r, n);
}

WalkFn walk_for(BatchIsa isa) noexcept {
    switch (isa) {
        case BatchIsa::Baseline:
            return walk_baseline;
        case BatchIsa::Avx2:
            return walk_avx2;
        case BatchIsa::Avx512:
            return walk_avx512;
    }
    return walk_baseline;
}

// The binary32 walks: SSE2's four lanes, AVX2's eight, AVX-512's sixteen; the ops without a
// vector kernel through the double walk of the same instruction set.
using WalkFnF = void (*)(const Instr*, const Instr*, const LanesF*, LanesF*, int);

[[gnu::flatten]] void walk_f32_baseline(const Instr* in, const Instr* end, const LanesF* p,
                                        LanesF* r, int n) {
    walk<IvSse2F, LanesF>(in, end, p, r, n, walk_baseline);
}
[[gnu::target("avx2"), gnu::flatten]] void walk_f32_avx2(const Instr* in, const Instr* end,
                                                         const LanesF* p, LanesF* r, int n) {
    walk<IvAvx2F, LanesF>(in, end, p, r, n, walk_avx2);
}

[[gnu::target("avx512f"), gnu::flatten]] void walk_f32_avx512(const Instr* in, const Instr* end,
                                                              const LanesF* p, LanesF* r, int n) {
    walk<IvAvx512F, LanesF>(in, end, p, r, n, walk_avx512);
}

WalkFnF walk_f32_for(BatchIsa isa) noexcept {
    switch (isa) {
        case BatchIsa::Baseline:
            return walk_f32_baseline;
        case BatchIsa::Avx2:
            return walk_f32_avx2;
        case BatchIsa::Avx512:
            return walk_f32_avx512;
    }
    return walk_f32_baseline;
}

#else

/// Any other CPU: the inputs copied, exp and log batched, every other op lane by lane.
void walk_portable(const Instr* in, const Instr* const end, const Lanes* p, Lanes* r, int n) {
    for (; in != end; ++in) {
        if (in->op == Op::VarX || in->op == Op::VarY || in->op == Op::VarZ) {
            r[in->out] = p[static_cast<int>(in->op) - static_cast<int>(Op::VarX)];
        } else if (in->op == Op::Exp || in->op == Op::Log) {
            exp_log_lanes(in->op == Op::Exp, r[in->a], r[in->out], n);
        } else {
            scalar_lanes(*in, r, n);
        }
    }
}

/// Any other CPU, binary32 registers: every op lane by lane in double, rounded outward.
void walk_portable_f32(const Instr* in, const Instr* const end, const LanesF* p, LanesF* r, int n) {
    for (; in != end; ++in) {
        if (in->op == Op::VarX || in->op == Op::VarY || in->op == Op::VarZ) {
            r[in->out] = p[static_cast<int>(in->op) - static_cast<int>(Op::VarX)];
            continue;
        }
        const LanesF& a = r[in->a];
        const LanesF& b = arity(in->op) == 2 ? r[in->b] : a;
        LanesF& o = r[in->out];
        for (int i = 0; i < n; ++i) set_lane(o, i, scalar_op(*in, lane(a, i), lane(b, i)));
    }
}

#endif

}  // namespace
}  // namespace detail

void run_interval_batch(const Instr* begin, const Instr* end, const IntervalLanes* p,
                        IntervalLanes* r, int n) {
    assert(n >= 1 && n <= kIntervalLanes);
#if CERTRAY_BATCH_X86
    detail::walk_for(batch_isa())(begin, end, p, r, n);
#else
    detail::walk_portable(begin, end, p, r, n);
#endif
}

void run_interval_batch(const Instr* begin, const Instr* end, const IntervalLanesF* p,
                        IntervalLanesF* r, int n) {
    assert(n >= 1 && n <= kIntervalLanes);
#if CERTRAY_BATCH_X86
    detail::walk_f32_for(batch_isa())(begin, end, p, r, n);
#else
    detail::walk_portable_f32(begin, end, p, r, n);
#endif
}

}  // namespace certray::expr
