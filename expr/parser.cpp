// expr/parser.cpp — lexer and precedence parser of the .expr language (see parser.h for the
// grammar).
#include "expr/parser.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "interval/interval.h"

namespace certray::expr {
namespace detail {

bool parse_decimal(std::string_view text, bool allow_sign, double& value, std::string& error) {
    std::size_t i = 0;
    bool negative = false;
    if (allow_sign && i < text.size() && (text[i] == '+' || text[i] == '-')) {
        negative = text[i] == '-';
        ++i;
    }
    const std::size_t start = i;
    // Mantissa: digits [ '.' digits ] with at least one digit; then [ e [+-] digits ].
    long first_nonzero_exp = 0;  // decimal exponent estimate of the leading nonzero digit
    bool seen_nonzero = false;
    long int_digits = 0;
    long frac_digits = 0;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') {
        if (text[i] != '0' && !seen_nonzero) seen_nonzero = true;
        if (seen_nonzero) ++int_digits;
        ++i;
    }
    const std::size_t int_end = i;
    long leading_frac_zeros = 0;
    if (i < text.size() && text[i] == '.') {
        ++i;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9') {
            if (!seen_nonzero) {
                if (text[i] == '0')
                    ++leading_frac_zeros;
                else
                    seen_nonzero = true;
            }
            ++frac_digits;
            ++i;
        }
    }
    if (int_end == start && frac_digits == 0) {
        error = "malformed number '" + std::string(text) + "'";
        return false;
    }
    long exp10 = 0;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        bool eneg = false;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
            eneg = text[i] == '-';
            ++i;
        }
        const std::size_t exp_start = i;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9') {
            if (exp10 < 100000) exp10 = exp10 * 10 + (text[i] - '0');
            ++i;
        }
        if (i == exp_start) {
            error = "malformed number '" + std::string(text) + "': expected digits in the exponent";
            return false;
        }
        if (eneg) exp10 = -exp10;
    }
    if (i != text.size()) {
        error = "malformed number '" + std::string(text) + "'";
        return false;
    }
    double v = 0.0;
    NearestScope env;  // the nearest double, whatever the caller's rounding direction
    const char* first = text.data() + start;
    const char* last = text.data() + text.size();
    const auto res = std::from_chars(first, last, v, std::chars_format::general);
    if (res.ec == std::errc::result_out_of_range) {
        // Overflow or underflow: decide from the decimal exponent of the leading digit.
        first_nonzero_exp =
            int_digits > 0 ? int_digits - 1 + exp10 : -(leading_frac_zeros + 1) + exp10;
        if (seen_nonzero && first_nonzero_exp > 0) {
            error = "number '" + std::string(text) + "' is out of the range of double";
            return false;
        }
        v = 0.0;  // the nearest double to a tiny number
    } else if (res.ec != std::errc() || res.ptr != last) {
        error = "malformed number '" + std::string(text) + "'";
        return false;
    }
    if (!std::isfinite(v)) {
        error = "number '" + std::string(text) + "' is out of the range of double";
        return false;
    }
    value = negative ? -v : v;
    return true;
}

std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string(), 0, 0, "cannot open file");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw InputError(path.string(), 0, 0, "cannot read file");
    return ss.str();
}

}  // namespace detail

