// tests/expr/batch_isa_test.cpp — every copy of Evaluator<Batch>'s walk (expr/eval_batch.h:
// baseline SSE2, AVX2, AVX-512) against the scalar double evaluator, lane by lane, bit for bit.
//
// Each test runs once per copy this CPU supports (set_batch_isa), so the default path and the
// AVX paths are all checked in one run. The carrying walk (AVX2, AVX-512) keeps the previous
// result in registers and skips stores of values that die at the next instruction: the cases
// below put a result in the first, the second and both operand slots of the next instruction,
// with and without a later reader, after every op.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "interval/batch.h"
// eval.h before builder.h: builder.h's expr::min & co. would hide certray::min(double, double).
#include "expr/builder.h"
#include "expr/graph.h"
#include "expr/prune.h"
#include "expr/tape.h"
#include "tests/support/batch_isa.h"
#include "tests/support/generators.h"
#include "tests/support/random_dag.h"

namespace certray::expr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Same bits, or both NaN (the payload of a NaN is not part of the contract).
bool same(double a, double b) {
    return (std::isnan(a) && std::isnan(b)) ||
           std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

using testing::batch_isas;
using IsaGuard = testing::BatchIsaGuard;

/// The lanes of `tape` at p under every copy, each against eval<double> at that lane. Returns
/// a description of the first mismatch, or "" when all lanes of all copies agree.
std::string mismatch(const Tape& tape, const std::array<Batch, 3>& p) {
    IsaGuard guard;
    Evaluator<double> ed;
    std::array<double, kBatch> want{};
    for (int i = 0; i < kBatch; ++i) want[i] = ed(tape, {p[0][i], p[1][i], p[2][i]});
    for (BatchIsa isa : batch_isas()) {
        set_batch_isa(isa);
        Evaluator<Batch> eb;
        const Batch r = eb(tape, p);
        for (int i = 0; i < kBatch; ++i) {
            if (!same(r[i], want[i])) {
                return std::string(batch_isa_name(isa)) + " lane " + std::to_string(i) + " at (" +
                       std::to_string(p[0][i]) + ", " + std::to_string(p[1][i]) + ", " +
                       std::to_string(p[2][i]) + "): batch " + std::to_string(r[i]) + ", double " +
                       std::to_string(want[i]);
            }
        }
    }
    return "";
}

/// Special values: signed zeros, infinities, NaN, subnormals, the ends of the normal range.
const std::vector<double>& specials() {
    static const std::vector<double> v = {0.0,     -0.0,   kInf,    -kInf,    kNaN,    5e-324,
                                          -5e-324, 1e-310, DBL_MIN, -DBL_MIN, DBL_MAX, -DBL_MAX,
                                          1.0,     -1.0,   0.5,     -2.5,     3.0,     1e300};
    return v;
}

/// Batches covering every (x, y) pair of specials(), z cycling through them too.
std::vector<std::array<Batch, 3>> special_pairs() {
    const std::vector<double>& s = specials();
    std::vector<std::array<Batch, 3>> out;
    std::array<Batch, 3> p;
    int lane = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        for (std::size_t j = 0; j < s.size(); ++j) {
            p[0][lane] = s[i];
            p[1][lane] = s[j];
            p[2][lane] = s[(i + 2 * j) % s.size()];
            if (++lane == kBatch) {
                out.push_back(p);
                lane = 0;
            }
        }
    }
    if (lane > 0) out.push_back(p);  // the tail repeats lanes of the previous batch
    return out;
}

TEST(BatchIsa, ControlsTheCopy) {
    IsaGuard guard;
    EXPECT_TRUE(batch_isa_supported(BatchIsa::Baseline));
    for (BatchIsa isa : batch_isas()) {
        EXPECT_TRUE(set_batch_isa(isa));
        EXPECT_EQ(batch_isa(), isa);
    }
    EXPECT_STREQ(batch_isa_name(BatchIsa::Avx2), "avx2");
}

using Unary = Expr (*)(Expr);
using Binary = Expr (*)(Expr, Expr);

std::vector<std::pair<const char*, Unary>> unaries() {
    return {
        {"neg", [](Expr a) { return -a; }},           {"abs", [](Expr a) { return abs(a); }},
        {"square", [](Expr a) { return square(a); }}, {"sqrt", [](Expr a) { return sqrt(a); }},
        {"exp", [](Expr a) { return exp(a); }},       {"log", [](Expr a) { return log(a); }},
        {"sin", [](Expr a) { return sin(a); }},       {"cos", [](Expr a) { return cos(a); }},
        {"pow0", [](Expr a) { return pow(a, 0); }},   {"pow3", [](Expr a) { return pow(a, 3); }},
        {"pow6", [](Expr a) { return pow(a, 6); }}};
}

