// expr/load.h — reading a scene file into a Graph, by its extension (.expr, .vm, .txt, .json).
#pragma once

#include <string>

#include "expr/graph.h"

namespace certray::expr {

/// Reads `path` as the .expr language (extension .expr), the Fidget .vm format (extension .vm),
/// a blob particle file with the reference parameters (extension .txt, expr/scene_import.h) or a
/// Lipschitz-Pruning JSON CSG tree (extension .json; its bounds: import_csg_json_file).
/// Throws certray::InputError naming the file (and line and column for syntax errors).
Graph load_graph_file(const std::string& path);

}  // namespace certray::expr
