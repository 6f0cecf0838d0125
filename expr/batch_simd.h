// expr/batch_simd.h — internal to the batch walks (eval_batch.cpp, and through
// expr/interval_batch_simd.h eval_interval_batch.cpp), the camera's rows of rays
// (tracers/camera.cpp, its √) and the coherent walk's normals (tracers/coherent_walk.cpp, their
// √ and ÷): one vector type per instruction set, and libm lane by lane.
//
// Contract: each type gives R (a register of kWidth doubles), load/store (unaligned), set1, the
// IEEE arithmetic, neg (sign flip), abs (sign clear), and min/max with certray's rule, each lane
// bit for bit the scalar double operation. MINPD a, b is exactly (a < b) ? a : b (ties and a NaN
// in b give b), so only a NaN in a needs a blend. The AVX types' functions carry target
// attributes: they inline only into functions compiled for that target (no -march anywhere).
#pragma once

#include <cmath>

#include "expr/op.h"
#include "interval/number.h"

// V's AVX types appear in generic templates before they are inlined into their AVX wrappers.
#pragma GCC diagnostic ignored "-Wpsabi"
// GCC 12 flags the deliberately undefined registers inside its own AVX-512 intrinsics.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

#if defined(__x86_64__) && defined(__GNUC__)
#define CERTRAY_BATCH_X86 1
#include <immintrin.h>
#else
#define CERTRAY_BATCH_X86 0
#endif

