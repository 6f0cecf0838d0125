// tests/expr/fidget_ops_test.cpp — Fidget's further opcodes (issue 14) through expr/: the .vm
// importer and the .expr parser and printer (round trip), the evaluator over double, Interval and
// MpfrInterval, the batch walk (every copy, bit for bit against the scalar double evaluator, with
// the carried-operand patterns), and pruning of and/or.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "expr/derived.h"
#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "expr/graph.h"
#include "expr/parser.h"
#include "expr/printer.h"
#include "expr/prune.h"
#include "expr/tape.h"
#include "expr/vm_import.h"
#include "interval/batch.h"
#include "interval/mpfr_interval.h"
#include "tests/support/generators.h"
#include "tests/support/graph_eval.h"
#include "tests/support/mpfr_oracle.h"

namespace certray::expr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::filesystem::path kModel = std::filesystem::path(CERTRAY_TEST_DATA) / "fidget_ops.vm";

const std::vector<Op>& new_ops() {
    static const std::vector<Op> ops = {Op::Floor,   Op::Ceil, Op::Round, Op::Tan, Op::Asin,
                                        Op::Acos,    Op::Atan, Op::Recip, Op::Not, Op::Atan2,
                                        Op::Compare, Op::Mod,  Op::And,   Op::Or};
    return ops;
}

