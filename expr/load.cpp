// expr/load.cpp — dispatch on the file extension (.expr, .vm, .txt particles, .json CSG trees).
#include "expr/load.h"

#include <string_view>

#include "expr/input_error.h"
#include "expr/parser.h"
#include "expr/scene_import.h"
#include "expr/vm_import.h"

namespace certray::expr {

Graph load_graph_file(const std::string& path) {
    const std::string_view p(path);
    if (p.ends_with(".expr")) return parse_expr_file(path);
    if (p.ends_with(".vm")) return import_vm_file(path);
    if (p.ends_with(".txt")) return import_particles_file(path);
    if (p.ends_with(".json")) return import_csg_json_file(path).graph;
    throw InputError(path, 0, 0,
                     "unknown scene format: expected a file ending in .expr, .vm, .txt (blob "
                     "particles) or .json (Lipschitz-Pruning CSG tree)");
}

}  // namespace certray::expr
