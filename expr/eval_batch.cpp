// expr/eval_batch.cpp — Evaluator<Batch>'s tape walk, vectorised for the CPU it runs on.
//
// Contract: run_batch applies each instruction to kBatch lanes with the IEEE double operation
// run<double> applies — one rounding per operation, in the tape's order, no FMA contraction and no
// reassociation — so lane i of the output register is bit for bit what the scalar double
// evaluator computes at lane i's point (NaN for NaN). min and max keep certray::min/max's rule
// (a < b or a is NaN) ? a : b, signed-zero ties included; exp, log, sin and cos call libm lane by
// lane; aⁿ repeats pow(double, unsigned)'s products. Registers other than the output may be left
// stale (a value whose only reader is the next instruction is never stored).
// Evaluator<Batch> runs a tape's *batch code* (compile_batch, cached per Tape::serial): a constant
// read by add, sub, mul, div, min or max becomes that instruction's immediate operand (the same
// IEEE operation on the same two values), a Const nothing else reads is dropped, and each op byte
// is rewritten as the walk's dispatch key — op, which operands are the previous result, and
// whether the result may stay unstored (by register liveness). Bare instruction lists (the
// quadtree's pruned SSA leaves) run as they are, their keys computed on the way.
// Two walks, each one template over a vector type V, compiled once per instruction set:
// - walk_plain (Baseline: SSE2, which every x86-64 CPU has): every result goes to memory;
// - walk_carry (Avx2: target "avx2"; Avx512: target "avx512f"): the previous instruction's result
//   stays in vector registers; an operand naming its register is taken from there, and the store
//   is skipped when the value dies at the next instruction. The stores and the dispatch dominate
//   the cost (docs/benchmarks.md), hence immediates and 128 lanes. AVX-512 carries all 128 lanes
//   (16 registers); AVX2 (16 registers in all) and the baseline walk the 128 lanes as two halves;
//   every copy also walks the first half alone, for lists that fill only that (8×8 tiles).
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

#include "expr/batch_code.h"
#include "expr/batch_simd.h"
#include "expr/eval.h"
#include "interval/batch.h"

