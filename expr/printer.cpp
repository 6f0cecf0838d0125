// expr/printer.cpp — iterative printer of the DAG as .expr text with bindings for shared nodes.
#include "expr/printer.h"

#include <charconv>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <utility>
#include <vector>

#include "expr/parser.h"

namespace certray::expr {
namespace {

// Deepest chain of inline (unbound) operations before a binding is forced; far below kMaxNesting.
constexpr int kMaxInlineDepth = 48;
static_assert(kMaxInlineDepth < kMaxNesting);

// Binding strength of a node as printed: 1 sums, 2 products, 3 negation, 4 powers, 5 atoms.
int precedence(const Node& n) {
    switch (n.op) {
        case Op::Add:
        case Op::Sub:
            return 1;
        case Op::Mul:
        case Op::Div:
            return 2;
        case Op::Neg:
            return 3;
        case Op::Square:
        case Op::Pow:
            return 4;
        case Op::Const:
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
        case Op::Abs:
        case Op::Sqrt:
        case Op::Exp:
        case Op::Log:
        case Op::Sin:
        case Op::Cos:
        case Op::Min:
        case Op::Max:
        case Op::Floor:
        case Op::Ceil:
        case Op::Round:
        case Op::Tan:
        case Op::Asin:
        case Op::Acos:
        case Op::Atan:
        case Op::Recip:
        case Op::Not:
        case Op::Atan2:
        case Op::Compare:
        case Op::Mod:
        case Op::And:
        case Op::Or:
            return 5;
    }
    return 5;
}

// "name(" of a function-call op, for the printer's text pieces (static storage).
const char* fn_open(Op op) {
    switch (op) {
        case Op::Floor:
            return "floor(";
        case Op::Ceil:
            return "ceil(";
        case Op::Round:
            return "round(";
        case Op::Tan:
            return "tan(";
        case Op::Asin:
            return "asin(";
        case Op::Acos:
            return "acos(";
        case Op::Atan:
            return "atan(";
        case Op::Recip:
            return "recip(";
        case Op::Not:
            return "not(";
        case Op::Atan2:
            return "atan2(";
        case Op::Compare:
            return "compare(";
        case Op::Mod:
            return "mod(";
        case Op::And:
            return "and(";
        case Op::Or:
            return "or(";
        default:
            return "?(";  // not a function-call op
    }
}

std::string format_constant(double c) {
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof buf, std::fabs(c));
    std::string digits(buf, res.ptr);
    return std::signbit(c) ? "(-" + digits + ")" : digits;
}

class Printer {
  public:
    explicit Printer(const Graph& g) : g_(g) {}

    std::string run() {
        const NodeId root = g_.output();
        if (!root.valid()) throw std::invalid_argument("print_expr: the graph has no output");
        const std::vector<NodeId> post = postorder(root);
        // Use counts from reachable parents.
        uses_.assign(root.value + 1, 0);
        for (NodeId id : post) {
            const Node& n = g_.node(id);
            if (n.a.valid()) ++uses_[n.a.value];
            if (n.b.valid()) ++uses_[n.b.value];
        }
        names_.assign(root.value + 1, std::string());
        std::vector<int> depth(root.value + 1, 0);
        std::vector<NodeId> bound;
        for (NodeId id : post) {
            const Node& n = g_.node(id);
            if (arity(n.op) == 0) continue;
            int d = 0;
            for (NodeId c : {n.a, n.b}) {
                if (c.valid() && names_[c.value].empty()) d = std::max(d, depth[c.value]);
            }
            depth[id.value] = d + 1;
            if (id != root && (uses_[id.value] > 1 || depth[id.value] > kMaxInlineDepth)) {
                names_[id.value] = std::string(1, 't').append(std::to_string(bound.size()));
                bound.push_back(id);
            }
        }
        for (NodeId id : bound) {
            out_ += names_[id.value];
            out_ += " = ";
            emit(id);
            out_ += '\n';
        }
        emit(root);
        out_ += '\n';
        return std::move(out_);
    }

