// expr/graph.cpp — hash-consing, canonical child order and exact-only simplification of the DAG.
#include "expr/graph.h"

#include <bit>
#include <cfenv>
#include <cmath>
#include <stdexcept>
#include <string>

#include "interval/interval.h"
#include "interval/number.h"
namespace certray::expr {
namespace detail {
namespace {

// Results smaller than this in magnitude are not folded: below it the residual of a product,
// quotient or square root may itself underflow, and then a zero residual proves nothing.
constexpr double kTiny = 0x1p-900;

// TwoSum (Knuth): s + e = a + b exactly, so a + b is representable iff e == 0.
bool exact_sum(double a, double b, double& out) {
    const double s = a + b;
    if (!std::isfinite(s)) return false;
    const double bp = s - a;
    const double ap = s - bp;
    const double e = (a - ap) + (b - bp);
    if (e != 0.0) return false;
    out = s;
    return true;
}

// TwoProduct with fma: p + fma(a, b, −p) = a·b exactly while nothing underflows.
bool exact_product(double a, double b, double& out) {
    const double p = a * b;
    if (!std::isfinite(p)) return false;
    if (a == 0.0 || b == 0.0) {
        out = p;  // ±0, exact
        return true;
    }
    if (std::fabs(p) < kTiny) return false;
    if (std::fma(a, b, -p) != 0.0) return false;
    out = p;
    return true;
}

// q = a/b is exact iff the remainder a − q·b (representable without underflow) is zero.
bool exact_quotient(double a, double b, double& out) {
    if (b == 0.0) return false;
    const double q = a / b;
    if (!std::isfinite(q)) return false;
    if (a == 0.0) {
        out = q;
        return true;
    }
    if (std::fabs(q) < kTiny || std::fabs(a) < kTiny) return false;
    if (std::fma(q, b, -a) != 0.0) return false;
    out = q;
    return true;
}

// r = √c is exact iff r·r − c == 0 (c ≥ 0).
bool exact_sqrt(double c, double& out) {
    if (!(c >= 0.0)) return false;
    const double r = std::sqrt(c);
    if (c != 0.0) {
        if (c < kTiny) return false;
        if (std::fma(r, r, -c) != 0.0) return false;
    }
    out = r;
    return true;
}

// cⁿ by repeated exact products; terminates quickly because |c| ∉ {0, 1} overflows, underflows
// below kTiny or becomes inexact within ~1100 steps.
bool exact_power(double c, std::uint32_t n, double& out) {
    if (n == 0) {
        out = 1.0;
        return true;
    }
    if (c == 0.0 || c == 1.0) {
        out = (n % 2 == 1) ? c : std::fabs(c);
        return true;
    }
    if (c == -1.0) {
        out = (n % 2 == 1) ? -1.0 : 1.0;
        return true;
    }
    double r = c;
    for (std::uint32_t i = 1; i < n; ++i) {
        if (!exact_product(r, c, r)) return false;
    }
    out = r;
    return true;
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    // splitmix64 finaliser over a running combination
    std::uint64_t z = h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2));
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

}  // namespace
}  // namespace detail

std::size_t Graph::NodeHash::operator()(const Node& n) const noexcept {
    std::uint64_t h = static_cast<std::uint64_t>(n.op);
    h = detail::mix(h, n.a.value);
    h = detail::mix(h, n.b.value);
    h = detail::mix(h, std::bit_cast<std::uint64_t>(n.constant));
    h = detail::mix(h, n.exponent);
    return static_cast<std::size_t>(h);
}

bool Graph::NodeEqual::operator()(const Node& l, const Node& r) const noexcept {
    return l.op == r.op && l.a == r.a && l.b == r.b &&
           std::bit_cast<std::uint64_t>(l.constant) == std::bit_cast<std::uint64_t>(r.constant) &&
           l.exponent == r.exponent;
}

void Graph::check_child(NodeId id) const {
    if (!id.valid() || id.value >= nodes_.size()) {
        throw std::invalid_argument("expr::Graph: invalid node id " + std::to_string(id.value));
    }
}

