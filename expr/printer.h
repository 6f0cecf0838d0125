// expr/printer.h — prints an expr::Graph as .expr text that parses back to the same graph.
//
// Contract: parse_expr(print_expr(g)) has the same structure as g below its output (same nodes
// after deduplication, same constants bit for bit), and print_expr of it is the same text. Nodes
// used more than once (and nodes that would nest too deeply) become bindings `t0 = ...`, `t1 = ...`
// in dependency order, so the text stays linear in the size of the DAG and within the parser's
// nesting limit. Constants are printed in the shortest form that reads back to the same double;
// negative constants in parentheses, e.g. `(-0.5)`. The walk is iterative: no recursion over the
// DAG.
#pragma once

#include <string>

#include "expr/graph.h"

namespace certray::expr {

/// The .expr text of `g` (bindings, then f on the last line). Throws std::invalid_argument if `g`
/// has no output.
std::string print_expr(const Graph& g);

}  // namespace certray::expr
