// expr/load.h — reading a scene file into a Graph, by its extension (.expr or .vm).
#pragma once

#include <string>

#include "expr/graph.h"

namespace certray::expr {

/// Reads `path` as the .expr language (extension .expr) or the Fidget .vm format (extension .vm).
/// Throws certray::InputError naming the file (and line and column for syntax errors).
Graph load_graph_file(const std::string& path);

}  // namespace certray::expr