bool same(double a, double b) {
    return (std::isnan(a) && std::isnan(b)) ||
           std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

TEST(FidgetOps, CodesAreAppendedAndNamed) {
    static_assert(static_cast<int>(Op::Floor) == 19 && static_cast<int>(Op::Or) == 32);
    static_assert(kOpCount == 33);
    for (Op op : new_ops()) {
        EXPECT_FALSE(name(op).empty());
        EXPECT_EQ(arity(op), op >= Op::Atan2 ? 2 : 1) << name(op);
    }
}

TEST(FidgetOps, VmModelUsesEveryOpcodeAndMatchesTheGraph) {
    const Graph g = import_vm_file(kModel);
    std::vector<bool> seen(kOpCount, false);
    for (NodeId id : g.topological_order()) seen[static_cast<int>(g.node(id).op)] = true;
    for (Op op : new_ops()) EXPECT_TRUE(seen[static_cast<int>(op)]) << name(op);
    const Tape tape(g);
    for (double x : {-2.75, -1.0, -0.3, 0.0, 0.25, 1.5, 2.0, 7.1}) {
        for (double y : {-1.5, 0.0, 0.4, 3.0}) {
            for (double z : {-4.5, -0.5, 0.0, 1.2, 6.0}) {
                const double want = testing::eval_graph(g, x, y, z);
                EXPECT_TRUE(same(eval<double>(tape, {x, y, z}), want)) << x << " " << y << " " << z;
            }
        }
    }
}

TEST(FidgetOps, ExprRoundTripAndParse) {
    const Graph g = import_vm_file(kModel);
    const std::string text = print_expr(g);
    const Graph h = parse_expr(text);
    EXPECT_EQ(print_expr(h), text);
    const Tape tg(g), th(h);
    for (double x : {-1.25, 0.5, 3.0}) {
        EXPECT_TRUE(same(eval<double>(tg, {x, 0.75, -2.0}), eval<double>(th, {x, 0.75, -2.0})));
    }
    const Graph p = parse_expr(
        "floor(x) + ceil(y) + round(z) + tan(x) + asin(y) + acos(y) + atan(z) + recip(x)"
        " + not(x) + atan2(y, x) + compare(x, y) + mod(x, 3) + and(x, y) + or(x, y)");
    const Tape tp(p);
    const double x = 1.5, y = -0.25, z = 2.5;
    const double want = std::floor(x) + std::ceil(y) + std::round(z) + std::tan(x) + std::asin(y) +
                        std::acos(y) + std::atan(z) + 1.0 / x + 0.0 + std::atan2(y, x) + 1.0 + 1.5 +
                        y + x;
    EXPECT_EQ(eval<double>(tp, {x, y, z}), want);
}

TEST(FidgetOps, ConstantsFoldExactly) {
    Graph g;
    const NodeId c = g.constant(2.5), zero = g.constant(0.0), x = g.var(0);
    EXPECT_EQ(g.node(g.unary(Op::Floor, c)).constant, 2.0);
    EXPECT_EQ(g.node(g.unary(Op::Round, c)).constant, 3.0);
    EXPECT_EQ(g.node(g.unary(Op::Not, zero)).constant, 1.0);
    EXPECT_EQ(g.node(g.binary(Op::Compare, c, zero)).constant, 1.0);
    EXPECT_EQ(g.binary(Op::And, zero, x), zero);
    EXPECT_EQ(g.binary(Op::And, c, x), x);
    EXPECT_EQ(g.binary(Op::Or, c, x), c);
    EXPECT_EQ(g.node(g.unary(Op::Recip, g.constant(4.0))).constant, 0.25);
    EXPECT_EQ(g.node(g.unary(Op::Recip, g.constant(3.0))).op, Op::Recip);  // 1/3 is not exact
}

// Interval and MpfrInterval over a box around random points enclose the 256-bit value there.
RC_GTEST_PROP(FidgetOps, VmModelIntervalEnclosesMpfr, ()) {
    static const Tape tape(import_vm_file(kModel));
    const auto coord = [] {
        return *rc::gen::map(rc::gen::inRange(-4000, 4000), [](int k) { return k / 1000.0; });
    };
    const double x = coord(), y = coord(), z = coord();
    const double w = std::ldexp(1.0, *rc::gen::inRange(-30, 1));
    const Interval box = eval<Interval>(
        tape, {Interval(x - w, x + w), Interval(y - w, y + w), Interval(z - w, z + w)});
    const MpfrInterval exact =
        eval<MpfrInterval>(tape, {MpfrInterval(x), MpfrInterval(y), MpfrInterval(z)});
    RC_ASSERT(testing::encloses(box.lower(), box.upper(), exact));
    if (box.defined) RC_ASSERT(!exact.is_empty());
}

// ---- the batch walk
// -------------------------------------------------------------------------------

std::string batch_mismatch(const Tape& tape, const std::array<Batch, 3>& p) {
    const BatchIsa saved = batch_isa();
    Evaluator<double> ed;
    std::string out;
    for (BatchIsa isa : {BatchIsa::Baseline, BatchIsa::Avx2, BatchIsa::Avx512}) {
        if (!batch_isa_supported(isa)) continue;
        set_batch_isa(isa);
        Evaluator<Batch> eb;
        const Batch r = eb(tape, p);
        for (int i = 0; i < kBatch && out.empty(); ++i) {
            const double want = ed(tape, {p[0][i], p[1][i], p[2][i]});
            if (!same(r[i], want)) {
                out = std::string(batch_isa_name(isa)) + " lane " + std::to_string(i) + ": " +
                      std::to_string(r[i]) + " vs " + std::to_string(want);
            }
        }
        // Bare instruction lists (not batch code) take the same path.
        std::vector<Batch> regs(tape.registers());
        detail::run_batch(tape.instrs().data(), tape.instrs().data() + tape.instrs().size(),
                          p.data(), regs.data());
        for (int i = 0; i < kBatch && out.empty(); ++i) {
            const double want = ed(tape, {p[0][i], p[1][i], p[2][i]});
            if (!same(regs[tape.output()][i], want)) out = "bare list lane " + std::to_string(i);
        }
    }
    set_batch_isa(saved);
    return out;
}

std::array<Batch, 3> special_batch(int shift) {
    static const std::vector<double> s = {0.0,    -0.0,    kInf,    -kInf, kNaN,
                                          5e-324, -1e-310, DBL_MAX, 1.0,   -1.0,
                                          0.5,    -2.5,    3.0,     1e300, 1.5707963267948966,
                                          -0.7,   2.0,     7.5,     -3.0,  1e-20,
                                          4.0};
    std::array<Batch, 3> p;
    for (int i = 0; i < kBatch; ++i) {
        p[0][i] = s[(i + shift) % s.size()];
        p[1][i] = s[(i / s.size() + 3 * shift) % s.size()];
        p[2][i] = s[(i * 7 + shift) % s.size()];
    }
    return p;
}

TEST(FidgetOps, BatchWalkIsBitForBitTheScalarEvaluator) {
    for (Op op : new_ops()) {
        // Shapes that put the previous result in the first, second, or both operand slots, with
        // a constant operand (never an immediate form for these ops) and a later reader.
        std::vector<Graph> graphs;
        for (int shape = 0; shape < 5; ++shape) {
            Graph g;
            const NodeId x = g.var(0), y = g.var(1), z = g.var(2);
            const auto f = [&](NodeId a, NodeId b) {
                return arity(op) == 1 ? g.unary(op, a) : g.binary(op, a, b);
            };
            NodeId out;
            switch (shape) {
                case 0:
                    out = f(x, y);
                    break;
                case 1:
                    out = f(g.binary(Op::Add, x, z), y);
                    break;
                case 2:
                    out = f(y, g.binary(Op::Mul, x, z));
                    break;
                case 3: {
                    const NodeId s = g.binary(Op::Sub, x, y);
                    out = f(s, s);
                    break;
                }
                default: {
                    const NodeId a = f(x, g.constant(2.0));
                    out = g.binary(Op::Add, f(a, z), a);
                    break;
                }
            }
            g.set_output(out);
            graphs.push_back(g);
        }
        for (const Graph& g : graphs) {
            const Tape tape(g);
            for (int shift = 0; shift < 6; ++shift) {
                EXPECT_EQ(batch_mismatch(tape, special_batch(shift)), "") << name(op);
            }
        }
    }
    const Tape model(import_vm_file(kModel));
    for (int shift = 0; shift < 4; ++shift)
        EXPECT_EQ(batch_mismatch(model, special_batch(shift)), "");
}

// ---- pruning
// --------------------------------------------------------------------------------------

// Lipschitz bounds (GradBound): where finite they hold between points of the box, decided in
// MPFR; where an op may jump on the box there is no finite bound.
RC_GTEST_PROP(FidgetOps, LipschitzBoundHoldsOrIsInfinite, ()) {
    static const std::vector<Tape> tapes = [] {
        std::vector<Tape> t;
        for (const char* text :
             {"tan(x) + atan(y) - z", "asin(0.5 * sin(x)) + acos(0.25 * y)", "atan2(y, x + 3) - z",
              "floor(x) + y", "mod(x, 2) + round(y)", "and(compare(x, y), z) + or(not(x), y)",
              "recip(x^2 + 1) + ceil(z)"}) {
            t.emplace_back(parse_expr(text));
        }
        return t;
    }();
    const Tape& tape = tapes[*rc::gen::inRange<std::size_t>(0, tapes.size())];
    const auto coord = [] {
        return *rc::gen::map(rc::gen::inRange(-3000, 3000), [](int k) { return k / 1000.0; });
    };
    const double w = std::ldexp(1.0, *rc::gen::inRange(-12, 0));
    std::array<Interval, 3> box;
    std::array<double, 3> p, q;
    for (int i = 0; i < 3; ++i) {
        const double c = coord();
        box[i] = Interval(c - w, c + w);
        p[i] = *testing::gen_point_in(c - w, c + w);
        q[i] = *testing::gen_point_in(c - w, c + w);
    }
    const double lambda = lipschitz_bound(tape, box);
    RC_ASSERT(lambda >= 0);
    if (std::isfinite(lambda)) RC_ASSERT(testing::lipschitz_holds(tape, lambda, p, q));
    // A jump inside the box: floor(x) + y over x ∈ [0.5, 1.5] has no Lipschitz constant.
    static const Tape jump(parse_expr("floor(x) + y"));
    RC_ASSERT(
        std::isinf(lipschitz_bound(jump, {Interval(0.5, 1.5), Interval(0, 1), Interval(0.0)})));
}

TEST(FidgetOps, AndOrPruneWhereTheFirstOperandDecides) {
    Graph g;
    const NodeId x = g.var(0), y = g.var(1);
    const NodeId sel = g.binary(Op::And, x, g.unary(Op::Sin, y));  // x ≠ 0 on the box: sin y
    g.set_output(g.binary(Op::Add, g.binary(Op::Or, sel, y), y));
    const Tape tape(g);
    const std::array<Interval, 3> box{Interval(1, 2), Interval(0.5, 1), Interval(0.0)};
    const PruneResult r = prune(tape, box);
    EXPECT_LT(r.after, r.before);
    for (double px : {1.0, 1.5, 2.0}) {
        for (double py : {0.5, 0.75, 1.0}) {
            EXPECT_EQ(eval<double>(r.tape, {px, py, 0.0}), eval<double>(tape, {px, py, 0.0}));
        }
    }
    // floor over a box where it does not jump folds to its constant.
    Graph h;
    h.set_output(h.binary(Op::Sub, h.unary(Op::Floor, h.var(0)), h.var(1)));
    const PruneResult f = prune(Tape(h), {Interval(1.2, 1.7), Interval(0, 1), Interval(0.0)});
    EXPECT_LT(f.after, f.before);
    EXPECT_EQ(eval<double>(f.tape, {1.5, 0.25, 0.0}), 0.75);
}

}  // namespace
}  // namespace certray::expr
