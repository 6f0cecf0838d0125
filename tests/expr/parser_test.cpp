// tests/expr/parser_test.cpp — the .expr language: precedence, literals, bindings, every error path
// with its location, nesting limits, and the printer's round trip.
#include "expr/parser.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "expr/input_error.h"
#include "expr/printer.h"
#include "expr/vm_import.h"
#include "tests/support/graph_eval.h"

namespace certray::expr {
namespace {

using ::testing::HasSubstr;

double eval(const Graph& g, double x, double y, double z) {
    return testing::eval_graph(g, x, y, z);
}

const Node& out(const Graph& g) { return g.node(g.output()); }
const Node& child_a(const Graph& g, const Node& n) { return g.node(n.a); }
const Node& child_b(const Graph& g, const Node& n) { return g.node(n.b); }

// The message of the InputError thrown by parsing `text` as file "t.expr", or "" if none.
std::string error_of(const std::string& text) {
    try {
        parse_expr(text, "t.expr");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Parser, UnaryMinusIsLooserThanPower) {
    const Graph g = parse_expr("-x^2");
    ASSERT_EQ(out(g).op, Op::Neg);
    const Node& sq = child_a(g, out(g));
    ASSERT_EQ(sq.op, Op::Square);
    EXPECT_EQ(g.node(sq.a).op, Op::VarX);
    EXPECT_EQ(eval(g, 3, 0, 0), -9.0);
}

TEST(Parser, PowerIsTighterThanProduct) {
    // 2·3² = 18 (not (2·3)² = 36); all steps exact, so folded to one constant.
    const Graph g = parse_expr("2*3^2");
    ASSERT_EQ(out(g).op, Op::Const);
    EXPECT_EQ(out(g).constant, 18.0);
    const Graph h = parse_expr("2*x^3");
    ASSERT_EQ(out(h).op, Op::Mul);
    const Node& a = child_a(h, out(h));
    const Node& b = child_b(h, out(h));
    const Node& pw = a.op == Op::Pow ? a : b;
    const Node& two = a.op == Op::Pow ? b : a;
    ASSERT_EQ(pw.op, Op::Pow);
    EXPECT_EQ(pw.exponent, 3u);
    EXPECT_EQ(two.constant, 2.0);
}

TEST(Parser, BinaryOperatorsAreLeftAssociative) {
    EXPECT_EQ(out(parse_expr("1-2-3")).constant, -4.0);  // (1−2)−3, right-assoc would give 2
    EXPECT_EQ(out(parse_expr("8/4/2")).constant, 1.0);   // (8/4)/2, right-assoc would give 4
    const Graph g = parse_expr("x-y-z");
    ASSERT_EQ(out(g).op, Op::Sub);
    EXPECT_EQ(child_b(g, out(g)).op, Op::VarZ);
    const Node& inner = child_a(g, out(g));
    ASSERT_EQ(inner.op, Op::Sub);
    EXPECT_EQ(g.node(inner.a).op, Op::VarX);
    EXPECT_EQ(g.node(inner.b).op, Op::VarY);
    const Graph d = parse_expr("x/y/z");
    ASSERT_EQ(out(d).op, Op::Div);
    EXPECT_EQ(child_a(d, out(d)).op, Op::Div);
    EXPECT_EQ(child_b(d, out(d)).op, Op::VarZ);
}

TEST(Parser, PrecedenceOfSumsProductsAndNegation) {
    const Graph g = parse_expr("x + y*z");
    ASSERT_EQ(out(g).op, Op::Add);
    EXPECT_EQ(eval(g, 1, 2, 3), 7.0);
    const Graph h = parse_expr("-x*y");  // (−x)·y
    ASSERT_EQ(out(h).op, Op::Mul);
    EXPECT_TRUE(child_a(h, out(h)).op == Op::Neg || child_b(h, out(h)).op == Op::Neg);
    const Graph k = parse_expr("x - -y");
    ASSERT_EQ(out(k).op, Op::Sub);
    EXPECT_EQ(child_b(k, out(k)).op, Op::Neg);
    const Graph p = parse_expr("(x+1)^3");
    ASSERT_EQ(out(p).op, Op::Pow);
    EXPECT_EQ(child_a(p, out(p)).op, Op::Add);
    EXPECT_EQ(eval(p, 1, 0, 0), 8.0);
    EXPECT_EQ(out(parse_expr("2^10")).constant, 1024.0);
    EXPECT_EQ(out(parse_expr("(x^2)^3")).op, Op::Pow);
    EXPECT_EQ(out(parse_expr("x^0")).op, Op::Pow);  // not folded to 1: x may be undefined
    EXPECT_EQ(out(parse_expr("--x")).op, Op::VarX);
    EXPECT_EQ(out(parse_expr("square(x)")).op, Op::Square);
    EXPECT_EQ(parse_expr("square(x)").output(), parse_expr("x^2").output());
}

TEST(Parser, Literals) {
    EXPECT_EQ(out(parse_expr("1.5")).constant, 1.5);
    EXPECT_EQ(out(parse_expr(".5")).constant, 0.5);
    EXPECT_EQ(out(parse_expr("1.")).constant, 1.0);
    EXPECT_EQ(out(parse_expr("2e-3")).constant, 0.002);
    EXPECT_EQ(out(parse_expr("2E+3")).constant, 2000.0);
    EXPECT_EQ(out(parse_expr("0.1")).constant, 0.1);        // the nearest double
    EXPECT_EQ(out(parse_expr("1e-400")).constant, 0.0);     // nearest double to 10^-400 is 0
    EXPECT_EQ(out(parse_expr("4e-320")).constant, 4e-320);  // subnormal
    EXPECT_EQ(out(parse_expr("-0")).constant, 0.0);
    EXPECT_TRUE(std::signbit(out(parse_expr("-0")).constant));
    // 0.1 + 0.2 is not folded (its exact sum is not a double).
    EXPECT_EQ(out(parse_expr("0.1 + 0.2")).op, Op::Add);
}

TEST(Parser, FunctionsAndComments) {
    const Graph g = parse_expr(
        "# a comment line\n"
        "min(sqrt(x), abs(y)) + max(exp(z), log(x)) - sin(y) * cos(z)  # trailing comment\n");
    const double x = 2.0, y = -0.5, z = 0.25;
    const double want = std::fmin(std::sqrt(x), std::fabs(y)) +
                        std::fmax(std::exp(z), std::log(x)) - std::sin(y) * std::cos(z);
    EXPECT_EQ(eval(g, x, y, z), want);
    EXPECT_TRUE(g.uses_var(0));
    EXPECT_TRUE(g.uses_var(2));
}

TEST(Parser, BindingsAreSharedSubexpressions) {
    const Graph g = parse_expr(
        "r2 = x^2 + y^2 + z^2\n"
        "\n"
        "r = sqrt(r2)\n"
        "min(r - 1, z + 0.5) * r2\n");
    EXPECT_EQ(eval(g, 1, 2, 2), std::fmin(3.0 - 1.0, 2.5) * 9.0);
    // The same text without bindings builds the same DAG.
    const Graph h = parse_expr("min(sqrt(x^2 + y^2 + z^2) - 1, z + 0.5) * (x^2 + y^2 + z^2)");
    EXPECT_EQ(g.topological_order().size(), h.topological_order().size());
    EXPECT_EQ(print_expr(g), print_expr(h));
}

TEST(Parser, TheExampleOfTheDesign) {
    const Graph g = parse_expr(
        "# a comment\n"
        "r2 = x^2 + y^2 + z^2          # a binding: a named, shared subexpression\n"
        "min(sqrt(r2) - 1, z + 0.5)    # the last expression is f\n",
        "design.expr");
    EXPECT_EQ(out(g).op, Op::Min);
    EXPECT_EQ(eval(g, 0, 0, 0), -1.0);   // inside the unit sphere: sqrt(0) − 1
    EXPECT_EQ(eval(g, 0, 0, -2), -1.5);  // below the plane z = −0.5
    EXPECT_EQ(eval(g, 2, 2, 1), 1.5);    // min(3 − 1, 1.5)
}

TEST(Parser, LineContinuationInsideParentheses) {
    const Graph g = parse_expr("min(x,\n    y) + (1 +\n 2)");
    EXPECT_EQ(eval(g, 1, 2, 0), 4.0);
    EXPECT_EQ(error_of("x +\ny"), "t.expr:1:4: expected an expression, found end of line");
}

TEST(Parser, ErrorsNameFileLineColumnAndWhatWasExpected) {
    EXPECT_EQ(error_of("a = 1\nb = 2\nf = min(x, y\n"),
              "t.expr:4:1: expected ')' after arguments of 'min', found end of input");
    EXPECT_EQ(error_of("min(x y)"), "t.expr:1:7: expected ')' after arguments of 'min', found 'y'");
    EXPECT_EQ(error_of("(x + 1"),
              "t.expr:1:7: expected ')' to close the '(' at 1:1, found end of input");
    EXPECT_EQ(error_of("x + foo"), "t.expr:1:5: undefined name 'foo'");
    EXPECT_EQ(error_of("foo(x)"), "t.expr:1:1: unknown function 'foo'");
    EXPECT_EQ(error_of("a = 1\na = 2\na"), "t.expr:2:1: 'a' is already defined at line 1");
    EXPECT_EQ(error_of("x = 1\nx"), "t.expr:1:1: cannot bind 'x': the name is reserved");
    EXPECT_EQ(error_of("sqrt = 1\n2"), "t.expr:1:1: cannot bind 'sqrt': the name is reserved");
    EXPECT_EQ(error_of("a = a + 1\na"), "t.expr:1:5: undefined name 'a'");
    EXPECT_EQ(error_of("b = c\nc = 1\nb"),
              "t.expr:1:5: undefined name 'c'");  // use before definition
    EXPECT_EQ(error_of("min(x)"), "t.expr:1:1: 'min' takes 2 arguments, got 1");
    EXPECT_EQ(error_of("sqrt(x, y)"), "t.expr:1:1: 'sqrt' takes 1 argument, got 2");
    EXPECT_EQ(error_of("1 + sqrt x"), "t.expr:1:10: expected '(' after function 'sqrt', found 'x'");
    EXPECT_EQ(error_of("x^-2"),
              "t.expr:1:3: expected a non-negative integer literal after '^', found '-'");
    EXPECT_EQ(error_of("x^1.5"),
              "t.expr:1:3: expected a non-negative integer literal after '^', found '1.5'");
    EXPECT_EQ(error_of("x^2^3"),
              "t.expr:1:4: chained '^' is ambiguous; use parentheses, e.g. (x^2)^3");
    EXPECT_EQ(error_of("x^99999999999"), "t.expr:1:3: exponent '99999999999' is too large");
    EXPECT_EQ(error_of("x @ y"), "t.expr:1:3: unexpected character '@'");
    EXPECT_EQ(error_of("2 x"), "t.expr:1:3: expected an operator or end of line, found 'x'");
    EXPECT_EQ(error_of("1e400"), "t.expr:1:1: number '1e400' is out of the range of double");
    EXPECT_EQ(error_of("1e+"),
              "t.expr:1:2: malformed number '1e+': expected digits in the exponent");
    EXPECT_EQ(error_of("inf"), "t.expr:1:1: undefined name 'inf'");
    EXPECT_EQ(error_of("x * * y"), "t.expr:1:5: expected an expression, found '*'");
    EXPECT_EQ(error_of("+x"), "t.expr:1:1: expected an expression, found '+'");
    EXPECT_EQ(error_of("x )"), "t.expr:1:3: expected an operator or end of line, found ')'");
    EXPECT_EQ(error_of(""), "t.expr:1:1: expected an expression (the input is empty)");
    EXPECT_EQ(error_of("# only a comment\n"),
              "t.expr:2:1: expected an expression (the input is empty)");
    EXPECT_EQ(error_of("a = x\n"),
              "t.expr:2:1: expected a final expression defining f after the bindings");
    EXPECT_EQ(error_of("x\ny\n"),
              "t.expr:1:1: the expression defining f must be the last statement; name "
              "intermediate values with 'name = ...'");
    EXPECT_EQ(error_of("x = "), "t.expr:1:1: cannot bind 'x': the name is reserved");
    EXPECT_EQ(error_of("a = \na"), "t.expr:1:5: expected an expression, found end of line");
}

TEST(Parser, InputErrorCarriesItsParts) {
    try {
        parse_expr("y +\n", "scene.expr");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "scene.expr");
        EXPECT_EQ(e.line(), 1);
        EXPECT_EQ(e.column(), 4);
        EXPECT_EQ(e.message(), "expected an expression, found end of line");
    }
    try {
        parse_expr_file("/nonexistent/dir/scene.expr");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.line(), 0);
        EXPECT_THAT(e.what(), HasSubstr("/nonexistent/dir/scene.expr: cannot open file"));
    }
}

TEST(Parser, DeepNestingIsAnErrorNotACrash) {
    const std::string deep = std::string(10000, '(') + "x" + std::string(10000, ')');
    const std::string e = error_of(deep);
    EXPECT_THAT(e, HasSubstr("t.expr:1:"));
    EXPECT_THAT(e, HasSubstr("nested deeper than"));
    std::string calls;
    for (int i = 0; i < 10000; ++i) calls += "sin(";
    calls += "x" + std::string(10000, ')');
    EXPECT_THAT(error_of(calls), HasSubstr("nested deeper than"));
    // Within the limit it parses.
    const std::string ok = std::string(200, '(') + "x" + std::string(200, ')');
    EXPECT_EQ(out(parse_expr(ok)).op, Op::VarX);
}

TEST(Parser, LongFlatInputsNeedNoRecursion) {
    std::string sum = "x";
    for (int i = 0; i < 100000; ++i) sum += " + y";
    const Graph g = parse_expr(sum);
    EXPECT_EQ(g.topological_order().size(), 100002u);
    EXPECT_EQ(eval(g, 1, 1, 0), 100001.0);
    const std::string negs = std::string(100001, '-') + "x";  // odd count: −x
    EXPECT_EQ(out(parse_expr(negs)).op, Op::Neg);
}

// print → parse keeps the structure: the re-parsed graph prints the same text and has as many
// reachable nodes; it also evaluates to the same values.
void expect_round_trip(const Graph& g) {
    const std::string text = print_expr(g);
    Graph h;
    ASSERT_NO_THROW(h = parse_expr(text, "printed")) << text.substr(0, 2000);
    EXPECT_EQ(print_expr(h), text);
    EXPECT_EQ(h.topological_order().size(), g.topological_order().size());
    for (double p : {-0.75, 0.3, 1.7}) {
        const double a = eval(g, p, 0.5 - p, p * p);
        const double b = eval(h, p, 0.5 - p, p * p);
        if (std::isnan(a)) {
            EXPECT_TRUE(std::isnan(b));
        } else {
            EXPECT_EQ(a, b);
        }
    }
}

TEST(Printer, RoundTripsExpressions) {
    for (const char* text : {
             "x",
             "-x^2",
             "0.1 + 0.2",
             "x - (y - z)",
             "x / (y / z)",
             "x - -y",
             "-(x + y)",
             "-(x * y)",
             "(x + 1)^3 * (y - 2)^2",
             "(-1.1)^3 + x",
             "x * -0 + x * 0 + 1e-300 * y + 123456789012345680000 * z",
             "x^0 + sqrt(x)^5 - abs(-x) / exp(y) + log(z) * sin(x) - cos(y)",
             "r2 = x^2 + y^2 + z^2\nmin(sqrt(r2) - 1, max(r2, z + 0.5))",
             "a = x * y\nb = a + a\nc = b * b\nc - a",
             "0.30000000000000004 * x - 0.1 * y",
         }) {
        SCOPED_TRACE(text);
        expect_round_trip(parse_expr(text));
    }
}

TEST(Printer, SharedNodesBecomeBindings) {
    const Graph g = parse_expr("a = sqrt(x + y)\na * exp(a) + a");
    const std::string text = print_expr(g);
    // Operands of + and * are in a canonical order that is arbitrary but fixed: accept either.
    EXPECT_THAT(
        text,
        ::testing::AnyOf(
            "t0 = sqrt(x + y)\nt0 * exp(t0) + t0\n", "t0 = sqrt(y + x)\nt0 * exp(t0) + t0\n",
            "t0 = sqrt(x + y)\nt0 + t0 * exp(t0)\n", "t0 = sqrt(y + x)\nt0 + t0 * exp(t0)\n",
            "t0 = sqrt(x + y)\nexp(t0) * t0 + t0\n", "t0 = sqrt(y + x)\nexp(t0) * t0 + t0\n",
            "t0 = sqrt(x + y)\nt0 + exp(t0) * t0\n", "t0 = sqrt(y + x)\nt0 + exp(t0) * t0\n"));
}

TEST(Printer, DeepChainsStayWithinTheNestingLimit) {
    Graph g;
    NodeId n = g.var(0);
    for (int i = 0; i < 20000; ++i) n = g.unary(Op::Sin, g.binary(Op::Mul, n, g.var(1)));
    g.set_output(n);
    expect_round_trip(g);
}

TEST(Printer, RoundTripsEveryModel) {
    const std::filesystem::path dir = std::filesystem::path(CERTRAY_TEST_DATA) / "models";
    int count = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
        if (entry.path().extension() != ".vm") continue;
        SCOPED_TRACE(entry.path().string());
        expect_round_trip(import_vm_file(entry.path()));
        ++count;
    }
    EXPECT_EQ(count, 11);
}

}  // namespace
}  // namespace certray::expr
