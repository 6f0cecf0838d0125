// expr/vm_import.cpp — line-by-line reader of Fidget's .vm format into an expr::Graph.
#include "expr/vm_import.h"

#include <string>
#include <unordered_map>
#include <vector>

#include "expr/parser.h"

namespace certray::expr {
namespace {

struct Word {
    std::string_view text;
    int column;
};

enum class Kind { VarX, VarY, VarZ, Const, Unary, Binary, Unsupported, Unknown };

struct Opcode {
    Kind kind = Kind::Unknown;
    Op op = Op::Const;
};

Opcode lookup(std::string_view s) {
    if (s == "var-x") return {Kind::VarX, Op::VarX};
    if (s == "var-y") return {Kind::VarY, Op::VarY};
    if (s == "var-z") return {Kind::VarZ, Op::VarZ};
    if (s == "const") return {Kind::Const, Op::Const};
    if (s == "neg") return {Kind::Unary, Op::Neg};
    if (s == "abs") return {Kind::Unary, Op::Abs};
    if (s == "sqrt") return {Kind::Unary, Op::Sqrt};
    if (s == "square") return {Kind::Unary, Op::Square};
    if (s == "exp") return {Kind::Unary, Op::Exp};
    if (s == "ln") return {Kind::Unary, Op::Log};
    if (s == "sin") return {Kind::Unary, Op::Sin};
    if (s == "cos") return {Kind::Unary, Op::Cos};
    if (s == "add") return {Kind::Binary, Op::Add};
    if (s == "sub") return {Kind::Binary, Op::Sub};
    if (s == "mul") return {Kind::Binary, Op::Mul};
    if (s == "div") return {Kind::Binary, Op::Div};
    if (s == "min") return {Kind::Binary, Op::Min};
    if (s == "max") return {Kind::Binary, Op::Max};
    for (Op op : {Op::Floor, Op::Ceil, Op::Round, Op::Tan, Op::Asin, Op::Acos, Op::Atan, Op::Recip,
                  Op::Not, Op::Atan2, Op::Compare, Op::Mod, Op::And, Op::Or}) {
        if (s == name(op)) return {arity(op) == 1 ? Kind::Unary : Kind::Binary, op};
    }
    // Fidget's pseudo-random opcodes: no real function to certify.
    for (std::string_view u : {"rand", "mix"}) {
        if (s == u) return {Kind::Unsupported, Op::Const};
    }
    return {Kind::Unknown, Op::Const};
}

int expected_args(Kind k) {
    switch (k) {
        case Kind::VarX:
        case Kind::VarY:
        case Kind::VarZ:
            return 0;
        case Kind::Const:
        case Kind::Unary:
            return 1;
        case Kind::Binary:
            return 2;
        case Kind::Unsupported:
        case Kind::Unknown:
            break;
    }
    return -1;
}

// Splits a line into whitespace-separated words with 1-based columns; a word starting with '#'
// begins a comment that runs to the end of the line.
std::vector<Word> split(std::string_view line) {
    std::vector<Word> words;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        if (i >= line.size() || line[i] == '#') break;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        words.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
    }
    return words;
}

}  // namespace

Graph import_vm(std::string_view text, std::string_view filename) {
    const std::string file(filename);
    Graph g;
    struct Defined {
        NodeId id;
        int line;
    };
    std::unordered_map<std::string_view, Defined> ids;
    NodeId last;
    int line_no = 0;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        const std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        const std::vector<Word> w = split(line);
        if (w.empty()) continue;
        auto fail = [&](int column, const std::string& message) -> void {
            throw InputError(file, line_no, column, message);
        };
        if (w.size() < 2) {
            fail(w[0].column + static_cast<int>(w[0].text.size()),
                 "expected an opcode after id '" + std::string(w[0].text) + "'");
        }
        const Word& id = w[0];
        const Word& opword = w[1];
        if (auto it = ids.find(id.text); it != ids.end()) {
            fail(id.column, "duplicate id '" + std::string(id.text) + "' (first defined at line " +
                                std::to_string(it->second.line) + ")");
        }
        const Opcode oc = lookup(opword.text);
        if (oc.kind == Kind::Unsupported) {
            fail(opword.column, "unsupported opcode '" + std::string(opword.text) + "'");
        }
        if (oc.kind == Kind::Unknown) {
            fail(opword.column, "unknown opcode '" + std::string(opword.text) + "'");
        }
        const int nargs = static_cast<int>(w.size()) - 2;
        const int want = expected_args(oc.kind);
        if (nargs != want) {
            std::string msg(1, '\'');  // built by appending: GCC 12 warns falsely on "'" + s
            msg.append(opword.text).append("' takes ").append(std::to_string(want));
            msg.append(want == 1 ? " argument" : " arguments").append(", got ");
            msg.append(std::to_string(nargs));
            fail(nargs > want ? w[2 + want].column : opword.column, msg);
        }
        auto arg = [&](int k) -> NodeId {
            const Word& a = w[2 + k];
            const auto it = ids.find(a.text);
            if (it == ids.end()) {
                throw InputError(file, line_no, a.column,
                                 "undefined id '" + std::string(a.text) +
                                     "' (arguments must name ids defined on earlier lines)");
            }
            return it->second.id;
        };
        NodeId node;
        switch (oc.kind) {
            case Kind::VarX:
                node = g.var(0);
                break;
            case Kind::VarY:
                node = g.var(1);
                break;
            case Kind::VarZ:
                node = g.var(2);
                break;
            case Kind::Const: {
                double v = 0.0;
                std::string error;
                if (!detail::parse_decimal(w[2].text, true, v, error)) fail(w[2].column, error);
                node = g.constant(v);
                break;
            }
            case Kind::Unary:
                node = g.unary(oc.op, arg(0));
                break;
            case Kind::Binary: {
                const NodeId a = arg(0);
                const NodeId b = arg(1);
                node = g.binary(oc.op, a, b);
                break;
            }
            case Kind::Unsupported:
            case Kind::Unknown:
                break;  // rejected above
        }
        ids.emplace(id.text, Defined{node, line_no});
        last = node;
    }
    if (!last.valid()) {
        throw InputError(file, 0, 0, "no instructions: expected '<id> <opcode> [args]' lines");
    }
    g.set_output(last);
    return g;
}

Graph import_vm_file(const std::filesystem::path& path) {
    const std::string text = detail::read_file(path);
    return import_vm(text, path.string());
}

}  // namespace certray::expr
