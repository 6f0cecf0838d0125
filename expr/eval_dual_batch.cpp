// expr/eval_dual_batch.cpp — Dual<double, 3> over lanes (expr/eval_dual_batch.h).
//
// Each op's lane loop is Dual's formula (interval/dual.h) written per lane: the arithmetic on
// GCC's generic vectors of 4 lanes (8 on AVX-512), up to the vector holding lane n − 1 (the same
// IEEE operation in each lane); libm's functions at each of the n lanes' values. The ops without a
// loop here run Dual's own operation lane by lane, through detail::run on a one-instruction list.
//
// The vector instantiation of number.h's binary_power (Op::Pow) may be left out of line (profile-
// guided builds leave it so): then it is compiled for the baseline instruction set, the same IEEE
// products (the same bits), and GCC's -Wpsabi note on its vector return is expected (caller and
// copy are in this translation unit and agree on it).
#pragma GCC diagnostic ignored "-Wpsabi"
#include "expr/eval_dual_batch.h"

#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "interval/dual.h"

namespace certray::expr {
namespace {

using D3 = Dual<double, 3>;
constexpr int L = kDualLanes;

/// Lane k of x as a Dual.
D3 get(const DualLanes& x, int k) { return D3(x.v[k], {x.g[0][k], x.g[1][k], x.g[2][k]}); }
void put(DualLanes& x, int k, const D3& d) {
    x.v[k] = d.a;
    for (int i = 0; i < 3; ++i) x.g[i][k] = d.v[static_cast<std::size_t>(i)];
}

/// Dual's own operation for `in` on lanes 0 … n − 1: run<D3> on the instruction alone.
[[gnu::noinline]] void scalar_lanes(const Instr& in, DualLanes* r, int n) {
    thread_local std::vector<Instr> one(1);
    one[0] = in;
    one[0].a = 0;
    if (arity(in.op) == 2) one[0].b = 1;  // Pow's b is its exponent
    one[0].out = 2;
    D3 regs[3];
    const std::array<D3, 3> unused{};
    for (int k = 0; k < n; ++k) {
        regs[0] = get(r[in.a], k);
        if (arity(in.op) == 2) regs[1] = get(r[in.b], k);
        detail::run<D3>(one, unused, regs);
        put(r[in.out], k, regs[2]);
    }
}

/// Four or eight lanes of doubles (GCC's generic vectors: IEEE operations lane by lane, two SSE2,
/// one AVX or one AVX-512 instruction each; may alias the doubles it is read from). DualLanes'
/// arrays are 64-byte aligned and kDualLanes is a multiple of 8.
using V4 = double __attribute__((vector_size(32), __may_alias__));
using V8 = double __attribute__((vector_size(64), __may_alias__));
static_assert(kDualLanes % 8 == 0);
template <class V>
V* vec(double* x) {
    return reinterpret_cast<V*>(x);
}
template <class V>
const V* vec(const double* x) {
    return reinterpret_cast<const V*>(x);
}

/// The chain rule's partials: o.g = d · a.g over the first nc vectors of lanes (d per lane).
template <class V>
[[gnu::always_inline]] inline void chain(const double* d, const DualLanes& a, DualLanes& o,
                                         int nc) {
    for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < nc; ++c) vec<V>(o.g[i])[c] = vec<V>(d)[c] * vec<V>(a.g[i])[c];
    }
}