namespace certray::expr {
namespace detail {
namespace {

static_assert(sizeof(Batch) == kBatch * sizeof(double), "Batch must be its lanes, contiguous");

// ---- the arithmetic of each code, shared by both walks --------------------------------------

/// True for the codes computed by arith(): everything but the leaves and the libm calls.
constexpr bool is_arith(unsigned c) {
    return c >= code(Op::Neg) && c < kCodeCount && !(c >= code(Op::Exp) && c <= code(Op::Cos)) &&
           !is_scalar(c);
}

/// Code C on one vector of lanes: x is operand a; y is operand b (binary ops) or the immediate
/// (kXxRI: a ∘ imm, kXxIR: imm ∘ a), unused by unary ops; n is Pow's exponent.
template <class V, unsigned C>
[[gnu::always_inline]] inline typename V::R arith(typename V::R x, typename V::R y, unsigned n) {
    static_assert(is_arith(C));
    if constexpr (C == code(Op::Neg)) return V::neg(x);
    if constexpr (C == code(Op::Abs)) return V::abs(x);
    if constexpr (C == code(Op::Square)) return V::square(x);
    if constexpr (C == code(Op::Sqrt)) return V::sqrt(x);
    if constexpr (C == code(Op::Pow)) return pow_lanes<V>(x, n);
    if constexpr (C == code(Op::Add) || C == kAddRI) return V::add(x, y);
    if constexpr (C == code(Op::Sub) || C == kSubRI) return V::sub(x, y);
    if constexpr (C == kSubIR) return V::sub(y, x);
    if constexpr (C == code(Op::Mul) || C == kMulRI) return V::mul(x, y);
    if constexpr (C == code(Op::Div) || C == kDivRI) return V::div(x, y);
    if constexpr (C == kDivIR) return V::div(y, x);
    if constexpr (C == code(Op::Min) || C == kMinRI) return V::min(x, y);
    if constexpr (C == kMinIR) return V::min(y, x);
    if constexpr (C == code(Op::Max) || C == kMaxRI) return V::max(x, y);
    if constexpr (C == kMaxIR) return V::max(y, x);
}

/// Whether code C reads operand b from a register (the binary ops; not their immediate forms).
template <unsigned C>
constexpr bool reads_b = code_reads(C) == 2;

/// The Op of a kScalar1/kScalar2 instruction: in `imm` in batch code (keyed), else its own.
inline Op scalar_op(const Instr& in, bool keyed) {
    return keyed ? static_cast<Op>(static_cast<unsigned>(in.imm)) : in.op;
}

// ---- the plain walk ---------------------------------------------------------------------------

/// One arithmetic instruction of walk_plain over N lanes: every operand from memory, the result
/// to memory.
template <class V, int N, int S, unsigned C>
[[gnu::always_inline]] inline void plain_step(const Instr& in, double* regs) {
    constexpr int W = V::kWidth;
    using R = typename V::R;
    double* const o = regs + std::size_t{in.out} * S;
    const double* const a = regs + std::size_t{in.a} * S;
    const double* const b = regs + std::size_t{in.b} * S;  // read by binary ops only
    const R imm = V::set1(in.imm);
    for (int k = 0; k < N; k += W) {
        R y = imm;  // the immediate, or unused (unary)
        if constexpr (reads_b<C>) y = V::load(b + k);
        V::store(o + k, arith<V, C>(V::load(a + k), y, in.b));
    }
}

/// Runs instructions [in, end) over N lanes. p[0..2]: the inputs (N doubles each); register k is
/// the N doubles at regs + k·S. Operands are read before the output is written, lane block by lane
/// block, so an output register may be an operand's (as the tape's allocator allows).
template <class V, int N, int S>
inline void walk_plain(const Instr* in, const Instr* const end, const double* const* p,
                       double* regs, bool keyed) {
    constexpr int W = V::kWidth;
    static_assert(N % W == 0 && N <= S);
    for (; in != end; ++in) {
        double* const o = regs + std::size_t{in->out} * S;
        const unsigned c = keyed ? code(in->op) / 8 : batch_code(in->op);  // the batch code
        switch (c) {
            case code(Op::Const): {
                const typename V::R imm = V::set1(in->imm);
                for (int k = 0; k < N; k += W) V::store(o + k, imm);
                break;
            }
            case code(Op::VarX):
            case code(Op::VarY):
            case code(Op::VarZ): {
                const double* const x = p[c - code(Op::VarX)];
                for (int k = 0; k < N; k += W) V::store(o + k, V::load(x + k));
                break;
            }
            case code(Op::Exp):
            case code(Op::Log):
            case code(Op::Sin):
            case code(Op::Cos):
                transcendental<N>(static_cast<Op>(c), regs + std::size_t{in->a} * S, o);
                break;
            case kScalar1:
            case kScalar2:
                scalar_lanes<N>(scalar_op(*in, keyed), regs + std::size_t{in->a} * S,
                                regs + std::size_t{in->b} * S, o);
                break;
#define CERTRAY_PLAIN_CASE(C)              \
    case C:                                \
        plain_step<V, N, S, C>(*in, regs); \
        break;
                CERTRAY_PLAIN_CASE(code(Op::Neg))
                CERTRAY_PLAIN_CASE(code(Op::Abs))
                CERTRAY_PLAIN_CASE(code(Op::Square))
                CERTRAY_PLAIN_CASE(code(Op::Sqrt))
                CERTRAY_PLAIN_CASE(code(Op::Pow))
                CERTRAY_PLAIN_CASE(code(Op::Add))
                CERTRAY_PLAIN_CASE(code(Op::Sub))
                CERTRAY_PLAIN_CASE(code(Op::Mul))
                CERTRAY_PLAIN_CASE(code(Op::Div))
                CERTRAY_PLAIN_CASE(code(Op::Min))
                CERTRAY_PLAIN_CASE(code(Op::Max))
                CERTRAY_PLAIN_CASE(kAddRI)
                CERTRAY_PLAIN_CASE(kSubRI)
                CERTRAY_PLAIN_CASE(kSubIR)
                CERTRAY_PLAIN_CASE(kMulRI)
                CERTRAY_PLAIN_CASE(kDivRI)
                CERTRAY_PLAIN_CASE(kDivIR)
                CERTRAY_PLAIN_CASE(kMinRI)
                CERTRAY_PLAIN_CASE(kMinIR)
                CERTRAY_PLAIN_CASE(kMaxRI)
                CERTRAY_PLAIN_CASE(kMaxIR)
#undef CERTRAY_PLAIN_CASE
            default:
                break;  // unreachable: every code is a case above
        }
    }
}

// ---- the carrying walk ------------------------------------------------------------------------

/// Bit o set when op o reads its first (kReadsA) or second (kReadsB) operand register.
constexpr std::uint32_t reads_mask(int operands) {
    std::uint32_t m = 0;
    for (unsigned o = 0; o < kCodeCount; ++o) {
        const int reads = code_reads(o);
        if (reads >= operands) m |= 1u << o;
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
                                              const double* const* p, double* regs, bool keyed) {
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
    } else if constexpr (OP == Op::Exp || OP == Op::Log || OP == Op::Sin || OP == Op::Cos) {
        // libm lane by lane, memory to memory; a carried operand is spilled first.
        alignas(64) double tmp[N];
        if constexpr (AA) each<B>([&](auto k) { V::store(tmp + k() * W, acc[k()]); });
        transcendental<N>(OP, AA ? tmp : a, o);
        each<B>([&](auto k) { acc[k()] = V::load(o + k() * W); });
        stored = true;
    } else if constexpr (is_scalar(code(OP))) {
        // OP is the code kScalar1/kScalar2 (not an Op): the scalar functions lane by lane, memory
        // to memory; a carried operand is spilled first.
        alignas(64) double tmp[N];
        if constexpr (AA || BA) each<B>([&](auto k) { V::store(tmp + k() * W, acc[k()]); });
        scalar_lanes<N>(scalar_op(in, keyed), AA ? tmp : a, BA ? tmp : b, o);
        each<B>([&](auto k) { acc[k()] = V::load(o + k() * W); });
        stored = true;
    } else {
        constexpr unsigned C = code(OP);
        const R imm = V::set1(in.imm);  // the immediate, or unused
        each<B>([&](auto k) {
            R y = imm;
            if constexpr (reads_b<C>) y = Bv(k);
            acc[k()] = arith<V, C>(A(k), y, in.b);
        });
    }
    if (!KEEP && !stored) each<B>([&](auto k) { V::store(o + k() * W, acc[k()]); });
}

/// walk_plain's results, keeping the previous result in N/kWidth vector registers (`acc`). Each
/// instruction is dispatched once on a key (op, a is carried, b is carried, result may stay
/// unstored), so every case is straight-line code. A result stays unstored only when the next
/// instruction reads its register and writes that same register: no later instruction can read
/// the value, and the next one takes it from acc. The last instruction (the output) is stored.
/// `keyed`: the list is batch code, whose op bytes are already the keys (compile_batch, which
/// also keeps results unstored by liveness: whenever the next instruction is their last reader).
template <class V, int N, int S>
inline void walk_carry(const Instr* in, const Instr* const end, const double* const* p,
                       double* regs, bool keyed) {
    constexpr int B = N / V::kWidth;
    static_assert(N % V::kWidth == 0 && N <= S);
    typename V::R acc[B] = {};
    std::uint32_t carried = ~0u;  // the register whose value acc holds (none yet)
    for (; in != end; ++in) {
        unsigned k = keyed ? code(in->op) : batch_code(in->op);
        if (!keyed) {
            const std::uint32_t out = in->out;
            unsigned keep = 0;
            if (in + 1 != end) {
                const Instr& next = in[1];
                const std::uint32_t m = 1u << batch_code(next.op);
                keep = next.out == out &&
                       (((m & kReadsA) && next.a == out) || ((m & kReadsB) && next.b == out));
            }
            const std::uint32_t m = 1u << k;
            k = key(k, (m & kReadsA) && in->a == carried, (m & kReadsB) && in->b == carried,
                    keep != 0);
            carried = out;
        }
        // Leaves never carry an operand, unary ops never a second one: their keys skip those.
        static_assert(kOpCount == 33, "walk_carry: give a new op its cases below");
        switch (k) {
#define CERTRAY_CARRY_CASE(OP, AA, BA, KEEP)                                 \
    case code(Op::OP) * 8 + AA * 4 + BA * 2 + KEEP:                          \
        carry_step<V, N, S, Op::OP, AA, BA, KEEP>(acc, *in, p, regs, keyed); \
        break;
#define CERTRAY_CARRY_IMM_CASE(C, AA, KEEP)                                                 \
    case C * 8 + AA * 4 + KEEP:                                                             \
        carry_step<V, N, S, static_cast<Op>(C), AA, false, KEEP>(acc, *in, p, regs, keyed); \
        break;
#define CERTRAY_CARRY_IMM(C)        \
    CERTRAY_CARRY_IMM_CASE(C, 0, 0) \
    CERTRAY_CARRY_IMM_CASE(C, 0, 1) CERTRAY_CARRY_IMM_CASE(C, 1, 0) CERTRAY_CARRY_IMM_CASE(C, 1, 1)
#define CERTRAY_CARRY_CODE_CASE(C, AA, BA, KEEP)                                         \
    case C * 8 + AA * 4 + BA * 2 + KEEP:                                                 \
        carry_step<V, N, S, static_cast<Op>(C), AA, BA, KEEP>(acc, *in, p, regs, keyed); \
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
            CERTRAY_CARRY_IMM(kAddRI)
            CERTRAY_CARRY_IMM(kSubRI)
            CERTRAY_CARRY_IMM(kSubIR)
            CERTRAY_CARRY_IMM(kMulRI)
            CERTRAY_CARRY_IMM(kDivRI)
            CERTRAY_CARRY_IMM(kDivIR)
            CERTRAY_CARRY_IMM(kMinRI)
            CERTRAY_CARRY_IMM(kMinIR)
            CERTRAY_CARRY_IMM(kMaxRI)
            CERTRAY_CARRY_IMM(kMaxIR)
            CERTRAY_CARRY_CODE_CASE(kScalar1, 0, 0, 0)
            CERTRAY_CARRY_CODE_CASE(kScalar1, 0, 0, 1)
            CERTRAY_CARRY_CODE_CASE(kScalar1, 1, 0, 0)
            CERTRAY_CARRY_CODE_CASE(kScalar1, 1, 0, 1)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 0, 0, 0)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 0, 0, 1)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 1, 0, 0)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 1, 0, 1)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 0, 1, 0)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 0, 1, 1)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 1, 1, 0)
            CERTRAY_CARRY_CODE_CASE(kScalar2, 1, 1, 1)