std::vector<std::pair<const char*, Binary>> binaries() {
    return {{"add", [](Expr a, Expr b) { return a + b; }},
            {"sub", [](Expr a, Expr b) { return a - b; }},
            {"mul", [](Expr a, Expr b) { return a * b; }},
            {"div", [](Expr a, Expr b) { return a / b; }},
            {"min", [](Expr a, Expr b) { return min(a, b); }},
            {"max", [](Expr a, Expr b) { return max(a, b); }}};
}

/// Every unary op u and binary op b on every pair of special values, with u's result carried into
/// b's first slot, its second slot, both slots, and (a later reader) stored as well; and b after
/// a constant in either slot.
TEST(BatchIsa, EveryOpOnSpecialValuesInEveryCarrySlot) {
    const auto points = special_pairs();
    for (const auto& [uname, u] : unaries()) {
        for (const auto& [bname, b] : binaries()) {
            for (int shape = 0; shape < 6; ++shape) {
                Graph g;
                auto [x, y, z] = vars(g);
                const Expr ux = u(x);
                Expr f;
                switch (shape) {
                    case 0:
                        f = b(ux, y);
                        break;  // u(x) in slot a
                    case 1:
                        f = b(y, ux);
                        break;  // u(x) in slot b
                    case 2:
                        f = b(ux, ux);
                        break;  // both slots
                    case 3:
                        f = b(b(ux, y), ux);
                        break;  // read again later: stored
                    case 4:
                        f = b(u(b(x, constant(g, 0.75))), z);
                        break;  // constant in slot b
                    default:
                        f = u(b(b(constant(g, -1.5), y), b(z, x)));
                        break;  // constant, slot a
                }
                g.set_output(f.id);
                const Tape t(g);
                for (const auto& p : points) {
                    const std::string m = mismatch(t, p);
                    ASSERT_EQ(m, "") << uname << " / " << bname << " shape " << shape;
                }
            }
        }
    }
}

/// Tapes of a single instruction and tapes whose output is a constant or a variable.
TEST(BatchIsa, TinyTapes) {
    const auto points = special_pairs();
    for (int shape = 0; shape < 3; ++shape) {
        Graph g;
        auto [x, y, z] = vars(g);
        g.set_output(shape == 0 ? y.id : shape == 1 ? g.constant(-0.0) : (x + 0.0).id);
        const Tape t(g);
        for (const auto& p : points) ASSERT_EQ(mismatch(t, p), "") << "shape " << shape;
    }
}

/// The batch code (expr/eval.h, BatchCode) folds a constant read by add, sub, mul, div, min or
/// max into that instruction as an immediate, in either operand slot, and drops its Const when no
/// other instruction reads it. Every binary op with constants of every kind (signed zeros,
/// subnormal, huge) on either side of every special value; a constant also read by sqrt (its Const
/// must stay); both operands constant; one constant read at the start and at the end of a tape.
TEST(BatchIsa, ImmediateOperandsInEitherSlot) {
    const auto points = special_pairs();
    const double consts[] = {0.0, -0.0, 5e-324, -DBL_MIN, 1.0, -2.5, 1e300, -DBL_MAX};
    for (const auto& [bname, b] : binaries()) {
        for (double c : consts) {
            for (int shape = 0; shape < 5; ++shape) {
                Graph g;
                auto [x, y, z] = vars(g);
                const Expr k = constant(g, c);
                Expr f;
                switch (shape) {
                    case 0:
                        f = b(x, k);  // immediate second
                        break;
                    case 1:
                        f = b(k, x);  // immediate first
                        break;
                    case 2:
                        f = b(b(k, x), sqrt(k));  // the Const is also read by sqrt
                        break;
                    case 3:
                        f = b(b(x, k), b(k, constant(g, 0.375)));  // both operands constant
                        break;
                    default:
                        f = b(b(b(x, k), square(y)), b(z, k));  // read early and late
                        break;
                }
                g.set_output(f.id);
                const Tape t(g);
                for (const auto& p : points) {
                    ASSERT_EQ(mismatch(t, p), "") << bname << " with " << c << " shape " << shape;
                }
            }
        }
    }
    // The graph orders the operands of add, mul, min and max its own way; SSA lists built by
    // hand put the constant in each slot of every binary op.
    for (Op op : {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Min, Op::Max}) {
        for (double c : consts) {
            for (bool first : {true, false}) {
                const Instr k{Op::Const, 0, 0, 0, c}, x{Op::VarX, 1, 0, 0, 0.0};
                const Instr f{op, 2, first ? 0u : 1u, first ? 1u : 0u, 0.0};
                const Tape t = Tape::from_ssa({k, x, f});
                for (const auto& p : points) {
                    ASSERT_EQ(mismatch(t, p), "")
                        << name(op) << " with " << c << " first " << first;
                }
            }
        }
    }
}