namespace {

enum class Tok {
    Number,
    Ident,
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    Comma,
    Equals,
    Newline,
    End
};

struct Token {
    Tok kind = Tok::End;
    std::string_view text;
    int line = 1;
    int column = 1;
    double number = 0.0;
};

std::string describe(const Token& t) {
    switch (t.kind) {
        case Tok::Newline:
            return "end of line";
        case Tok::End:
            return "end of input";
        case Tok::Number:
        case Tok::Ident:
        case Tok::Plus:
        case Tok::Minus:
        case Tok::Star:
        case Tok::Slash:
        case Tok::Caret:
        case Tok::LParen:
        case Tok::RParen:
        case Tok::Comma:
        case Tok::Equals:
            break;
    }
    std::string quoted(1, '\'');
    quoted += t.text;
    quoted += '\'';
    return quoted;
}

bool is_ident_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_ident_char(char c) { return is_ident_start(c) || (c >= '0' && c <= '9'); }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Splits the text into tokens. Newlines inside parentheses are dropped (line continuation).
std::vector<Token> lex(std::string_view text, const std::string& file) {
    std::vector<Token> out;
    int line = 1;
    int col = 1;
    int depth = 0;
    std::size_t i = 0;
    auto push = [&](Tok k, std::size_t len) {
        Token t;
        t.kind = k;
        t.text = text.substr(i, len);
        t.line = line;
        t.column = col;
        out.push_back(t);
        i += len;
        col += static_cast<int>(len);
    };
    while (i < text.size()) {
        const char c = text[i];
        if (c == '\n') {
            if (depth == 0)
                push(Tok::Newline, 1);
            else
                ++i;
            ++line;
            col = 1;
        } else if (c == ' ' || c == '\t' || c == '\r') {
            ++i;
            ++col;
        } else if (c == '#') {
            while (i < text.size() && text[i] != '\n') {
                ++i;
                ++col;
            }
        } else if (is_digit(c) || (c == '.' && i + 1 < text.size() && is_digit(text[i + 1]))) {
            std::size_t j = i;
            while (j < text.size() && is_digit(text[j])) ++j;
            if (j < text.size() && text[j] == '.') {
                ++j;
                while (j < text.size() && is_digit(text[j])) ++j;
            }
            if (j < text.size() && (text[j] == 'e' || text[j] == 'E')) {
                std::size_t k = j + 1;
                if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
                if (k < text.size() && is_digit(text[k])) {
                    while (k < text.size() && is_digit(text[k])) ++k;
                    j = k;
                } else {
                    throw InputError(file, line, col + static_cast<int>(j - i),
                                     "malformed number '" + std::string(text.substr(i, k - i)) +
                                         "': expected digits in the exponent");
                }
            }
            Token t;
            t.kind = Tok::Number;
            t.text = text.substr(i, j - i);
            t.line = line;
            t.column = col;
            std::string error;
            if (!detail::parse_decimal(t.text, false, t.number, error)) {
                throw InputError(file, line, col, error);
            }
            out.push_back(t);
            col += static_cast<int>(j - i);
            i = j;
        } else if (is_ident_start(c)) {
            std::size_t j = i;
            while (j < text.size() && is_ident_char(text[j])) ++j;
            push(Tok::Ident, j - i);
        } else {
            Tok k = Tok::End;
            switch (c) {
                case '+':
                    k = Tok::Plus;
                    break;
                case '-':
                    k = Tok::Minus;
                    break;
                case '*':
                    k = Tok::Star;
                    break;
                case '/':
                    k = Tok::Slash;
                    break;
                case '^':
                    k = Tok::Caret;
                    break;
                case '(':
                    k = Tok::LParen;
                    ++depth;
                    break;
                case ')':
                    k = Tok::RParen;
                    if (depth > 0) --depth;
                    break;
                case ',':
                    k = Tok::Comma;
                    break;
                case '=':
                    k = Tok::Equals;
                    break;
                default: {
                    std::string shown =
                        (static_cast<unsigned char>(c) < 0x20 ||
                         static_cast<unsigned char>(c) >= 0x7f)
                            ? "byte " + std::to_string(static_cast<unsigned char>(c))
                            : std::string{'\'', c, '\''};
                    throw InputError(file, line, col, "unexpected character " + shown);
                }
            }
            push(k, 1);
        }
    }
    Token end;
    end.kind = Tok::End;
    end.line = line;
    end.column = col;
    out.push_back(end);
    return out;
}

struct Function {
    Op op;
    int args;
};

std::optional<Function> find_function(std::string_view s) {
    if (s == "sqrt") return Function{Op::Sqrt, 1};
    if (s == "abs") return Function{Op::Abs, 1};
    if (s == "exp") return Function{Op::Exp, 1};
    if (s == "log") return Function{Op::Log, 1};
    if (s == "sin") return Function{Op::Sin, 1};
    if (s == "cos") return Function{Op::Cos, 1};
    if (s == "square") return Function{Op::Square, 1};
    if (s == "min") return Function{Op::Min, 2};
    if (s == "max") return Function{Op::Max, 2};
    for (Op op : {Op::Floor, Op::Ceil, Op::Round, Op::Tan, Op::Asin, Op::Acos, Op::Atan, Op::Recip,
                  Op::Not, Op::Atan2, Op::Compare, Op::Mod, Op::And, Op::Or}) {
        if (s == name(op)) return Function{op, arity(op)};
    }
    return std::nullopt;
}

int var_axis(std::string_view s) {
    if (s == "x") return 0;
    if (s == "y") return 1;
    if (s == "z") return 2;
    return -1;
}

class Parser {
  public:
    Parser(std::string_view text, std::string file)
        : file_(std::move(file)), toks_(lex(text, file_)) {}