NodeId Graph::insert(const Node& n) {
    if (auto it = index_.find(n); it != index_.end()) return it->second;
    if (nodes_.size() >= UINT32_MAX - 1) throw std::length_error("expr::Graph: too many nodes");
    const NodeId id{static_cast<std::uint32_t>(nodes_.size())};
    // The shape hash depends only on the structure below the node, never on ids.
    std::uint64_t s = detail::mix(0x5eedULL, static_cast<std::uint64_t>(n.op));
    s = detail::mix(s, n.a.valid() ? shape_[n.a.value] : 0);
    s = detail::mix(s, n.b.valid() ? shape_[n.b.value] : 0);
    s = detail::mix(s, std::bit_cast<std::uint64_t>(n.constant));
    s = detail::mix(s, n.exponent);
    nodes_.push_back(n);
    shape_.push_back(s);
    index_.emplace(n, id);
    return id;
}

NodeId Graph::constant(double value) {
    if (!std::isfinite(value)) {
        throw std::invalid_argument("expr::Graph: a constant must be finite (got NaN or infinity)");
    }
    Node n;
    n.op = Op::Const;
    n.constant = value;
    return insert(n);
}

NodeId Graph::var(int axis) {
    Node n;
    switch (axis) {
        case 0:
            n.op = Op::VarX;
            break;
        case 1:
            n.op = Op::VarY;
            break;
        case 2:
            n.op = Op::VarZ;
            break;
        default:
            throw std::invalid_argument("expr::Graph: axis must be 0, 1 or 2");
    }
    return insert(n);
}

NodeId Graph::unary(Op op, NodeId a) {
    // The folds' error-free transformations and the comparisons with 0 and 1 are exact only in
    // round-to-nearest with subnormals kept: the same DAG whatever the caller's state.
    const NearestScope env;
    if (arity(op) != 1 || op == Op::Pow) {
        throw std::invalid_argument("expr::Graph::unary: not a unary op: " + std::string(name(op)));
    }
    check_child(a);
    const Node na = nodes_[a.value];  // a copy: insertion may reallocate nodes_
    const bool is_const = na.op == Op::Const;
    const double c = na.constant;
    double r = 0.0;
    switch (op) {
        case Op::Neg:
            if (is_const) return constant(-c);  // exact
            if (na.op == Op::Neg) return na.a;  // −(−x) = x
            break;
        case Op::Abs:
            if (is_const) return constant(std::fabs(c));        // exact
            if (na.op == Op::Neg) return unary(Op::Abs, na.a);  // |−x| = |x|
            if (na.op == Op::Abs) return a;                     // ||x|| = |x|
            break;
        case Op::Square:
            if (is_const && detail::exact_product(c, c, r)) return constant(r);
            if (na.op == Op::Neg || na.op == Op::Abs) return unary(Op::Square, na.a);  // (±x)² = x²
            break;
        case Op::Sqrt:
            if (is_const && detail::exact_sqrt(c, r)) return constant(r);
            break;
        case Op::Exp:
            if (is_const && c == 0.0) return constant(1.0);  // e⁰ = 1 exactly
            break;
        case Op::Log:
            if (is_const && c == 1.0) return constant(0.0);  // ln 1 = 0 exactly
            break;
        case Op::Sin:
            if (is_const && c == 0.0) return constant(c);  // sin(±0) = ±0
            break;
        case Op::Cos:
            if (is_const && c == 0.0) return constant(1.0);  // cos 0 = 1
            break;
        case Op::Floor:
            if (is_const) return constant(std::floor(c));  // exact
            break;
        case Op::Ceil:
            if (is_const) return constant(std::ceil(c));  // exact
            break;
        case Op::Round:
            if (is_const) return constant(std::round(c));  // exact
            break;
        case Op::Not:
            if (is_const) return constant(c == 0.0 ? 1.0 : 0.0);  // exact
            break;
        case Op::Tan:
        case Op::Asin:
        case Op::Atan:
            if (is_const && c == 0.0) return constant(c);  // f(±0) = ±0
            break;
        case Op::Acos:
            break;
        case Op::Recip:
            if (is_const && detail::exact_quotient(1.0, c, r)) return constant(r);
            break;
        case Op::Const:
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
        case Op::Add:
        case Op::Sub:
        case Op::Mul:
        case Op::Div:
        case Op::Min:
        case Op::Max:
        case Op::Pow:
        case Op::Atan2:
        case Op::Compare:
        case Op::Mod:
        case Op::And:
        case Op::Or:
            break;  // rejected above
    }
    Node n;
    n.op = op;
    n.a = a;
    return insert(n);
}

