// expr/parser.h — the .expr infix language (docs/design.md "The expression language") →
// expr::Graph.
//
// Grammar (newlines end statements, except inside parentheses, where they are ignored):
//   program   := { statement NEWLINE } ; the last statement is the expression f
//   statement := name '=' sum           ; a binding, usable on later lines only
//              | sum                     ; f: only allowed as the last statement
//   sum       := product { ('+' | '-') product }          ; left-associative
//   product   := unary { ('*' | '/') unary }              ; left-associative
//   unary     := { '-' } power                            ; -x^2 is −(x²)
//   power     := primary [ '^' integer ]                   ; a^2^3 is rejected: (a^2)^3
//   primary   := number | x | y | z | name | function '(' sum { ',' sum } ')' | '(' sum ')'
// Numbers are decimal (`1`, `1.5`, `.5`, `1.`, `2e-3`), meaning the nearest double; no sign, no
// hex, no inf/nan. Functions: sqrt abs exp log sin cos square floor ceil round tan asin acos atan
// recip not (1 argument), min max atan2 compare mod and or (2; Fidget's semantics, expr/op.h).
// Comments run from '#' to the end of the line. Nesting (parentheses, function calls) is limited to
// kMaxNesting levels, so no input can overflow the stack. Errors throw certray::InputError with
// file, line and column.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "expr/graph.h"
#include "expr/input_error.h"

namespace certray::expr {

/// Deepest nesting of parentheses and function calls the parser accepts.
inline constexpr int kMaxNesting = 256;

/// Parses .expr text into a Graph whose output is f. Throws certray::InputError ("file:line:col:
/// message") on any malformed input; `filename` is used only in messages.
Graph parse_expr(std::string_view text, std::string_view filename = "<string>");

/// Reads and parses the .expr file at `path`. Throws certray::InputError, also when it cannot be
/// read.
Graph parse_expr_file(const std::filesystem::path& path);

namespace detail {

/// Parses a whole decimal literal (digits with optional '.', fraction and exponent; an optional
/// leading sign when `allow_sign`) to the nearest double; underflow gives ±0. Returns false and
/// sets `error` for anything else (hex, inf, nan, trailing characters, overflow).
bool parse_decimal(std::string_view text, bool allow_sign, double& value, std::string& error);

/// Reads a whole file into a string. Throws certray::InputError (line 0) when it cannot.
std::string read_file(const std::filesystem::path& path);

}  // namespace detail
}  // namespace certray::expr
