// expr/load.cpp — dispatch on the file extension.
#include "expr/load.h"

#include <string_view>

#include "expr/input_error.h"
#include "expr/parser.h"
#include "expr/vm_import.h"

namespace certray::expr {

Graph load_graph_file(const std::string& path) {
    const std::string_view p(path);
    if (p.ends_with(".expr")) return parse_expr_file(path);
    if (p.ends_with(".vm")) return import_vm_file(path);
    throw InputError(path, 0, 0, "unknown scene format: expected a file ending in .expr or .vm");
}

}  // namespace certray::expr
