// expr/builder.h — a C++ builder for expr::Graph: write f with ordinary operators.
//
//   expr::Graph g;
//   auto [x, y, z] = expr::vars(g);
//   auto f = sqrt(x * x + y * y + z * z) - 1.0;
//   g.set_output(f.id);
//
// Every operation goes through Graph::constant/unary/binary/pow, so the result is deduplicated and
// simplified exactly as parsed or imported expressions are. Combining handles of two different
// graphs throws std::invalid_argument.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>

#include "expr/graph.h"

namespace certray::expr {

/// A handle to a node of a Graph; a cheap value type. The Graph must outlive it.
struct Expr {
    Graph* graph = nullptr;
    NodeId id;
};

/// The handles of x, y and z in `g`: `auto [x, y, z] = vars(g);`.
inline std::array<Expr, 3> vars(Graph& g) {
    return {Expr{&g, g.var(0)}, Expr{&g, g.var(1)}, Expr{&g, g.var(2)}};
}

/// A handle to the constant `value` in `g` (finite; see Graph::constant).
inline Expr constant(Graph& g, double value) { return Expr{&g, g.constant(value)}; }

namespace detail {

inline Graph& same_graph(const Expr& a, const Expr& b) {
    if (a.graph == nullptr || a.graph != b.graph) {
        throw std::invalid_argument("expr::Expr: operands belong to different graphs");
    }
    return *a.graph;
}
inline Graph& graph_of(const Expr& a) {
    if (a.graph == nullptr) throw std::invalid_argument("expr::Expr: empty handle");
    return *a.graph;
}
inline Expr binary(Op op, const Expr& a, const Expr& b) {
    Graph& g = same_graph(a, b);
    return Expr{&g, g.binary(op, a.id, b.id)};
}
inline Expr binary(Op op, const Expr& a, double b) {
    Graph& g = graph_of(a);
    return Expr{&g, g.binary(op, a.id, g.constant(b))};
}
inline Expr binary(Op op, double a, const Expr& b) {
    Graph& g = graph_of(b);
    return Expr{&g, g.binary(op, g.constant(a), b.id)};
}
inline Expr unary(Op op, const Expr& a) {
    Graph& g = graph_of(a);
    return Expr{&g, g.unary(op, a.id)};
}

}  // namespace detail

/// a + b
inline Expr operator+(const Expr& a, const Expr& b) { return detail::binary(Op::Add, a, b); }
/// a + b
inline Expr operator+(const Expr& a, double b) { return detail::binary(Op::Add, a, b); }
/// a + b
inline Expr operator+(double a, const Expr& b) { return detail::binary(Op::Add, a, b); }
/// a − b
inline Expr operator-(const Expr& a, const Expr& b) { return detail::binary(Op::Sub, a, b); }
/// a − b
inline Expr operator-(const Expr& a, double b) { return detail::binary(Op::Sub, a, b); }
/// a − b
inline Expr operator-(double a, const Expr& b) { return detail::binary(Op::Sub, a, b); }
/// a · b
inline Expr operator*(const Expr& a, const Expr& b) { return detail::binary(Op::Mul, a, b); }
/// a · b
inline Expr operator*(const Expr& a, double b) { return detail::binary(Op::Mul, a, b); }
/// a · b
inline Expr operator*(double a, const Expr& b) { return detail::binary(Op::Mul, a, b); }
/// a / b
inline Expr operator/(const Expr& a, const Expr& b) { return detail::binary(Op::Div, a, b); }
/// a / b
inline Expr operator/(const Expr& a, double b) { return detail::binary(Op::Div, a, b); }
/// a / b
inline Expr operator/(double a, const Expr& b) { return detail::binary(Op::Div, a, b); }
/// −a
inline Expr operator-(const Expr& a) { return detail::unary(Op::Neg, a); }

/// √a
inline Expr sqrt(const Expr& a) { return detail::unary(Op::Sqrt, a); }
/// |a|
inline Expr abs(const Expr& a) { return detail::unary(Op::Abs, a); }
/// a²
inline Expr square(const Expr& a) { return detail::unary(Op::Square, a); }
/// eᵃ
inline Expr exp(const Expr& a) { return detail::unary(Op::Exp, a); }
/// ln a
inline Expr log(const Expr& a) { return detail::unary(Op::Log, a); }
/// sin a
inline Expr sin(const Expr& a) { return detail::unary(Op::Sin, a); }
/// cos a
inline Expr cos(const Expr& a) { return detail::unary(Op::Cos, a); }
/// min(a, b)
inline Expr min(const Expr& a, const Expr& b) { return detail::binary(Op::Min, a, b); }
/// min(a, b)
inline Expr min(const Expr& a, double b) { return detail::binary(Op::Min, a, b); }
/// min(a, b)
inline Expr min(double a, const Expr& b) { return detail::binary(Op::Min, a, b); }
/// max(a, b)
inline Expr max(const Expr& a, const Expr& b) { return detail::binary(Op::Max, a, b); }
/// max(a, b)
inline Expr max(const Expr& a, double b) { return detail::binary(Op::Max, a, b); }
/// max(a, b)
inline Expr max(double a, const Expr& b) { return detail::binary(Op::Max, a, b); }
/// ⌊a⌋, ⌈a⌉, a rounded half away from 0 (Fidget's floor, ceil, round)
inline Expr floor(const Expr& a) { return detail::unary(Op::Floor, a); }
inline Expr ceil(const Expr& a) { return detail::unary(Op::Ceil, a); }
inline Expr round(const Expr& a) { return detail::unary(Op::Round, a); }
/// tan a, asin a, acos a, atan a, 1/a
inline Expr tan(const Expr& a) { return detail::unary(Op::Tan, a); }
inline Expr asin(const Expr& a) { return detail::unary(Op::Asin, a); }
inline Expr acos(const Expr& a) { return detail::unary(Op::Acos, a); }
inline Expr atan(const Expr& a) { return detail::unary(Op::Atan, a); }
inline Expr recip(const Expr& a) { return detail::unary(Op::Recip, a); }
/// Fidget's not: 1 if a = 0, else 0
inline Expr logic_not(const Expr& a) { return detail::unary(Op::Not, a); }
/// atan2(y, x), the angle of (x, y) in (−π, π]
inline Expr atan2(const Expr& y, const Expr& x) { return detail::binary(Op::Atan2, y, x); }
/// Fidget's compare: −1, 0, 1 as a < b, a = b, a > b
inline Expr compare(const Expr& a, const Expr& b) { return detail::binary(Op::Compare, a, b); }
/// a − |b|·⌊a/|b|⌋ (Euclidean remainder)
inline Expr mod(const Expr& a, const Expr& b) { return detail::binary(Op::Mod, a, b); }
/// a − |b|·⌊a/|b|⌋ (Euclidean remainder)
inline Expr mod(const Expr& a, double b) { return detail::binary(Op::Mod, a, b); }
/// Fidget's and: a if a = 0, else b; or: a if a ≠ 0, else b
inline Expr logic_and(const Expr& a, const Expr& b) { return detail::binary(Op::And, a, b); }
inline Expr logic_or(const Expr& a, const Expr& b) { return detail::binary(Op::Or, a, b); }
/// aⁿ for a non-negative integer n
inline Expr pow(const Expr& a, unsigned n) {
    Graph& g = detail::graph_of(a);
    return Expr{&g, g.pow(a.id, static_cast<std::uint32_t>(n))};
}

}  // namespace certray::expr
