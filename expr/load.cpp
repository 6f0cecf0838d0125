// expr/load.cpp — dispatch on the file extension.
#include "expr/load.h"

#include "expr/input_error.h"
#include "expr/parser.h"
#include "expr/vm_import.h"

namespace certray::expr {

Graph load_graph_file(const std::string& path) {
    auto ends_with = [&](const char* ext) {
        const std::string e(ext);
        return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
    };
    if (ends_with(".expr")) return parse_expr_file(path);
    if (ends_with(".vm")) return import_vm_file(path);
    throw InputError(path, 0, 0, "unknown scene format: expected a file ending in .expr or .vm");
}

}  // namespace certray::expr