/// The walk on vectors V of W lanes.
template <class V>
[[gnu::always_inline]] inline void walk(const Instr* in, const Instr* const end,
                                        const std::array<double, 3>* p, int n, DualLanes* r) {
    using certray::cos, certray::exp, certray::log, certray::sin, certray::sqrt;
    constexpr int W = static_cast<int>(sizeof(V) / sizeof(double));
    alignas(64) double d[L] = {};    // lanes from n on stay 0 where libm fills only n
    const int nc = (n + W - 1) / W;  // vectors of lanes; lanes from n on are computed, never read
    const int nc4 = nc * (W / 4);    // the same lanes in vectors of four
    for (; in != end; ++in) {
        DualLanes& o = r[in->out];
        const int k_ary = arity(in->op);
        const DualLanes& a = k_ary >= 1 ? r[in->a] : o;
        const DualLanes& b = k_ary == 2 ? r[in->b] : a;
        assert(k_ary == 0 || (&o != &a && &o != &b));
        switch (in->op) {
            case Op::Const:
                for (int k = 0; k < L; ++k) o.v[k] = in->imm;
                for (auto& g : o.g) {
                    for (int k = 0; k < L; ++k) g[k] = 0.0;
                }
                break;
            case Op::VarX:
            case Op::VarY:
            case Op::VarZ: {
                const int axis = static_cast<int>(in->op) - static_cast<int>(Op::VarX);
                for (int k = 0; k < L; ++k)
                    o.v[k] = k < n ? p[k][static_cast<std::size_t>(axis)] : 0.0;
                for (int i = 0; i < 3; ++i) {
                    for (int k = 0; k < L; ++k) o.g[i][k] = i == axis ? 1.0 : 0.0;
                }
                break;
            }
            case Op::Add:
            case Op::Sub: {
                const bool add = in->op == Op::Add;
                for (int i = 0; i < 4; ++i) {
                    const V* x = vec<V>(i == 0 ? a.v : a.g[i - 1]);
                    const V* y = vec<V>(i == 0 ? b.v : b.g[i - 1]);
                    V* z = vec<V>(i == 0 ? o.v : o.g[i - 1]);
                    for (int c = 0; c < nc; ++c) z[c] = add ? x[c] + y[c] : x[c] - y[c];
                }
                break;
            }
            case Op::Neg:
                for (int i = 0; i < 4; ++i) {
                    const V* x = vec<V>(i == 0 ? a.v : a.g[i - 1]);
                    V* z = vec<V>(i == 0 ? o.v : o.g[i - 1]);
                    for (int c = 0; c < nc; ++c) z[c] = -x[c];
                }
                break;
            case Op::Mul:  // (f·g)' = f'·g + f·g'
                for (int c = 0; c < nc; ++c) vec<V>(o.v)[c] = vec<V>(a.v)[c] * vec<V>(b.v)[c];
                for (int i = 0; i < 3; ++i) {
                    for (int c = 0; c < nc; ++c) {
                        vec<V>(o.g[i])[c] =
                            vec<V>(a.g[i])[c] * vec<V>(b.v)[c] + vec<V>(a.v)[c] * vec<V>(b.g[i])[c];
                    }
                }
                break;
            case Op::Div:  // (f/g)' = (f' − q·g')/g, q = f/g
                for (int c = 0; c < nc; ++c) vec<V>(o.v)[c] = vec<V>(a.v)[c] / vec<V>(b.v)[c];
                for (int i = 0; i < 3; ++i) {
                    for (int c = 0; c < nc; ++c) {
                        vec<V>(o.g[i])[c] =
                            (vec<V>(a.g[i])[c] - vec<V>(o.v)[c] * vec<V>(b.g[i])[c]) /
                            vec<V>(b.v)[c];
                    }
                }
                break;
            case Op::Pow: {  // chain(fⁿ, n·fⁿ⁻¹), f⁰ = 1 with zero partials; number.h's pow
                const unsigned e = in->b;
                if (e == 0) {
                    for (int c = 0; c < nc; ++c) vec<V>(o.v)[c] = V{} + 1.0;
                    for (int i = 0; i < 3; ++i) {
                        for (int c = 0; c < nc; ++c) vec<V>(o.g[i])[c] = V{};
                    }
                    break;
                }
                for (int c = 0; c < nc; ++c) {
                    const V x = vec<V>(a.v)[c];
                    vec<V>(d)[c] = static_cast<double>(e) * binary_power(x, e - 1);
                    vec<V>(o.v)[c] = binary_power(x, e);
                }
                chain<V>(d, a, o, nc);
                break;
            }
            case Op::Square:  // chain(f², 2·f)
                for (int c = 0; c < nc; ++c) {
                    vec<V>(o.v)[c] = vec<V>(a.v)[c] * vec<V>(a.v)[c];
                    vec<V>(d)[c] = 2.0 * vec<V>(a.v)[c];
                }
                chain<V>(d, a, o, nc);
                break;
            case Op::Sqrt:  // chain(√f, 0.5/√f) where f > 0, else NaN partials
                for (int k = 0; k < n; ++k) {
                    o.v[k] = sqrt(a.v[k]);
                    d[k] = a.v[k] > 0 ? 0.5 / o.v[k] : std::numeric_limits<double>::quiet_NaN();
                }
                chain<V>(d, a, o, nc);
                break;
            case Op::Exp:  // chain(eᶠ, eᶠ)
                for (int k = 0; k < n; ++k) o.v[k] = exp(a.v[k]);
                chain<V>(o.v, a, o, nc);
                break;
            case Op::Log:  // (log f)' = f'/f
                for (int k = 0; k < n; ++k) o.v[k] = log(a.v[k]);
                for (int i = 0; i < 3; ++i) {
                    for (int c = 0; c < nc; ++c)
                        vec<V>(o.g[i])[c] = vec<V>(a.g[i])[c] / vec<V>(a.v)[c];
                }
                break;
            case Op::Sin:  // chain(sin f, cos f)
                for (int k = 0; k < n; ++k) {
                    o.v[k] = sin(a.v[k]);
                    d[k] = cos(a.v[k]);
                }
                chain<V>(d, a, o, nc);
                break;
            case Op::Cos:  // chain(cos f, −sin f)
                for (int k = 0; k < n; ++k) {
                    o.v[k] = cos(a.v[k]);
                    d[k] = -sin(a.v[k]);
                }
                chain<V>(d, a, o, nc);
                break;
            case Op::Recip:  // Dual(1) / f: q = 1/f, (0 − q·f')/f
                for (int c = 0; c < nc; ++c) vec<V>(o.v)[c] = 1.0 / vec<V>(a.v)[c];
                for (int i = 0; i < 3; ++i) {
                    for (int c = 0; c < nc; ++c) {
                        vec<V>(o.g[i])[c] =
                            (0.0 - vec<V>(o.v)[c] * vec<V>(a.g[i])[c]) / vec<V>(a.v)[c];
                    }
                }
                break;
            // The selects in vectors of four lanes: on AVX-512F without AVX512DQ, GCC 12 takes a
            // comparison of eight lanes apart lane by lane (tracers/camera.cpp's row8_avx512).
            case Op::Min:  // certray::min's value; g's partials where g < f, else f's
            case Op::Max:  // certray::max's value; g's partials where f < g, else f's
                for (int c = 0; c < nc4; ++c) {
                    const V4 x = vec<V4>(a.v)[c], y = vec<V4>(b.v)[c];
                    const bool lower = in->op == Op::Min;
                    // (x < y or x NaN) ? x : y for min, (x > y or x NaN) ? x : y for max.
                    const auto keep_x = (lower ? x < y : x > y) | (x != x);
                    vec<V4>(o.v)[c] = keep_x ? x : y;
                    const auto take_y = lower ? y < x : x < y;
                    for (int i = 0; i < 3; ++i) {
                        vec<V4>(o.g[i])[c] = take_y ? vec<V4>(b.g[i])[c] : vec<V4>(a.g[i])[c];
                    }
                }
                break;
            case Op::Abs:  // |f|, −f' where f < 0, else f' (at 0: the right-hand branch)
                for (int c = 0; c < nc4; ++c) {
                    const V4 x = vec<V4>(a.v)[c];
                    const auto negative = x < 0.0;
                    // fabs: the sign bit cleared (−0 → +0).
                    using VI = decltype(negative);  // the lanes' bits as integers
                    vec<V4>(o.v)[c] =
                        reinterpret_cast<V4>(reinterpret_cast<VI>(x) & 0x7fffffffffffffffLL);
                    for (int i = 0; i < 3; ++i) {
                        vec<V4>(o.g[i])[c] = negative ? -vec<V4>(a.g[i])[c] : vec<V4>(a.g[i])[c];
                    }
                }
                break;
            default:
                scalar_lanes(*in, r, n);
                break;
        }
    }
}

void walk_baseline(const Instr* in, const Instr* end, const std::array<double, 3>* p, int n,
                   DualLanes* r) {
    walk<V4>(in, end, p, n, r);
}
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2"), gnu::flatten]] void walk_avx2(const Instr* in, const Instr* end,
                                                     const std::array<double, 3>* p, int n,
                                                     DualLanes* r) {
    walk<V4>(in, end, p, n, r);
}
[[gnu::target("avx512f"), gnu::flatten]] void walk_avx512(const Instr* in, const Instr* end,
                                                          const std::array<double, 3>* p, int n,
                                                          DualLanes* r) {
    walk<V8>(in, end, p, n, r);
}
#endif

}  // namespace

void run_dual_batch(const Instr* begin, const Instr* end, const std::array<double, 3>* p, int n,
                    DualLanes* r) {
    assert(n >= 1 && n <= kDualLanes);
#if defined(__x86_64__) && defined(__GNUC__)
    if (batch_isa() == BatchIsa::Avx512) return walk_avx512(begin, end, p, n, r);
    if (batch_isa() == BatchIsa::Avx2) return walk_avx2(begin, end, p, n, r);
#endif
    walk_baseline(begin, end, p, n, r);
}

}  // namespace certray::expr