NodeId Graph::binary(Op op, NodeId a, NodeId b) {
    // The folds' error-free transformations and the comparisons with 0 and 1 are exact only in
    // round-to-nearest with subnormals kept: the same DAG whatever the caller's state.
    const NearestScope env;
    if (arity(op) != 2) {
        throw std::invalid_argument("expr::Graph::binary: not a binary op: " +
                                    std::string(name(op)));
    }
    check_child(a);
    check_child(b);
    if (is_commutative(op)) {
        // Order by structure first, so that the order does not depend on insertion history.
        const bool swap = shape_[a.value] != shape_[b.value] ? shape_[a.value] > shape_[b.value]
                                                             : a.value > b.value;
        if (swap) std::swap(a, b);
    }
    const Node na = nodes_[a.value];
    const Node nb = nodes_[b.value];
    const bool ca = na.op == Op::Const;
    const bool cb = nb.op == Op::Const;
    double r = 0.0;
    switch (op) {
        case Op::Add:
            if (ca && cb && detail::exact_sum(na.constant, nb.constant, r)) return constant(r);
            if (cb && nb.constant == 0.0) return a;  // x + (±0) = x as a real function
            if (ca && na.constant == 0.0) return b;
            break;
        case Op::Sub:
            if (ca && cb && detail::exact_sum(na.constant, -nb.constant, r)) return constant(r);
            if (cb && nb.constant == 0.0) return a;                  // x − 0 = x
            if (ca && na.constant == 0.0) return unary(Op::Neg, b);  // 0 − x = −x
            break;
        case Op::Mul:
            if (ca && cb && detail::exact_product(na.constant, nb.constant, r)) {
                return constant(r);
            }
            if (cb && nb.constant == 1.0) return a;  // x·1 = x
            if (ca && na.constant == 1.0) return b;
            if (cb && nb.constant == -1.0) return unary(Op::Neg, a);  // x·(−1) = −x
            if (ca && na.constant == -1.0) return unary(Op::Neg, b);
            // x·x = x²: the same real function and the same double; as a Square it is seen as
            // a sum-of-squares term by the Lipschitz root forms (interval/grad_bound.h).
            if (a.value == b.value) return unary(Op::Square, a);
            break;
        case Op::Div:
            if (ca && cb && detail::exact_quotient(na.constant, nb.constant, r)) {
                return constant(r);
            }
            if (cb && nb.constant == 1.0) return a;                   // x/1 = x
            if (cb && nb.constant == -1.0) return unary(Op::Neg, a);  // x/(−1) = −x
            break;
        case Op::Min:
            if (ca && cb) return constant(std::fmin(na.constant, nb.constant));  // exact
            if (a == b) return a;                                                // min(x, x) = x
            break;
        case Op::Max:
            if (ca && cb) return constant(std::fmax(na.constant, nb.constant));  // exact
            if (a == b) return a;
            break;
        case Op::Compare:
            if (ca && cb) return constant(certray::compare(na.constant, nb.constant));  // exact
            break;
        case Op::And:
            if (ca) return na.constant == 0.0 ? a : b;  // and(0, y) = 0, and(c ≠ 0, y) = y
            break;
        case Op::Or:
            if (ca) return na.constant != 0.0 ? a : b;  // or(c ≠ 0, y) = c, or(0, y) = y
            break;
        case Op::Atan2:
        case Op::Mod:
            break;
        case Op::Const:
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
        case Op::Neg:
        case Op::Abs:
        case Op::Square:
        case Op::Sqrt:
        case Op::Exp:
        case Op::Log:
        case Op::Sin:
        case Op::Cos:
        case Op::Pow:
        case Op::Floor:
        case Op::Ceil:
        case Op::Round:
        case Op::Tan:
        case Op::Asin:
        case Op::Acos:
        case Op::Atan:
        case Op::Recip:
        case Op::Not:
            break;  // rejected above
    }
    Node n;
    n.op = op;
    n.a = a;
    n.b = b;
    return insert(n);
}

