// expr/eval_batch.cpp — Evaluator<Batch>'s tape walk, vectorised for the CPU it runs on.
//
// Contract: run_batch(tape, p, r) applies each instruction to kBatch lanes with the IEEE double
// operation run<double> applies — one rounding per operation, in the tape's order, no FMA
// contraction and no reassociation — so lane i of r[tape.output()] is bit for bit what the scalar
// double evaluator computes at lane i's point (NaN for NaN). min and max keep certray::min/max's
// rule (a < b or a is NaN) ? a : b, signed-zero ties included; exp, log, sin and cos call libm
// lane by lane; aⁿ repeats pow(double, unsigned)'s products. Registers other than the output may
// be left stale (a value read only by the next instruction, which overwrites it, is never stored).
// Two walks, each one template over a vector type V, compiled once per instruction set:
// - walk_plain (Baseline: SSE2, which every x86-64 CPU has): every result goes to memory;
// - walk_carry (Avx2: target "avx2"; Avx512: target "avx512f"): the previous instruction's result
//   stays in vector registers; an operand naming its register is taken from there, and the store
//   is skipped when the next instruction reads the register and overwrites it (its value is then
//   dead: nothing later can read it). The stores dominate the cost (docs/benchmarks.md).
// The entry points are `flatten`, so V's target-specific operations inline into them; no copy is
// compiled with -march and -ffp-contract=off holds for every copy (objdump shows no vfmadd). The
// copy that runs is chosen at the first call from __builtin_cpu_supports (expr/eval_batch.h).
// Reference: interpreter design of libfive/Fidget; docs/benchmarks.md "Expression evaluation".
#include "expr/eval_batch.h"

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <utility>

#include "expr/eval.h"
#include "interval/batch.h"

#if defined(__x86_64__) && defined(__GNUC__)
#define CERTRAY_BATCH_X86 1
#include <immintrin.h>
#else
#define CERTRAY_BATCH_X86 0
#endif

