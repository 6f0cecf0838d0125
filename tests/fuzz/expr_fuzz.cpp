// tests/fuzz/expr_fuzz.cpp — libFuzzer target for the .expr parser, the .vm importer and the
// printer: any input either throws certray::InputError or gives a graph whose printed text parses
// back to the same text. Anything else (a crash, a hang, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "expr/graph.h"
#include "expr/input_error.h"
#include "expr/parser.h"
#include "expr/printer.h"
#include "expr/vm_import.h"

namespace {

void check_round_trip(const certray::expr::Graph& g) {
    const std::string text = certray::expr::print_expr(g);
    std::string again;
    try {
        again = certray::expr::print_expr(certray::expr::parse_expr(text, "<printed>"));
    } catch (const certray::InputError&) {
        std::abort();  // the printer wrote something the parser rejects
    }
    if (text != again) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    // The first byte picks the reader, the rest is the text.
    const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
    try {
        if (data[0] & 1) {
            check_round_trip(certray::expr::import_vm(text, "<fuzz>"));
        } else {
            check_round_trip(certray::expr::parse_expr(text, "<fuzz>"));
        }
    } catch (const certray::InputError&) {
        // Rejected with a message: the expected outcome for most inputs.
    }
    return 0;
}
