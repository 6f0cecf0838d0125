// tests/support/graph_eval.h — a test-only evaluator of a Graph on doubles, independent of the
// library's tape and evaluator (a plain switch over the nodes), used to cross-check importers.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "expr/graph.h"

namespace certray::testing {

inline double eval_graph(const expr::Graph& g, double x, double y, double z) {
    std::vector<double> v(g.size());
    for (expr::NodeId id : g.topological_order()) {
        const expr::Node& n = g.node(id);
        const double a = n.a.valid() ? v[n.a.value] : 0.0;
        const double b = n.b.valid() ? v[n.b.value] : 0.0;
        double r = 0.0;
        switch (n.op) {
            case expr::Op::Const:
                r = n.constant;
                break;
            case expr::Op::VarX:
                r = x;
                break;
            case expr::Op::VarY:
                r = y;
                break;
            case expr::Op::VarZ:
                r = z;
                break;
            case expr::Op::Neg:
                r = -a;
                break;
            case expr::Op::Abs:
                r = std::fabs(a);
                break;
            case expr::Op::Square:
                r = a * a;
                break;
            case expr::Op::Sqrt:
                r = std::sqrt(a);
                break;
            case expr::Op::Exp:
                r = std::exp(a);
                break;
            case expr::Op::Log:
                r = std::log(a);
                break;
            case expr::Op::Sin:
                r = std::sin(a);
                break;
            case expr::Op::Cos:
                r = std::cos(a);
                break;
            case expr::Op::Add:
                r = a + b;
                break;
            case expr::Op::Sub:
                r = a - b;
                break;
            case expr::Op::Mul:
                r = a * b;
                break;
            case expr::Op::Div:
                r = a / b;
                break;
            case expr::Op::Min:
                r = std::fmin(a, b);
                break;
            case expr::Op::Max:
                r = std::fmax(a, b);
                break;
            case expr::Op::Floor:
                r = std::floor(a);
                break;
            case expr::Op::Ceil:
                r = std::ceil(a);
                break;
            case expr::Op::Round:
                r = std::round(a);
                break;
            case expr::Op::Tan:
                r = std::tan(a);
                break;
            case expr::Op::Asin:
                r = std::asin(a);
                break;
            case expr::Op::Acos:
                r = std::acos(a);
                break;
            case expr::Op::Atan:
                r = std::atan(a);
                break;
            case expr::Op::Recip:
                r = 1.0 / a;
                break;
            case expr::Op::Not:
                r = a == 0 ? 1.0 : 0.0;
                break;
            case expr::Op::Atan2:
                r = std::atan2(a, b);
                break;
            case expr::Op::Compare:
                r = a < b ? -1.0 : a > b ? 1.0 : a == b ? 0.0 : std::nan("");
                break;
            case expr::Op::Mod: {
                const double m = std::fmod(a, b);
                r = m < 0 ? m + std::fabs(b) : m;
                break;
            }
            case expr::Op::And:
                r = a == 0 ? a : b;
                break;
            case expr::Op::Or:
                r = a != 0 ? a : b;
                break;
            case expr::Op::Pow:
                r = 1.0;
                for (std::uint32_t k = 0; k < n.exponent; ++k) r *= a;
                break;
        }
        v[id.value] = r;
    }
    return v[g.output().value];
}

}  // namespace certray::testing