NodeId Graph::pow(NodeId a, std::uint32_t n) {
    // The folds' error-free transformations and the comparisons with 0 and 1 are exact only in
    // round-to-nearest with subnormals kept: the same DAG whatever the caller's state.
    const NearestScope env;
    check_child(a);
    if (n == 1) return a;
    if (n == 2) return unary(Op::Square, a);
    const Node na = nodes_[a.value];
    double r = 0.0;
    if (na.op == Op::Const && detail::exact_power(na.constant, n, r)) {
        return constant(r);
    }
    Node node;
    node.op = Op::Pow;
    node.a = a;
    node.exponent = n;
    return insert(node);
}

NodeId Graph::add(Op op, NodeId a, NodeId b, double value, std::uint32_t n) {
    switch (op) {
        case Op::Const:
            return constant(value);
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
            return var(static_cast<int>(op) - static_cast<int>(Op::VarX));
        case Op::Pow:
            return pow(a, n);
        default:
            return arity(op) == 1 ? unary(op, a) : binary(op, a, b);
    }
}

NodeId Graph::copy(const Graph& from, NodeId root, const std::array<NodeId, 3>& vars) {
    std::unordered_map<std::uint32_t, NodeId> map;
    for (const NodeId id : from.topological_order(root)) {
        const Node& n = from.node(id);
        const bool is_var = n.op == Op::VarX || n.op == Op::VarY || n.op == Op::VarZ;
        map[id.value] =
            is_var ? vars[static_cast<int>(n.op) - static_cast<int>(Op::VarX)]
                   : add(n.op, n.a.valid() ? map.at(n.a.value) : NodeId{},
                         n.b.valid() ? map.at(n.b.value) : NodeId{}, n.constant, n.exponent);
    }
    return map.at(root.value);
}

void Graph::set_output(NodeId id) {
    check_child(id);
    output_ = id;
}

std::vector<NodeId> Graph::topological_order(NodeId root) const {
    std::vector<NodeId> order;
    if (!root.valid()) return order;
    check_child(root);
    // Children have smaller ids than parents: one descending sweep marks everything reachable.
    std::vector<char> reached(root.value + 1, 0);
    reached[root.value] = 1;
    for (std::uint32_t i = root.value + 1; i-- > 0;) {
        if (!reached[i]) continue;
        const Node& n = nodes_[i];
        if (n.a.valid()) reached[n.a.value] = 1;
        if (n.b.valid()) reached[n.b.value] = 1;
    }
    for (std::uint32_t i = 0; i <= root.value; ++i) {
        if (reached[i]) order.push_back(NodeId{i});
    }
    return order;
}

std::vector<NodeId> Graph::topological_order() const { return topological_order(output_); }

bool Graph::uses_var(int axis) const {
    Op want = Op::VarX;
    switch (axis) {
        case 0:
            want = Op::VarX;
            break;
        case 1:
            want = Op::VarY;
            break;
        case 2:
            want = Op::VarZ;
            break;
        default:
            throw std::invalid_argument("expr::Graph::uses_var: axis must be 0, 1 or 2");
    }
    for (NodeId id : topological_order()) {
        if (nodes_[id.value].op == want) return true;
    }
    return false;
}

}  // namespace certray::expr
