// expr/vm_import.h — imports Fidget's .vm SSA text format (mkeeter/fidget `models/`; described in
// docs/guide/formats.md).
//
// Format: one instruction a line, `<id> <opcode> [args]`; blank lines and lines starting with '#'
// are skipped; ids are any token without spaces; arguments name ids defined on earlier lines; the
// last instruction is the output. Supported opcodes: var-x var-y var-z, const <number>,
// neg abs sqrt square exp ln sin cos (one argument), add sub mul div min max (two; `sub a b` is
// a − b). The other Fidget opcodes (floor ceil round tan asin acos atan not atan2 compare mod and
// or) are rejected as unsupported. Every error is a certray::InputError with line and column.
// Reference: Fidget (mkeeter/fidget) `models/*.vm`, `fidget::Context::from_text`.
#pragma once

#include <filesystem>
#include <string_view>

#include "expr/graph.h"
#include "expr/input_error.h"

namespace certray::expr {

/// Imports .vm text into a Graph (deduplicated and simplified like any Graph) whose output is the
/// last instruction. Throws certray::InputError for unknown or unsupported opcodes, undefined ids
/// (including forward references), duplicate ids, wrong argument counts and bad numbers.
Graph import_vm(std::string_view text, std::string_view filename = "<string>");

/// Reads and imports the .vm file at `path`. Throws certray::InputError, also when it cannot be
/// read.
Graph import_vm_file(const std::filesystem::path& path);

}  // namespace certray::expr