    Graph run() {
        std::optional<Token> final_start;  // the first token of the expression statement seen
        while (true) {
            while (peek().kind == Tok::Newline) ++pos_;
            if (peek().kind == Tok::End) break;
            if (final_start) {
                fail(*final_start,
                     "the expression defining f must be the last statement; name "
                     "intermediate values with 'name = ...'");
            }
            if (peek().kind == Tok::Ident && peek(1).kind == Tok::Equals) {
                binding();
            } else {
                final_start = peek();
                output_ = sum();
            }
            const Token& t = peek();
            if (t.kind != Tok::Newline && t.kind != Tok::End) {
                fail(t, "expected an operator or end of line, found " + describe(t));
            }
        }
        if (!final_start) {
            fail(peek(), bindings_.empty() ? "expected an expression (the input is empty)"
                                           : "expected a final expression defining f after the "
                                             "bindings");
        }
        graph_.set_output(output_);
        return std::move(graph_);
    }

  private:
    struct Binding {
        NodeId id;
        int line;
    };

    const Token& peek(std::size_t ahead = 0) const {
        const std::size_t k = std::min(pos_ + ahead, toks_.size() - 1);
        return toks_[k];
    }
    const Token& take() {
        const Token& t = toks_[pos_];
        if (pos_ + 1 < toks_.size()) ++pos_;
        return t;
    }
    [[noreturn]] void fail(const Token& t, const std::string& message) const {
        throw InputError(file_, t.line, t.column, message);
    }

    void binding() {
        const Token name = take();
        take();  // '='
        const std::string key(name.text);
        if (var_axis(name.text) >= 0 || find_function(name.text)) {
            fail(name, "cannot bind '" + key + "': the name is reserved");
        }
        if (auto it = bindings_.find(key); it != bindings_.end()) {
            fail(name,
                 "'" + key + "' is already defined at line " + std::to_string(it->second.line));
        }
        const NodeId value = sum();
        bindings_.emplace(key, Binding{value, name.line});
    }

    NodeId sum() {
        NodeId left = product();
        while (peek().kind == Tok::Plus || peek().kind == Tok::Minus) {
            const Op op = take().kind == Tok::Plus ? Op::Add : Op::Sub;
            const NodeId right = product();
            left = graph_.binary(op, left, right);
        }
        return left;
    }

    NodeId product() {
        NodeId left = unary();
        while (peek().kind == Tok::Star || peek().kind == Tok::Slash) {
            const Op op = take().kind == Tok::Star ? Op::Mul : Op::Div;
            const NodeId right = unary();
            left = graph_.binary(op, left, right);
        }
        return left;
    }

    NodeId unary() {
        std::size_t negations = 0;
        while (peek().kind == Tok::Minus) {
            take();
            ++negations;
        }
        NodeId v = power();
        for (std::size_t k = 0; k < negations; ++k) v = graph_.unary(Op::Neg, v);
        return v;
    }

