// tests/expr/graph_test.cpp — expr::Graph: frozen op codes, deduplication, exact-only folding,
// simplifications that keep the real function, reachability and the builder.
#include "expr/graph.h"

#include <gtest/gtest.h>

#include <array>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "expr/builder.h"
#include "expr/op.h"
#include "tests/support/fp_env.h"

namespace certray::expr {
namespace {

// The codes are written to files: they must never change.
static_assert(static_cast<int>(Op::Const) == 0);
static_assert(static_cast<int>(Op::VarX) == 1);
static_assert(static_cast<int>(Op::VarZ) == 3);
static_assert(static_cast<int>(Op::Neg) == 4);
static_assert(static_cast<int>(Op::Cos) == 11);
static_assert(static_cast<int>(Op::Add) == 12);
static_assert(static_cast<int>(Op::Max) == 17);
static_assert(static_cast<int>(Op::Pow) == 18);

TEST(Op, ArityAndName) {
    EXPECT_EQ(arity(Op::Const), 0);
    EXPECT_EQ(arity(Op::VarY), 0);
    EXPECT_EQ(arity(Op::Sqrt), 1);
    EXPECT_EQ(arity(Op::Pow), 1);
    EXPECT_EQ(arity(Op::Div), 2);
    EXPECT_EQ(arity(Op::Min), 2);
    EXPECT_EQ(name(Op::Log), "log");
    EXPECT_EQ(name(Op::Square), "square");
    EXPECT_EQ(name(Op::VarZ), "z");
    for (int k = 0; k < kOpCount; ++k) {
        const Op op = static_cast<Op>(k);
        EXPECT_GE(arity(op), 0);
        EXPECT_NE(name(op), "?");
    }
}

TEST(Graph, SameSubexpressionIsOneNode) {
    Graph g;
    const NodeId x = g.var(0);
    const NodeId y = g.var(1);
    const NodeId a = g.unary(Op::Sqrt, g.binary(Op::Add, g.unary(Op::Square, x), g.constant(2.0)));
    const std::size_t size = g.size();
    const NodeId b = g.unary(Op::Sqrt, g.binary(Op::Add, g.unary(Op::Square, x), g.constant(2.0)));
    EXPECT_EQ(a, b);
    EXPECT_EQ(g.size(), size);
    EXPECT_EQ(g.var(0), x);
    EXPECT_NE(x, y);
}

TEST(Graph, CommutativeOpsCanonicaliseChildOrder) {
    Graph g;
    const NodeId x = g.var(0);
    const NodeId y = g.var(1);
    for (Op op : {Op::Add, Op::Mul, Op::Min, Op::Max}) {
        EXPECT_EQ(g.binary(op, x, y), g.binary(op, y, x)) << name(op);
    }
    EXPECT_NE(g.binary(Op::Sub, x, y), g.binary(Op::Sub, y, x));
    EXPECT_NE(g.binary(Op::Div, x, y), g.binary(Op::Div, y, x));
}

TEST(Graph, ConstantsComparedByBitPattern) {
    Graph g;
    const NodeId pz = g.constant(0.0);
    const NodeId nz = g.constant(-0.0);
    EXPECT_NE(pz, nz);
    EXPECT_TRUE(std::signbit(g.node(nz).constant));
    EXPECT_EQ(g.constant(0.1), g.constant(0.1));
    EXPECT_NE(g.constant(0.1), g.constant(std::nextafter(0.1, 1.0)));
}

TEST(Graph, RejectsNonFiniteConstants) {
    Graph g;
    EXPECT_THROW(g.constant(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    EXPECT_THROW(g.constant(std::numeric_limits<double>::infinity()), std::invalid_argument);
    EXPECT_THROW(g.constant(-std::numeric_limits<double>::infinity()), std::invalid_argument);
    EXPECT_THROW(g.var(3), std::invalid_argument);
    EXPECT_THROW(g.unary(Op::Add, g.var(0)), std::invalid_argument);
    EXPECT_THROW(g.binary(Op::Sqrt, g.var(0), g.var(1)), std::invalid_argument);
    EXPECT_THROW(g.unary(Op::Neg, NodeId{1000}), std::invalid_argument);
}

// Expects `id` to be the constant `value`, bit for bit.
void expect_constant(const Graph& g, NodeId id, double value) {
    ASSERT_EQ(g.node(id).op, Op::Const);
    EXPECT_EQ(std::signbit(g.node(id).constant), std::signbit(value));
    EXPECT_EQ(g.node(id).constant, value);
}

TEST(Graph, FoldsOnlyExactResults) {
    Graph g;
    auto c = [&](double v) { return g.constant(v); };
    // 0.1 + 0.2 (as doubles) is 0.3000000000000000166533453693773481063544750213623046875, which is
    // not a double: no fold. 0.5 + 0.25 = 0.75 is exact.
    EXPECT_EQ(g.node(g.binary(Op::Add, c(0.1), c(0.2))).op, Op::Add);
    expect_constant(g, g.binary(Op::Add, c(0.5), c(0.25)), 0.75);
    expect_constant(g, g.binary(Op::Sub, c(0.5), c(0.25)), 0.25);
    EXPECT_EQ(g.node(g.binary(Op::Add, c(1.0), c(0x1p-60))).op, Op::Add);  // needs 61 bits
    EXPECT_EQ(g.node(g.binary(Op::Add, c(1e308), c(1e308))).op, Op::Add);  // overflows
    expect_constant(g, g.binary(Op::Mul, c(1.5), c(2.0)), 3.0);
    EXPECT_EQ(g.node(g.binary(Op::Mul, c(3.0), c(0.1))).op, Op::Mul);  // 3·0.1 is not a double
    EXPECT_EQ(g.node(g.binary(Op::Mul, c(1e-200), c(3e-200))).op, Op::Mul);  // underflows
    // x·x is x² (so that Lipschitz root forms see a sum of squares); not folded when it underflows.
    EXPECT_EQ(g.node(g.binary(Op::Mul, g.var(0), g.var(0))).op, Op::Square);
    EXPECT_EQ(g.node(g.binary(Op::Mul, c(1e-200), c(1e-200))).op, Op::Square);
    expect_constant(g, g.binary(Op::Div, c(1.0), c(4.0)), 0.25);
    EXPECT_EQ(g.node(g.binary(Op::Div, c(1.0), c(3.0))).op, Op::Div);
    EXPECT_EQ(g.node(g.binary(Op::Div, c(1.0), c(0.0))).op, Op::Div);
    expect_constant(g, g.unary(Op::Sqrt, c(2.25)), 1.5);
    EXPECT_EQ(g.node(g.unary(Op::Sqrt, c(2.0))).op, Op::Sqrt);
    EXPECT_EQ(g.node(g.unary(Op::Sqrt, c(-4.0))).op, Op::Sqrt);  // undefined: kept
    EXPECT_EQ(g.node(g.unary(Op::Exp, c(1.0))).op, Op::Exp);
    EXPECT_EQ(g.node(g.unary(Op::Log, c(2.0))).op, Op::Log);
    EXPECT_EQ(g.node(g.unary(Op::Sin, c(1.0))).op, Op::Sin);
    EXPECT_EQ(g.node(g.unary(Op::Cos, c(1.0))).op, Op::Cos);
    expect_constant(g, g.unary(Op::Exp, c(0.0)), 1.0);
    expect_constant(g, g.unary(Op::Cos, c(0.0)), 1.0);
    expect_constant(g, g.unary(Op::Log, c(1.0)), 0.0);
    expect_constant(g, g.unary(Op::Neg, c(0.1)), -0.1);
    expect_constant(g, g.unary(Op::Neg, c(0.0)), -0.0);
    expect_constant(g, g.unary(Op::Abs, c(-2.5)), 2.5);
    expect_constant(g, g.unary(Op::Square, c(-3.0)), 9.0);
    EXPECT_EQ(g.node(g.unary(Op::Square, c(0.1))).op, Op::Square);
    expect_constant(g, g.binary(Op::Min, c(2.0), c(-1.0)), -1.0);
    expect_constant(g, g.binary(Op::Max, c(2.0), c(-1.0)), 2.0);
    expect_constant(g, g.pow(c(3.0), 4), 81.0);
    expect_constant(g, g.pow(c(-2.0), 3), -8.0);
    expect_constant(g, g.pow(c(0.1), 0), 1.0);
    EXPECT_EQ(g.node(g.pow(c(0.1), 3)).op, Op::Pow);
    EXPECT_EQ(g.node(g.pow(c(10.0), 400)).op, Op::Pow);  // overflows
}

// The DAG does not depend on the caller's floating-point state (Graph opens a NearestScope): an
// exact sum folds under any rounding direction, set by fesetround or in MXCSR alone (where x87
// still says nearest, all that fegetround reads on x86-64), an inexact one never does, and under
// denormals-are-zero 2^-1074 is still read as itself (1 + 2^-1074 is not 1, and x + 2^-1074 is
// not x).
TEST(Graph, FoldsTheSameWhateverTheCallersState) {
    auto build = [](Graph& g) {
        const NodeId x = g.var(0);
        return std::array<NodeId, 4>{g.binary(Op::Add, g.constant(0.5), g.constant(0.25)),
                                     g.binary(Op::Add, g.constant(0.1), g.constant(0.2)),
                                     g.binary(Op::Add, g.constant(1.0), g.constant(0x1p-1074)),
                                     g.binary(Op::Add, x, g.constant(0x1p-1074))};
    };
    auto check = [](const Graph& g, const std::array<NodeId, 4>& n, const char* state) {
        EXPECT_EQ(g.node(n[0]).op, Op::Const) << state;
        EXPECT_EQ(g.node(n[0]).constant, 0.75) << state;
        EXPECT_EQ(g.node(n[1]).op, Op::Add) << state;
        EXPECT_EQ(g.node(n[2]).op, Op::Add) << state;
        EXPECT_EQ(g.node(n[3]).op, Op::Add) << state;
    };
    {
        Graph g;
        std::fesetround(FE_UPWARD);
        const auto n = build(g);
        std::fesetround(FE_TONEAREST);
        check(g, n, "fesetround upward");
    }
#if defined(__GNUC__) && defined(__x86_64__)
    const testing::FpWords before = testing::read_fp_words();
    for (const std::uint32_t mxcsr :
         {0x1f80u | (2u << 13), 0x1f80u | testing::kDaz | testing::kFtz}) {
        testing::FpWords w = before;
        w.mxcsr = mxcsr;
        w.x87 = 0x037f;
        Graph g;
        testing::write_fp_words(w);
        const auto n = build(g);
        testing::write_fp_words(before);
        check(g, n, mxcsr & testing::kDaz ? "ftz-daz" : "mxcsr upward");
    }
#endif
}

TEST(Graph, IdentitiesThatKeepTheRealFunction) {
    Graph g;
    const NodeId x = g.var(0);
    const NodeId y = g.var(1);
    const NodeId one = g.constant(1.0);
    const NodeId zero = g.constant(0.0);
    const NodeId mzero = g.constant(-0.0);
    EXPECT_EQ(g.binary(Op::Mul, x, one), x);
    EXPECT_EQ(g.binary(Op::Mul, one, x), x);
    EXPECT_EQ(g.binary(Op::Add, x, zero), x);
    EXPECT_EQ(g.binary(Op::Add, mzero, x), x);
    EXPECT_EQ(g.binary(Op::Sub, x, zero), x);
    EXPECT_EQ(g.binary(Op::Div, x, one), x);
    EXPECT_EQ(g.unary(Op::Neg, g.unary(Op::Neg, x)), x);
    EXPECT_EQ(g.binary(Op::Sub, zero, y), g.unary(Op::Neg, y));
    EXPECT_EQ(g.pow(x, 1), x);
    EXPECT_EQ(g.pow(x, 2), g.unary(Op::Square, x));
    EXPECT_EQ(g.binary(Op::Min, x, x), x);
    // Not folded: each could make an undefined point (x = sqrt(-1), x = 1/0) defined.
    const NodeId s = g.unary(Op::Sqrt, x);
    EXPECT_EQ(g.node(g.binary(Op::Sub, s, s)).op, Op::Sub);
    EXPECT_EQ(g.node(g.binary(Op::Mul, s, zero)).op, Op::Mul);
    EXPECT_EQ(g.node(g.binary(Op::Div, s, s)).op, Op::Div);
    const NodeId p0 = g.pow(s, 0);
    EXPECT_EQ(g.node(p0).op, Op::Pow);
    EXPECT_EQ(g.node(p0).exponent, 0u);
}

TEST(Graph, OutputReachabilityAndUsesVar) {
    Graph g;
    const NodeId x = g.var(0);
    const NodeId z = g.var(2);
    const NodeId unused = g.binary(Op::Mul, z, z);
    const NodeId f = g.binary(Op::Sub, g.unary(Op::Square, x), g.constant(1.0));
    EXPECT_TRUE(g.topological_order().empty());  // no output yet
    g.set_output(f);
    EXPECT_EQ(g.output(), f);
    EXPECT_TRUE(g.uses_var(0));
    EXPECT_FALSE(g.uses_var(1));
    EXPECT_FALSE(g.uses_var(2));
    const auto order = g.topological_order();
    EXPECT_EQ(order.size(), 4u);  // x, x², 1, x² − 1
    EXPECT_EQ(order.back(), f);
    for (NodeId id : order) EXPECT_NE(id, unused);
    g.set_output(unused);
    EXPECT_TRUE(g.uses_var(2));
    EXPECT_FALSE(g.uses_var(0));
    EXPECT_THROW(g.set_output(NodeId{99}), std::invalid_argument);
}

TEST(Graph, TopologicalOrderOfAHundredThousandDeepChain) {
    Graph g;
    const NodeId x = g.var(0);
    NodeId n = x;
    constexpr int kDepth = 100000;
    for (int i = 0; i < kDepth; ++i) {
        n = (i % 2 == 0) ? g.unary(Op::Sin, n) : g.binary(Op::Add, n, x);
    }
    g.set_output(n);
    const auto order = g.topological_order();
    ASSERT_EQ(order.size(), static_cast<std::size_t>(kDepth) + 1);
    // Children come before parents.
    std::vector<char> seen(g.size(), 0);
    for (NodeId id : order) {
        const Node& node = g.node(id);
        if (node.a.valid()) {
            EXPECT_TRUE(seen[node.a.value]);
        }
        if (node.b.valid()) {
            EXPECT_TRUE(seen[node.b.value]);
        }
        seen[id.value] = 1;
    }
    EXPECT_TRUE(g.uses_var(0));
    EXPECT_FALSE(g.uses_var(1));
}

TEST(Builder, SphereMatchesManualConstruction) {
    Graph g;
    auto [x, y, z] = vars(g);
    auto f = sqrt(x * x + y * y + z * z) - 1.0;
    g.set_output(f.id);

    Graph h;
    const NodeId hx = h.var(0), hy = h.var(1), hz = h.var(2);
    const NodeId r2 =
        h.binary(Op::Add, h.binary(Op::Add, h.binary(Op::Mul, hx, hx), h.binary(Op::Mul, hy, hy)),
                 h.binary(Op::Mul, hz, hz));
    const NodeId hf = h.binary(Op::Sub, h.unary(Op::Sqrt, r2), h.constant(1.0));
    EXPECT_EQ(g.size(), h.size());
    EXPECT_EQ(f.id, hf);
    EXPECT_EQ(g.node(f.id).op, Op::Sub);
    EXPECT_EQ(g.node(g.node(f.id).a).op, Op::Sqrt);
}

TEST(Builder, OperatorsAndFunctions) {
    Graph g;
    auto [x, y, z] = vars(g);
    EXPECT_EQ((x + y).id, (y + x).id);
    EXPECT_EQ((2.0 * x).id, (x * 2.0).id);
    EXPECT_EQ(g.node((1.0 - x).id).op, Op::Sub);
    EXPECT_EQ(g.node((-x).id).op, Op::Neg);
    EXPECT_EQ(pow(x, 2).id, square(x).id);
    EXPECT_EQ(g.node(pow(x, 5).id).exponent, 5u);
    EXPECT_EQ(g.node(min(x, 0.5).id).op, Op::Min);
    EXPECT_EQ(g.node(max(y, z).id).op, Op::Max);
    EXPECT_EQ(g.node((x / 3.0).id).op, Op::Div);
    EXPECT_EQ(g.node(abs(x).id).op, Op::Abs);
    EXPECT_EQ(g.node(exp(x).id).op, Op::Exp);
    EXPECT_EQ(g.node(log(x).id).op, Op::Log);
    EXPECT_EQ(g.node(sin(x).id).op, Op::Sin);
    EXPECT_EQ(g.node(cos(x).id).op, Op::Cos);
    EXPECT_EQ((x * 1.0).id, x.id);
    Graph other;
    auto [ox, oy, oz] = vars(other);
    EXPECT_THROW(x + ox, std::invalid_argument);
}

}  // namespace
}  // namespace certray::expr