// V's AVX types appear in the generic template before it is inlined into its AVX wrapper.
#pragma GCC diagnostic ignored "-Wpsabi"
// GCC 12 flags the deliberately undefined registers inside its own AVX-512 intrinsics.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace certray::expr {
namespace detail {
namespace {

static_assert(sizeof(Batch) == kBatch * sizeof(double), "Batch must be its lanes, contiguous");

// ---- one vector type per instruction set ----------------------------------------------------
// Each gives: R (a register of kWidth doubles), load/store (unaligned), set1, the IEEE arithmetic,
// neg (sign flip), abs (sign clear), and min/max with certray's rule. MINPD a, b is exactly
// (a < b) ? a : b (ties and a NaN in b give b), so only a NaN in a needs a blend.

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
    static R pow(R x, unsigned n) {             // pow(double, unsigned)'s products, lane by lane
        R r = set1(1.0);
        for (; n != 0; n >>= 1u) {
            if (n & 1u) r = mul(r, x);
            x = mul(x, x);
        }
        return r;
    }
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
    CERTRAY_AVX2 static R pow(R x, unsigned n) {  // pow(double, unsigned)'s products, lane by lane
        R r = set1(1.0);
        for (; n != 0; n >>= 1u) {
            if (n & 1u) r = mul(r, x);
            x = mul(x, x);
        }
        return r;
    }
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
    CERTRAY_AVX512 static R pow(R x,
                                unsigned n) {  // pow(double, unsigned)'s products, lane by lane
        R r = set1(1.0);
        for (; n != 0; n >>= 1u) {
            if (n & 1u) r = mul(r, x);
            x = mul(x, x);
        }
        return r;
    }
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
    static R pow(R x, unsigned n) {             // pow(double, unsigned)'s products, lane by lane
        R r = set1(1.0);
        for (; n != 0; n >>= 1u) {
            if (n & 1u) r = mul(r, x);
            x = mul(x, x);
        }
        return r;
    }
    static R sqrt(R a) { return std::sqrt(a); }
    static R neg(R a) { return -a; }
    static R abs(R a) { return std::abs(a); }
    static R min(R a, R b) { return certray::min(a, b); }
    static R max(R a, R b) { return certray::max(a, b); }
};
#endif

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

// ---- the plain walk ---------------------------------------------------------------------------

/// Runs instructions [in, end) over N lanes. p[0..2]: the inputs (N doubles each); register k is
/// the N doubles at regs + k·S. Operands are read before the output is written, lane block by lane
/// block, so an output register may be an operand's (as the tape's allocator allows).
template <class V, int N, int S>
inline void walk_plain(const Instr* in, const Instr* const end, const double* const* p,
                       double* regs) {
    constexpr int W = V::kWidth;
    static_assert(N % W == 0 && N <= S);
    for (; in != end; ++in) {
        double* const o = regs + std::size_t{in->out} * S;
        const double* const a = regs + std::size_t{in->a} * S;
        const double* const b = regs + std::size_t{in->b} * S;  // meaningful for binary ops only
        switch (in->op) {
            case Op::Const: {
                const typename V::R c = V::set1(in->imm);
                for (int k = 0; k < N; k += W) V::store(o + k, c);
                break;
            }
            case Op::VarX:
            case Op::VarY:
            case Op::VarZ: {
                const double* const x = p[static_cast<int>(in->op) - static_cast<int>(Op::VarX)];
                for (int k = 0; k < N; k += W) V::store(o + k, V::load(x + k));
                break;
            }
            case Op::Neg:
                for (int k = 0; k < N; k += W) V::store(o + k, V::neg(V::load(a + k)));
                break;
            case Op::Abs:
                for (int k = 0; k < N; k += W) V::store(o + k, V::abs(V::load(a + k)));
                break;
            case Op::Square:
                for (int k = 0; k < N; k += W) V::store(o + k, V::square(V::load(a + k)));
                break;
            case Op::Sqrt:
                for (int k = 0; k < N; k += W) V::store(o + k, V::sqrt(V::load(a + k)));
                break;
            case Op::Pow:
                for (int k = 0; k < N; k += W) V::store(o + k, V::pow(V::load(a + k), in->b));
                break;
            case Op::Exp:
            case Op::Log:
            case Op::Sin:
            case Op::Cos:
                transcendental<N>(in->op, a, o);
                break;
            case Op::Add:
                for (int k = 0; k < N; k += W)
                    V::store(o + k, V::add(V::load(a + k), V::load(b + k)));
                break;
            case Op::Sub:
                for (int k = 0; k < N; k += W)
                    V::store(o + k, V::sub(V::load(a + k), V::load(b + k)));
                break;
            case Op::Mul:
                for (int k = 0; k < N; k += W)
                    V::store(o + k, V::mul(V::load(a + k), V::load(b + k)));
                break;
            case Op::Div:
                for (int k = 0; k < N; k += W)
                    V::store(o + k, V::div(V::load(a + k), V::load(b + k)));
                break;
            case Op::Min:
                for (int k = 0; k < N; k += W)
                    V::store(o + k, V::min(V::load(a + k), V::load(b + k)));
                break;
            case Op::Max:
                for (int k = 0; k < N; k += W)
                    V::store(o + k, V::max(V::load(a + k), V::load(b + k)));
                break;
        }
    }
}

// ---- the carrying walk ------------------------------------------------------------------------

/// Bit o set when op o reads its first (kReadsA) or second (kReadsB) operand register.
constexpr std::uint32_t reads_mask(int operands) {
    std::uint32_t m = 0;
    for (int o = 0; o < kOpCount; ++o) {
        if (arity(static_cast<Op>(o)) >= operands) m |= 1u << o;
    }
    return m;
}
constexpr std::uint32_t kReadsA = reads_mask(1), kReadsB = reads_mask(2);

/// g(integral_constant<int, k>) for k = 0 … B−1, unrolled in the source: constant indices let the
/// compiler keep an array of B vector registers in registers.
template <int B, class G>
[[gnu::always_inline]] inline void each(G g) {
    [&]<int... K>(std::integer_sequence<int, K...>) { (g(std::integral_constant<int, K>{}), ...); }
    (std::make_integer_sequence<int, B>{});
}

/// One instruction of walk_carry, specialised on its op, on whether operand a (AA) or b (BA) is
/// the carried result `acc`, and on whether its own result may stay unstored (KEEP). Leaves acc
/// holding the result.
template <class V, int N, int S, Op OP, bool AA, bool BA, bool KEEP>
[[gnu::always_inline]] inline void carry_step(typename V::R (&acc)[N / V::kWidth], const Instr& in,
                                              const double* const* p, double* regs) {
    constexpr int W = V::kWidth, B = N / W;
    using R = typename V::R;
    double* const o = regs + std::size_t{in.out} * S;
    const double* const a = regs + std::size_t{in.a} * S;
    const double* const b = regs + std::size_t{in.b} * S;  // meaningful for binary ops only
    const auto A = [&](auto k) {
        if constexpr (AA)
            return acc[k()];
        else
            return V::load(a + k() * W);
    };
    const auto Bv = [&](auto k) {
        if constexpr (BA)
            return acc[k()];
        else
            return V::load(b + k() * W);
    };
    bool stored = false;
    if constexpr (OP == Op::Const) {
        const R c = V::set1(in.imm);
        each<B>([&](auto k) { acc[k()] = c; });
    } else if constexpr (OP == Op::VarX || OP == Op::VarY || OP == Op::VarZ) {
        const double* const x = p[static_cast<int>(OP) - static_cast<int>(Op::VarX)];
        each<B>([&](auto k) { acc[k()] = V::load(x + k() * W); });
    } else if constexpr (OP == Op::Neg) {
        each<B>([&](auto k) { acc[k()] = V::neg(A(k)); });
    } else if constexpr (OP == Op::Abs) {
        each<B>([&](auto k) { acc[k()] = V::abs(A(k)); });
    } else if constexpr (OP == Op::Square) {
        each<B>([&](auto k) { acc[k()] = V::square(A(k)); });
    } else if constexpr (OP == Op::Sqrt) {
        each<B>([&](auto k) { acc[k()] = V::sqrt(A(k)); });
    } else if constexpr (OP == Op::Pow) {
        each<B>([&](auto k) { acc[k()] = V::pow(A(k), in.b); });
    } else if constexpr (OP == Op::Exp || OP == Op::Log || OP == Op::Sin || OP == Op::Cos) {
        // libm lane by lane, memory to memory; a carried operand is spilled first.
        alignas(64) double tmp[N];
        if constexpr (AA) each<B>([&](auto k) { V::store(tmp + k() * W, acc[k()]); });
        transcendental<N>(OP, AA ? tmp : a, o);
        each<B>([&](auto k) { acc[k()] = V::load(o + k() * W); });
        stored = true;
    } else if constexpr (OP == Op::Add) {
        each<B>([&](auto k) { acc[k()] = V::add(A(k), Bv(k)); });
    } else if constexpr (OP == Op::Sub) {
        each<B>([&](auto k) { acc[k()] = V::sub(A(k), Bv(k)); });
    } else if constexpr (OP == Op::Mul) {
        each<B>([&](auto k) { acc[k()] = V::mul(A(k), Bv(k)); });
    } else if constexpr (OP == Op::Div) {
        each<B>([&](auto k) { acc[k()] = V::div(A(k), Bv(k)); });
    } else if constexpr (OP == Op::Min) {
        each<B>([&](auto k) { acc[k()] = V::min(A(k), Bv(k)); });
    } else {
        static_assert(OP == Op::Max);
        each<B>([&](auto k) { acc[k()] = V::max(A(k), Bv(k)); });
    }
    if (!KEEP && !stored) each<B>([&](auto k) { V::store(o + k() * W, acc[k()]); });
}

/// walk_plain's results, keeping the previous result in N/kWidth vector registers (`acc`). Each
/// instruction is dispatched once on a key (op, a is carried, b is carried, result may stay
/// unstored), so every case is straight-line code. A result stays unstored only when the next
/// instruction reads its register and writes that same register: no later instruction can read
/// the value, and the next one takes it from acc. The last instruction (the output) is stored.
template <class V, int N, int S>
inline void walk_carry(const Instr* in, const Instr* const end, const double* const* p,
                       double* regs) {
    constexpr int B = N / V::kWidth;
    static_assert(N % V::kWidth == 0 && N <= S);
    typename V::R acc[B] = {};
    std::uint32_t carried = ~0u;  // the register whose value acc holds (none yet)
    for (; in != end; ++in) {
        const std::uint32_t out = in->out;
        unsigned keep = 0;
        if (in + 1 != end) {
            const Instr& next = in[1];
            const std::uint32_t m = 1u << static_cast<unsigned>(next.op);
            keep = next.out == out &&
                   (((m & kReadsA) && next.a == out) || ((m & kReadsB) && next.b == out));
        }
        const std::uint32_t m = 1u << static_cast<unsigned>(in->op);
        const unsigned aa = (m & kReadsA) && in->a == carried;
        const unsigned ba = (m & kReadsB) && in->b == carried;
        // Leaves never carry an operand, unary ops never a second one: their keys skip those.
        static_assert(kOpCount == 19, "walk_carry: give a new op its cases below");
        switch (static_cast<unsigned>(in->op) * 8 + aa * 4 + ba * 2 + keep) {
#define CERTRAY_CARRY_CASE(OP, AA, BA, KEEP)                          \
    case static_cast<unsigned>(Op::OP) * 8 + AA * 4 + BA * 2 + KEEP:  \
        carry_step<V, N, S, Op::OP, AA, BA, KEEP>(acc, *in, p, regs); \
        break;
#define CERTRAY_CARRY_LEAF(OP) CERTRAY_CARRY_CASE(OP, 0, 0, 0) CERTRAY_CARRY_CASE(OP, 0, 0, 1)
#define CERTRAY_CARRY_UNARY(OP) \
    CERTRAY_CARRY_LEAF(OP) CERTRAY_CARRY_CASE(OP, 1, 0, 0) CERTRAY_CARRY_CASE(OP, 1, 0, 1)
#define CERTRAY_CARRY_BINARY(OP)    \
    CERTRAY_CARRY_UNARY(OP)         \
    CERTRAY_CARRY_CASE(OP, 0, 1, 0) \
    CERTRAY_CARRY_CASE(OP, 0, 1, 1) CERTRAY_CARRY_CASE(OP, 1, 1, 0) CERTRAY_CARRY_CASE(OP, 1, 1, 1)
            CERTRAY_CARRY_LEAF(Const)
            CERTRAY_CARRY_LEAF(VarX)
            CERTRAY_CARRY_LEAF(VarY)
            CERTRAY_CARRY_LEAF(VarZ)
            CERTRAY_CARRY_UNARY(Neg)
            CERTRAY_CARRY_UNARY(Abs)
            CERTRAY_CARRY_UNARY(Square)
            CERTRAY_CARRY_UNARY(Sqrt)
            CERTRAY_CARRY_UNARY(Exp)
            CERTRAY_CARRY_UNARY(Log)
            CERTRAY_CARRY_UNARY(Sin)
            CERTRAY_CARRY_UNARY(Cos)
            CERTRAY_CARRY_UNARY(Pow)
            CERTRAY_CARRY_BINARY(Add)
            CERTRAY_CARRY_BINARY(Sub)
            CERTRAY_CARRY_BINARY(Mul)
            CERTRAY_CARRY_BINARY(Div)
            CERTRAY_CARRY_BINARY(Min)
            CERTRAY_CARRY_BINARY(Max)
#undef CERTRAY_CARRY_BINARY
#undef CERTRAY_CARRY_UNARY
#undef CERTRAY_CARRY_LEAF
#undef CERTRAY_CARRY_CASE
            default:
                break;  // unreachable: every op × flag combination is a case above
        }
        carried = out;
    }
}

using WalkFn = void (*)(const Instr*, const Instr*, const double* const*, double*);

#if CERTRAY_BATCH_X86
[[gnu::flatten]] void walk_baseline(const Instr* in, const Instr* end, const double* const* p,
                                    double* regs) {
    walk_plain<Sse2, kBatch, kBatch>(in, end, p, regs);
}
[[gnu::target("avx2"), gnu::flatten]] void walk_avx2(const Instr* in, const Instr* end,
                                                     const double* const* p, double* regs) {
    walk_carry<Avx2, kBatch, kBatch>(in, end, p, regs);
}
[[gnu::target("avx512f"), gnu::flatten]] void walk_avx512(const Instr* in, const Instr* end,
                                                          const double* const* p, double* regs) {
    walk_carry<Avx512, kBatch, kBatch>(in, end, p, regs);
}
#else
void walk_baseline(const Instr* in, const Instr* end, const double* const* p, double* regs) {
    walk_plain<Scalar, kBatch, kBatch>(in, end, p, regs);
}
#endif

// ---- choosing the copy ------------------------------------------------------------------------

constexpr int kUnset = -1;
std::atomic<int> g_isa{kUnset};

BatchIsa best_supported() noexcept {
    if (const char* env = std::getenv("CERTRAY_BATCH_ISA")) {
        for (BatchIsa isa : {BatchIsa::Baseline, BatchIsa::Avx2, BatchIsa::Avx512}) {
            if (std::strcmp(env, batch_isa_name(isa)) == 0 && batch_isa_supported(isa)) return isa;
        }
    }
    // The widest copy: every copy gives the same bits, and on the development machine (AMD EPYC,
    // docs/benchmarks.md) AVX-512 is 1.2–1.9× faster than AVX2 per point.
    if (batch_isa_supported(BatchIsa::Avx512)) return BatchIsa::Avx512;
    if (batch_isa_supported(BatchIsa::Avx2)) return BatchIsa::Avx2;
    return BatchIsa::Baseline;
}

WalkFn walk_for(BatchIsa isa) noexcept {
#if CERTRAY_BATCH_X86
    switch (isa) {
        case BatchIsa::Baseline:
            return walk_baseline;
        case BatchIsa::Avx2:
            return walk_avx2;
        case BatchIsa::Avx512:
            return walk_avx512;
    }
#endif
    (void)isa;
    return walk_baseline;
}

}  // namespace