namespace certray::expr::detail {
// Internal linkage, as if written in each file that includes this header (the two walks): the
// AVX types' functions must never be shared with (or taken from) code built for another target.
namespace {

#if CERTRAY_BATCH_X86
struct Sse2 {
    using R = __m128d;
    static constexpr int kWidth = 2;
    static R load(const double* p) { return _mm_loadu_pd(p); }
    static void store(double* p, R x) { _mm_storeu_pd(p, x); }
    static R set1(double c) { return _mm_set1_pd(c); }
    static R add(R a, R b) { return _mm_add_pd(a, b); }
    static R sub(R a, R b) { return _mm_sub_pd(a, b); }
    static R mul(R a, R b) { return _mm_mul_pd(a, b); }
    static R div(R a, R b) { return _mm_div_pd(a, b); }
    static R square(R a) { return mul(a, a); }  // one rounding, like square(double)
    static R sqrt(R a) { return _mm_sqrt_pd(a); }
    static R neg(R a) { return _mm_xor_pd(a, _mm_set1_pd(-0.0)); }
    static R abs(R a) { return _mm_andnot_pd(_mm_set1_pd(-0.0), a); }
    static R keep_nan(R a, R t) {  // a where a is NaN, else t
        const R nan = _mm_cmpunord_pd(a, a);
        return _mm_or_pd(_mm_and_pd(nan, a), _mm_andnot_pd(nan, t));
    }
    static R min(R a, R b) { return keep_nan(a, _mm_min_pd(a, b)); }
    static R max(R a, R b) { return keep_nan(a, _mm_max_pd(a, b)); }
};

#define CERTRAY_AVX2 [[gnu::target("avx2")]]
struct Avx2 {
    using R = __m256d;
    static constexpr int kWidth = 4;
    CERTRAY_AVX2 static R load(const double* p) { return _mm256_loadu_pd(p); }
    CERTRAY_AVX2 static void store(double* p, R x) { _mm256_storeu_pd(p, x); }
    CERTRAY_AVX2 static R set1(double c) { return _mm256_set1_pd(c); }
    CERTRAY_AVX2 static R add(R a, R b) { return _mm256_add_pd(a, b); }
    CERTRAY_AVX2 static R sub(R a, R b) { return _mm256_sub_pd(a, b); }
    CERTRAY_AVX2 static R mul(R a, R b) { return _mm256_mul_pd(a, b); }
    CERTRAY_AVX2 static R div(R a, R b) { return _mm256_div_pd(a, b); }
    CERTRAY_AVX2 static R square(R a) { return mul(a, a); }  // one rounding, like square(double)
    CERTRAY_AVX2 static R sqrt(R a) { return _mm256_sqrt_pd(a); }
    CERTRAY_AVX2 static R neg(R a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
    CERTRAY_AVX2 static R abs(R a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
    CERTRAY_AVX2 static R keep_nan(R a, R t) {
        return _mm256_blendv_pd(t, a, _mm256_cmp_pd(a, a, _CMP_UNORD_Q));
    }
    CERTRAY_AVX2 static R min(R a, R b) { return keep_nan(a, _mm256_min_pd(a, b)); }
    CERTRAY_AVX2 static R max(R a, R b) { return keep_nan(a, _mm256_max_pd(a, b)); }
};
#undef CERTRAY_AVX2

#define CERTRAY_AVX512 [[gnu::target("avx512f")]]
struct Avx512 {
    using R = __m512d;
    static constexpr int kWidth = 8;
    CERTRAY_AVX512 static R load(const double* p) { return _mm512_loadu_pd(p); }
    CERTRAY_AVX512 static void store(double* p, R x) { _mm512_storeu_pd(p, x); }
    CERTRAY_AVX512 static R set1(double c) { return _mm512_set1_pd(c); }
    CERTRAY_AVX512 static R add(R a, R b) { return _mm512_add_pd(a, b); }
    CERTRAY_AVX512 static R sub(R a, R b) { return _mm512_sub_pd(a, b); }
    CERTRAY_AVX512 static R mul(R a, R b) { return _mm512_mul_pd(a, b); }
    CERTRAY_AVX512 static R div(R a, R b) { return _mm512_div_pd(a, b); }
    CERTRAY_AVX512 static R square(R a) { return mul(a, a); }  // one rounding, like square(double)
    CERTRAY_AVX512 static R sqrt(R a) { return _mm512_sqrt_pd(a); }
    CERTRAY_AVX512 static R sign_op(R a, bool flip) {  // AVX-512F has no FP xor/and: integer ones
        const __m512i s = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ull));
        const __m512i x = _mm512_castpd_si512(a);
        return _mm512_castsi512_pd(flip ? _mm512_xor_si512(x, s) : _mm512_andnot_si512(s, x));
    }
    CERTRAY_AVX512 static R neg(R a) { return sign_op(a, true); }
    CERTRAY_AVX512 static R abs(R a) { return sign_op(a, false); }
    CERTRAY_AVX512 static R keep_nan(R a, R t) {
        return _mm512_mask_blend_pd(_mm512_cmp_pd_mask(a, a, _CMP_UNORD_Q), t, a);
    }
    CERTRAY_AVX512 static R min(R a, R b) { return keep_nan(a, _mm512_min_pd(a, b)); }
    CERTRAY_AVX512 static R max(R a, R b) { return keep_nan(a, _mm512_max_pd(a, b)); }
};
#undef CERTRAY_AVX512
#else
/// Any other CPU: one double at a time, with the scalar evaluator's own functions.
struct Scalar {
    using R = double;
    static constexpr int kWidth = 1;
    static R load(const double* p) { return *p; }
    static void store(double* p, R x) { *p = x; }
    static R set1(double c) { return c; }
    static R add(R a, R b) { return a + b; }
    static R sub(R a, R b) { return a - b; }
    static R mul(R a, R b) { return a * b; }
    static R div(R a, R b) { return a / b; }
    static R square(R a) { return mul(a, a); }  // one rounding, like square(double)
    static R sqrt(R a) { return std::sqrt(a); }
    static R neg(R a) { return -a; }
    static R abs(R a) { return std::abs(a); }
    static R min(R a, R b) { return certray::min(a, b); }
    static R max(R a, R b) { return certray::max(a, b); }
};
#endif

/// xⁿ lane by lane with pow(double, unsigned)'s products, in its order (square and multiply).
/// Generic: it runs on V's target only inlined into a walk compiled for it (flatten).
template <class V>
inline typename V::R pow_lanes(typename V::R x, unsigned n) {
    typename V::R r = V::set1(1.0);
    for (; n != 0; n >>= 1u) {
        if (n & 1u) r = V::mul(r, x);
        x = V::mul(x, x);
    }
    return r;
}

/// o[k] = f(a[k]) for k < N with libm's exp, log, sin or cos (op), the scalar evaluator's own
/// functions; in place (o == a) is fine.
template <int N>
inline void transcendental(Op op, const double* a, double* o) {
    switch (op) {
        case Op::Exp:
            for (int k = 0; k < N; ++k) o[k] = std::exp(a[k]);
            break;
        case Op::Log:
            for (int k = 0; k < N; ++k) o[k] = std::log(a[k]);
            break;
        case Op::Sin:
            for (int k = 0; k < N; ++k) o[k] = std::sin(a[k]);
            break;
        case Op::Cos:
            for (int k = 0; k < N; ++k) o[k] = std::cos(a[k]);
            break;
        default:
            break;  // not a transcendental: never called so
    }
}

/// o[k] = op(a[k], b[k]) for k < N for the ops without a batch code of their own (Floor … Or),
/// with the scalar double functions run<double> calls (b unused by unary ops); in place is fine.
template <int N>
inline void scalar_lanes(Op op, const double* a, const double* b, double* o) {
    switch (op) {
#define CERTRAY_SCALAR1(OP, F)                      \
    case Op::OP:                                    \
        for (int k = 0; k < N; ++k) o[k] = F(a[k]); \
        break;
#define CERTRAY_SCALAR2(OP, F)                            \
    case Op::OP:                                          \
        for (int k = 0; k < N; ++k) o[k] = F(a[k], b[k]); \
        break;
        CERTRAY_SCALAR1(Floor, certray::floor)
        CERTRAY_SCALAR1(Ceil, certray::ceil)
        CERTRAY_SCALAR1(Round, certray::round)
        CERTRAY_SCALAR1(Tan, certray::tan)
        CERTRAY_SCALAR1(Asin, certray::asin)
        CERTRAY_SCALAR1(Acos, certray::acos)
        CERTRAY_SCALAR1(Atan, certray::atan)
        CERTRAY_SCALAR1(Not, certray::logic_not)
        CERTRAY_SCALAR2(Atan2, certray::atan2)
        CERTRAY_SCALAR2(Compare, certray::compare)
        CERTRAY_SCALAR2(Mod, certray::mod)
        CERTRAY_SCALAR2(And, certray::logic_and)
        CERTRAY_SCALAR2(Or, certray::logic_or)
#undef CERTRAY_SCALAR1
#undef CERTRAY_SCALAR2
        case Op::Recip:
            for (int k = 0; k < N; ++k) o[k] = 1.0 / a[k];
            break;
        default:
            break;  // an op with a batch code of its own: never called so
    }
}

}  // namespace
}  // namespace certray::expr::detail
