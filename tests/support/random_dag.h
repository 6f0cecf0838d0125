// tests/support/random_dag.h — RapidCheck generator of random expression DAGs.
//
// Every op appears; operands are drawn from all earlier nodes, so subexpressions are shared;
// constants include extreme magnitudes; the depth stays at most kMaxDepth.
#pragma once

#include <rapidcheck.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/op.h"
#include "expr/printer.h"
#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::expr {

/// How RapidCheck shows a failing graph: the .expr text.
inline void showValue(const Graph& g, std::ostream& os) { os << print_expr(g); }

}  // namespace certray::expr

namespace certray::testing {

inline constexpr int kMaxDepth = 12;

/// A random DAG with an output; `ops` is the number of non-leaf nodes requested. `smooth`: only
/// ops that are C¹ where defined (no abs, min, max), those expr/tangent.h has rules for.
inline rc::Gen<expr::Graph> gen_dag(int max_ops = 24, bool smooth = false) {
    return rc::gen::exec([max_ops, smooth] {
        using expr::Op;
        expr::Graph g;
        std::vector<expr::NodeId> nodes;
        std::vector<int> depth;
        auto add = [&](expr::NodeId id, int d) {
            nodes.push_back(id);
            depth.push_back(d);
        };
        for (int axis = 0; axis < 3; ++axis) add(g.var(axis), 0);
        const int constants = *rc::gen::inRange(1, 4);
        for (int i = 0; i < constants; ++i) {
            const double c = *rc::gen::oneOf(
                rc::gen::element(0.5, 1.0, 2.0, -3.0, 0.1, 1e-300, 1e300, -7.25),
                rc::gen::map(rc::gen::inRange(-1000, 1000), [](int k) { return k / 8.0; }));
            add(g.constant(c), 0);
        }
        const int ops = *rc::gen::inRange(1, max_ops);
        static const std::vector<Op> kUnary = {Op::Neg, Op::Abs, Op::Square, Op::Sqrt, Op::Exp,
                                               Op::Log, Op::Sin, Op::Cos,    Op::Pow};
        static const std::vector<Op> kBinary = {Op::Add, Op::Sub, Op::Mul,
                                                Op::Div, Op::Min, Op::Max};
        static const std::vector<Op> kSmoothUnary = {Op::Neg, Op::Square, Op::Sqrt, Op::Exp,
                                                     Op::Log, Op::Sin,    Op::Cos,  Op::Pow};
        static const std::vector<Op> kSmoothBinary = {Op::Add, Op::Sub, Op::Mul, Op::Div};
        for (int i = 0; i < ops; ++i) {
            // Prefer recent nodes so the output depends on most of the graph.
            auto pick = [&] {
                const int n = static_cast<int>(nodes.size());
                const int lo = *rc::gen::element(0, std::max(0, n - 4));
                return *rc::gen::inRange(lo, n);
            };
            const int a = pick();
            if (*rc::gen::inRange(0, 3) == 0) {
                const Op op = *rc::gen::elementOf(smooth ? kSmoothUnary : kUnary);
                if (depth[a] + 1 > kMaxDepth) continue;
                const expr::NodeId id = op == Op::Pow ? g.pow(nodes[a], *rc::gen::inRange(0u, 6u))
                                                      : g.unary(op, nodes[a]);
                add(id, depth[a] + 1);
            } else {
                const int b = pick();
                const int d = std::max(depth[a], depth[b]) + 1;
                if (d > kMaxDepth) continue;
                add(g.binary(*rc::gen::elementOf(smooth ? kSmoothBinary : kBinary), nodes[a],
                             nodes[b]),
                    d);
            }
        }
        g.set_output(nodes.back());
        return g;
    });
}

/// Half the time (drawn), g's output f becomes f − f(o + s·d) for a drawn s in [tmin, tmax]
/// (finite, and when f is finite there): the level set through a point of the ray, so that random
/// rays hit about as often as they miss.
inline void maybe_through_the_ray(expr::Graph& g, const Ray& ray) {
    if (!*rc::gen::arbitrary<bool>() || !std::isfinite(ray.tmax)) return;
    const double s = ray.tmin + (ray.tmax - ray.tmin) * *rc::gen::inRange(0, 65) / 64.0;
    const double c = expr::eval<double>(
        expr::Tape(g), {ray.o[0] + s * ray.d[0], ray.o[1] + s * ray.d[1], ray.o[2] + s * ray.d[2]});
    if (std::isfinite(c)) g.set_output(g.binary(expr::Op::Sub, g.output(), g.constant(c)));
}

}  // namespace certray::testing