#undef CERTRAY_CARRY_CODE_CASE
#undef CERTRAY_CARRY_IMM
#undef CERTRAY_CARRY_IMM_CASE
#undef CERTRAY_CARRY_BINARY
#undef CERTRAY_CARRY_UNARY
#undef CERTRAY_CARRY_LEAF
#undef CERTRAY_CARRY_CASE
            default:
                break;  // unreachable: every op × flag combination is a case above
        }
    }
}

using WalkFn = void (*)(const Instr*, const Instr*, const double* const*, double*, bool);

/// The walks over N lanes of kBatch-lane registers.
template <int N>
struct Walks {
#if CERTRAY_BATCH_X86
    [[gnu::flatten]] static void baseline(const Instr* in, const Instr* end, const double* const* p,
                                          double* regs, bool keyed) {
        walk_plain<Sse2, N, kBatch>(in, end, p, regs, keyed);
    }
    [[gnu::target("avx2"), gnu::flatten]] static void avx2(const Instr* in, const Instr* end,
                                                           const double* const* p, double* regs,
                                                           bool keyed) {
        walk_carry<Avx2, N, kBatch>(in, end, p, regs, keyed);
    }
    [[gnu::target("avx512f"), gnu::flatten]] static void avx512(const Instr* in, const Instr* end,
                                                                const double* const* p,
                                                                double* regs, bool keyed) {
        walk_carry<Avx512, N, kBatch>(in, end, p, regs, keyed);
    }
#else
    static void baseline(const Instr* in, const Instr* end, const double* const* p, double* regs,
                         bool keyed) {
        walk_plain<Scalar, N, kBatch>(in, end, p, regs, keyed);
    }
#endif
};