void run_batch(const Tape& tape, const Batch* p, Batch* r) {
    const std::vector<Instr>& code = tape.instrs();
    const double* const in[3] = {p[0].v.data(), p[1].v.data(), p[2].v.data()};
    walk_for(batch_isa())(code.data(), code.data() + code.size(), in, r[0].v.data());
}

}  // namespace detail

bool batch_isa_supported(BatchIsa isa) noexcept {
#if CERTRAY_BATCH_X86
    __builtin_cpu_init();  // in case the first evaluation runs before libgcc's constructor
    switch (isa) {
        case BatchIsa::Baseline:
            return true;
        case BatchIsa::Avx2:
            return __builtin_cpu_supports("avx2");
        case BatchIsa::Avx512:
            return __builtin_cpu_supports("avx512f");
    }
    return false;
#else
    return isa == BatchIsa::Baseline;
#endif
}

BatchIsa batch_isa() noexcept {
    int isa = detail::g_isa.load(std::memory_order_relaxed);
    if (isa == detail::kUnset) {
        // First use: choose, unless set_batch_isa got there first (then keep its choice).
        const int best = static_cast<int>(detail::best_supported());
        detail::g_isa.compare_exchange_strong(isa, best, std::memory_order_relaxed);
        isa = detail::g_isa.load(std::memory_order_relaxed);
    }
    return static_cast<BatchIsa>(isa);
}

bool set_batch_isa(BatchIsa isa) noexcept {
    if (!batch_isa_supported(isa)) return false;
    detail::g_isa.store(static_cast<int>(isa), std::memory_order_relaxed);
    return true;
}

const char* batch_isa_name(BatchIsa isa) noexcept {
    switch (isa) {
        case BatchIsa::Baseline:
            return "baseline";
        case BatchIsa::Avx2:
            return "avx2";
        case BatchIsa::Avx512:
            return "avx512";
    }
    return "?";
}

}  // namespace certray::expr
