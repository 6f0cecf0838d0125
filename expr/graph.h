// expr/graph.h — expr::Graph: the hash-consed expression DAG, an arena of nodes addressed by
// NodeId.
//
// Contract: nodes are created only through constant/var/unary/binary/pow, which deduplicate them
// (structural hashing; constants compared by bit pattern) and apply only simplifications that keep
// the real function unchanged: constant folding only when the double result is exact (checked by
// error-free transformations, and only in round-to-nearest), x·1 → x, x+0 → x, x−0 → x, x/1 → x,
// −(−x) → x, x¹ → x, x² → square(x). Nothing that could make an undefined point defined is applied
// (x − x is not 0, x·0 is not 0, x⁰ is not 1). Children always have smaller ids than their parent,
// so ascending id order is a topological order; no method recurses over the DAG. Reference: Fidget
// (mkeeter/fidget) `Context`; docs/design.md "The flow of data".
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "expr/op.h"

namespace certray::expr {

/// Strong index of a node in a Graph.
struct NodeId {
    std::uint32_t value = UINT32_MAX;  ///< UINT32_MAX means "no node"

    constexpr NodeId() = default;
    constexpr explicit NodeId(std::uint32_t v) : value(v) {}
    /// True when this refers to a node (is not the "no node" id).
    constexpr bool valid() const noexcept { return value != UINT32_MAX; }
    friend constexpr bool operator==(NodeId, NodeId) = default;
    friend constexpr auto operator<=>(NodeId, NodeId) = default;
};

/// The "no node" id (an absent child, an unset output).
inline constexpr NodeId kNoNode{};

/// One node: an op, up to two children, and the constant (Const) or exponent (Pow).
struct Node {
    Op op = Op::Const;
    NodeId a;                    ///< first child (unary and binary ops, Pow)
    NodeId b;                    ///< second child (binary ops)
    double constant = 0.0;       ///< the value of a Const node; 0.0 otherwise
    std::uint32_t exponent = 0;  ///< the exponent of a Pow node; 0 otherwise
};

/// The expression DAG. Value type (copyable); not thread-safe for concurrent insertion.
class Graph {
  public:
    /// The node for the finite constant `value`. Throws std::invalid_argument for NaN or ±inf.
    /// -0.0 and 0.0 are different nodes (compared by bit pattern).
    NodeId constant(double value);
    /// The node for variable x (axis 0), y (1) or z (2). Throws std::invalid_argument otherwise.
    NodeId var(int axis);
    /// The node for a unary op (Neg Abs Square Sqrt Exp Log Sin Cos) applied to `a`, simplified.
    /// Throws std::invalid_argument for an op of another arity or an invalid child.
    NodeId unary(Op op, NodeId a);
    /// The node for a binary op (Add Sub Mul Div Min Max) applied to `a`, `b`, simplified.
    /// Throws std::invalid_argument for an op of another arity or an invalid child.
    NodeId binary(Op op, NodeId a, NodeId b);
    /// The node for aⁿ (n ≥ 0); n = 1 gives `a`, n = 2 gives square(a).
    NodeId pow(NodeId a, std::uint32_t n);

    /// The node op(a, b) through the constructors above (simplified and deduplicated): `value` is
    /// the constant of Const, `n` the exponent of Pow; unused operands are ignored.
    NodeId add(Op op, NodeId a, NodeId b, double value, std::uint32_t n);
    /// Copies the subexpression `root` of `from` into this graph, each variable (axis i) replaced
    /// by vars[i], a node of this graph; returns the copy of `root`. Iterative.
    NodeId copy(const Graph& from, NodeId root, const std::array<NodeId, 3>& vars);

    /// The node with id `id` (must be < size()).
    const Node& node(NodeId id) const { return nodes_.at(id.value); }
    /// Number of nodes in the arena (reachable from the output or not).
    std::size_t size() const noexcept { return nodes_.size(); }

    /// Sets the function f of this graph. Throws std::invalid_argument for an invalid id.
    void set_output(NodeId id);
    /// The function f; kNoNode until set_output is called.
    NodeId output() const noexcept { return output_; }

    /// True when variable `axis` (0 x, 1 y, 2 z) is reachable from the output.
    bool uses_var(int axis) const;

    /// The nodes reachable from `root`, children before parents (ascending id). Iterative.
    std::vector<NodeId> topological_order(NodeId root) const;
    /// The nodes reachable from the output, children before parents; empty if no output is set.
    std::vector<NodeId> topological_order() const;

  private:
    struct NodeHash {
        std::size_t operator()(const Node& n) const noexcept;
    };
    struct NodeEqual {
        bool operator()(const Node& l, const Node& r) const noexcept;
    };

    NodeId insert(const Node& n);
    void check_child(NodeId id) const;

    std::vector<Node> nodes_;
    std::vector<std::uint64_t>
        shape_;  ///< structural (Merkle) hash per node: orders commutative children
    std::unordered_map<Node, NodeId, NodeHash, NodeEqual> index_;
    NodeId output_;
};

}  // namespace certray::expr