using Half = Walks<kBatch / 2>;

/// All kBatch lanes as two walks over half of them (the second on the upper lanes): for the
/// copies whose carried result would not fit the vector registers at full width (AVX2 has 16,
/// and 64 lanes is its best width, docs/benchmarks.md) or that carry nothing (baseline). One
/// instantiation fewer to compile, too.
template <WalkFn H>
void twice(const Instr* in, const Instr* end, const double* const* p, double* regs, bool keyed) {
    H(in, end, p, regs, keyed);
    const double* const upper[3] = {p[0] + kBatch / 2, p[1] + kBatch / 2, p[2] + kBatch / 2};
    H(in, end, upper, regs + kBatch / 2, keyed);
}

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

/// The walk over N lanes (kBatch or kBatch / 2) of the copy `isa`.
/// The copy `isa` of the walk over all lanes, or over the first half of them.
WalkFn walk_for(BatchIsa isa, bool half) noexcept {
#if CERTRAY_BATCH_X86
    switch (isa) {
        case BatchIsa::Baseline:
            return half ? Half::baseline : twice<Half::baseline>;
        case BatchIsa::Avx2:
            return half ? Half::avx2 : twice<Half::avx2>;
        case BatchIsa::Avx512:
            return half ? Half::avx512 : Walks<kBatch>::avx512;
    }
#endif
    (void)isa;
    return half ? Half::baseline : twice<Half::baseline>;
}

}  // namespace

void run_batch(const Instr* begin, const Instr* end, const Batch* p, Batch* r, int lanes) {
    const double* const in[3] = {p[0].v.data(), p[1].v.data(), p[2].v.data()};
    const bool half = lanes >= 0 && lanes <= kBatch / 2;
    walk_for(batch_isa(), half)(begin, end, in, r[0].v.data(), false);
}

void run_batch(const BatchCode& code, const Batch* p, Batch* r) {
    const double* const in[3] = {p[0].v.data(), p[1].v.data(), p[2].v.data()};
    const Instr* const begin = code.instrs.data();
    walk_for(batch_isa(), false)(begin, begin + code.instrs.size(), in, r[0].v.data(), true);
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