  private:
    // Depth-first postorder from the root, children a then b: depends on structure only, not ids.
    std::vector<NodeId> postorder(NodeId root) const {
        std::vector<NodeId> order;
        std::vector<char> state(root.value + 1, 0);  // 0 new, 1 open, 2 done
        std::vector<NodeId> stack{root};
        while (!stack.empty()) {
            const NodeId id = stack.back();
            char& s = state[id.value];
            if (s == 2) {
                stack.pop_back();
                continue;
            }
            const Node& n = g_.node(id);
            if (s == 0) {
                s = 1;
                if (n.b.valid() && state[n.b.value] == 0) stack.push_back(n.b);
                if (n.a.valid() && state[n.a.value] == 0) stack.push_back(n.a);
                continue;
            }
            s = 2;
            order.push_back(id);
            stack.pop_back();
        }
        return order;
    }

    struct Task {
        NodeId id;         // a node to print, or invalid for literal text
        int min_prec = 0;  // the node needs parentheses below this strength
        const char* text = nullptr;
        bool expand = false;  // print the definition even if the node is bound
    };

    // Prints the definition of `top` with an explicit stack of tasks.
    void emit(NodeId top) {
        std::vector<Task> stack{{top, 0, nullptr, true}};
        std::vector<Task> pieces;
        while (!stack.empty()) {
            const Task t = stack.back();
            stack.pop_back();
            if (!t.id.valid()) {
                out_ += t.text;
                continue;
            }
            if (!t.expand && !names_[t.id.value].empty()) {
                out_ += names_[t.id.value];
                continue;
            }
            const Node& n = g_.node(t.id);
            pieces.clear();
            auto child = [](NodeId c, int p) { return Task{c, p, nullptr, false}; };
            auto text = [](const char* s) { return Task{NodeId{}, 0, s, false}; };
            auto call = [&](const char* open) {
                pieces.push_back(text(open));
                pieces.push_back(child(n.a, 0));
                if (n.b.valid()) {
                    pieces.push_back(text(", "));
                    pieces.push_back(child(n.b, 0));
                }
                pieces.push_back(text(")"));
            };
            switch (n.op) {
                case Op::Const:
                    out_ += format_constant(n.constant);
                    continue;
                case Op::VarX:
                    out_ += 'x';
                    continue;
                case Op::VarY:
                    out_ += 'y';
                    continue;
                case Op::VarZ:
                    out_ += 'z';
                    continue;
                case Op::Neg:
                    pieces.push_back(text("-"));
                    pieces.push_back(child(n.a, 3));
                    break;
                case Op::Abs:
                    call("abs(");
                    break;
                case Op::Sqrt:
                    call("sqrt(");
                    break;
                case Op::Exp:
                    call("exp(");
                    break;
                case Op::Log:
                    call("log(");
                    break;
                case Op::Sin:
                    call("sin(");
                    break;
                case Op::Cos:
                    call("cos(");
                    break;
                case Op::Min:
                    call("min(");
                    break;
                case Op::Max:
                    call("max(");
                    break;
                case Op::Floor:
                case Op::Ceil:
                case Op::Round:
                case Op::Tan:
                case Op::Asin:
                case Op::Acos:
                case Op::Atan:
                case Op::Recip:
                case Op::Not:
                case Op::Atan2:
                case Op::Compare:
                case Op::Mod:
                case Op::And:
                case Op::Or:
                    call(fn_open(n.op));
                    break;
                case Op::Square:
                    pieces.push_back(child(n.a, 5));
                    pieces.push_back(text("^2"));
                    break;
                case Op::Pow:
                    pieces.push_back(child(n.a, 5));
                    exponents_.push_back(std::string(1, '^').append(std::to_string(n.exponent)));
                    pieces.push_back(text(exponents_.back().c_str()));
                    break;
                case Op::Add:
                case Op::Sub:
                    pieces.push_back(child(n.a, 1));
                    pieces.push_back(text(n.op == Op::Add ? " + " : " - "));
                    pieces.push_back(child(n.b, 2));
                    break;
                case Op::Mul:
                case Op::Div:
                    pieces.push_back(child(n.a, 2));
                    pieces.push_back(text(n.op == Op::Mul ? " * " : " / "));
                    pieces.push_back(child(n.b, 3));
                    break;
            }
            const bool parens = precedence(n) < t.min_prec;
            if (parens) stack.push_back(text(")"));
            for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) stack.push_back(*it);
            if (parens) stack.push_back(text("("));
        }
    }

    const Graph& g_;
    std::vector<int> uses_;
    std::vector<std::string> names_;     // binding name of a bound node, empty otherwise
    std::deque<std::string> exponents_;  // keeps "^n" texts alive while tasks point at them
    std::string out_;
};

}  // namespace

std::string print_expr(const Graph& g) { return Printer(g).run(); }

}  // namespace certray::expr