/// An Evaluator<Batch> keeps the batch code of the last tape it ran (keyed by Tape::serial): it
/// must follow whichever tape it is given — two tapes in turn, a copy, a tape assigned over, a
/// moved tape. Lane i has x = i/4 − 8, so x − 1 and 3x are exact.
TEST(BatchIsa, EvaluatorFollowsTheTapeItIsGiven) {
    const auto make = [](bool minus) {
        Graph g;
        auto [x, y, z] = vars(g);
        g.set_output((minus ? x - 1.0 : x * 3.0).id);
        return Tape(g);
    };
    const Tape t1 = make(true), t2 = make(false);
    ASSERT_NE(t1.serial(), t2.serial());
    std::array<Batch, 3> p;
    for (int i = 0; i < kBatch; ++i) {
        p[0][i] = i / 4.0 - 8.0;
        p[1][i] = p[2][i] = 0.0;
    }
    Evaluator<Batch> eb;
    const auto check = [&](const Tape& t, bool minus, const char* what) {
        const Batch r = eb(t, p);
        for (int i = 0; i < kBatch; ++i) {
            const double x = i / 4.0 - 8.0;
            ASSERT_EQ(r[i], minus ? x - 1.0 : 3.0 * x) << what << " lane " << i;
        }
    };
    check(t1, true, "t1");
    check(t2, false, "t2");
    check(t1, true, "t1 again");
    Tape a = t1;
    check(a, true, "copy of t1");
    a = t2;
    check(a, false, "t2 assigned over it");
    Tape m = std::move(a);
    EXPECT_EQ(a.serial(), 0u);  // NOLINT(bugprone-use-after-move): moved-from state is specified
    EXPECT_EQ(a.size(), 0u);    // NOLINT(bugprone-use-after-move)
    check(m, false, "moved");
    a = make(true);
    check(a, true, "a new tape in the moved-from one");
}

/// kBatch lanes of gen_double() values with NaN mixed in.
rc::Gen<std::array<Batch, 3>> gen_lanes() {
    return rc::gen::exec([] {
        std::array<Batch, 3> p;
        for (int i = 0; i < kBatch; ++i) {
            for (int k = 0; k < 3; ++k) {
                p[k][i] = *rc::gen::weightedOneOf<double>(
                    {{20, testing::gen_double()}, {1, rc::gen::just(kNaN)}});
            }
        }
        return p;
    });
}

RC_GTEST_PROP(BatchIsaProperty, RandomDagsMatchDoubleOnEveryCopy, ()) {
    const Tape t(*testing::gen_dag(40));
    const std::string m = mismatch(t, *gen_lanes());
    RC_ASSERT(m == "");
}

/// run_batch over a bare instruction list (the quadtree's leaves run their pruned SSA lists so):
/// every register is written once, so no result stays unstored; the carried operands remain. Over
/// all lanes and over the first half only.
RC_GTEST_PROP(BatchIsaProperty, SsaListsMatchDoubleOnEveryCopy, ()) {
    const Tape t(*testing::gen_dag(40));
    const auto p = *gen_lanes();
    IsaGuard guard;
    Evaluator<double> ed;
    const std::vector<Instr>& ssa = t.ssa();
    std::vector<Batch> slots(ssa.size());
    // All lanes, then only the first half (the walk the quadtree's 8×8 leaves use).
    for (const int lanes : {-1, kBatch / 2}) {
        for (BatchIsa isa : batch_isas()) {
            set_batch_isa(isa);
            detail::run_batch(ssa.data(), ssa.data() + ssa.size(), p.data(), slots.data(), lanes);
            for (int i = 0; i < (lanes < 0 ? kBatch : lanes); ++i) {
                const double want = ed(t, std::array<double, 3>{p[0][i], p[1][i], p[2][i]});
                RC_ASSERT(same(slots[ssa.size() - 1][i], want));
            }
        }
    }
}

/// Pruned tapes come from Tape::from_ssa and may hold dead values and constant outputs.
RC_GTEST_PROP(BatchIsaProperty, PrunedTapesMatchDoubleOnEveryCopy, ()) {
    const Tape full(*testing::gen_dag(40));
    std::array<Interval, 3> box;
    for (auto& b : box) {
        const auto [lo, hi] = *testing::gen_bounds();
        b = Interval(lo, hi);
    }
    const Tape t = prune(full, box).tape;
    const std::string m = mismatch(t, *gen_lanes());
    RC_ASSERT(m == "");
}

}  // namespace
}  // namespace certray::expr