    NodeId power() {
        NodeId base = primary();
        if (peek().kind != Tok::Caret) return base;
        take();
        const Token e = take();
        bool ok = e.kind == Tok::Number;
        for (char c : e.text) ok = ok && c >= '0' && c <= '9';
        if (!ok) fail(e, "expected a non-negative integer literal after '^', found " + describe(e));
        std::uint32_t n = 0;
        const auto res = std::from_chars(e.text.data(), e.text.data() + e.text.size(), n);
        if (res.ec != std::errc()) fail(e, "exponent '" + std::string(e.text) + "' is too large");
        if (peek().kind == Tok::Caret) {
            fail(peek(), "chained '^' is ambiguous; use parentheses, e.g. (x^2)^3");
        }
        return graph_.pow(base, n);
    }

    NodeId nested_sum(const Token& at) {
        if (++depth_ > kMaxNesting) {
            fail(at, "expression nested deeper than " + std::to_string(kMaxNesting) + " levels");
        }
        const NodeId v = sum();
        --depth_;
        return v;
    }

    NodeId primary() {
        const Token t = take();
        switch (t.kind) {
            case Tok::Number:
                return graph_.constant(t.number);
            case Tok::LParen: {
                const NodeId v = nested_sum(t);
                const Token& close = peek();
                if (close.kind != Tok::RParen) {
                    fail(close, "expected ')' to close the '(' at " + std::to_string(t.line) + ":" +
                                    std::to_string(t.column) + ", found " + describe(close));
                }
                take();
                return v;
            }
            case Tok::Ident:
                return name_or_call(t);
            case Tok::Plus:
            case Tok::Minus:
            case Tok::Star:
            case Tok::Slash:
            case Tok::Caret:
            case Tok::RParen:
            case Tok::Comma:
            case Tok::Equals:
            case Tok::Newline:
            case Tok::End:
                break;
        }
        fail(t, "expected an expression, found " + describe(t));
    }

    NodeId name_or_call(const Token& t) {
        const std::string key(t.text);
        if (const auto fn = find_function(t.text)) {
            const Token& open = peek();
            if (open.kind != Tok::LParen) {
                fail(open, "expected '(' after function '" + key + "', found " + describe(open));
            }
            take();
            std::vector<NodeId> args;
            if (peek().kind != Tok::RParen) {
                args.push_back(nested_sum(open));
                while (peek().kind == Tok::Comma) {
                    take();
                    args.push_back(nested_sum(open));
                }
            }
            const Token& close = peek();
            if (close.kind != Tok::RParen) {
                fail(close,
                     "expected ')' after arguments of '" + key + "', found " + describe(close));
            }
            take();
            if (static_cast<int>(args.size()) != fn->args) {
                fail(t, "'" + key + "' takes " + std::to_string(fn->args) +
                            (fn->args == 1 ? " argument" : " arguments") + ", got " +
                            std::to_string(args.size()));
            }
            return fn->args == 1 ? graph_.unary(fn->op, args[0])
                                 : graph_.binary(fn->op, args[0], args[1]);
        }
        if (const int axis = var_axis(t.text); axis >= 0) return graph_.var(axis);
        if (auto it = bindings_.find(key); it != bindings_.end()) return it->second.id;
        if (peek().kind == Tok::LParen) fail(t, "unknown function '" + key + "'");
        fail(t, "undefined name '" + key + "'");
    }

    std::string file_;
    std::vector<Token> toks_;
    std::size_t pos_ = 0;
    int depth_ = 0;
    Graph graph_;
    NodeId output_;
    std::unordered_map<std::string, Binding> bindings_;
};

}  // namespace

Graph parse_expr(std::string_view text, std::string_view filename) {
    return Parser(text, std::string(filename)).run();
}

Graph parse_expr_file(const std::filesystem::path& path) {
    const std::string text = detail::read_file(path);
    return parse_expr(text, path.string());
}

}  // namespace certray::expr
