// solvers/polynomial_check.h — whether g(t) = f(o + t·d) is a polynomial in t (or piecewise one),
// from the tape alone: one walk over the SSA form that tracks which values vary along a ray.
//
// Contract: why_not_along(tape, rule) is empty when every instruction meets its rule — an op
// whose rule is Never does not appear at all; an operand whose rule is Refused does not vary
// along the ray (it depends on no variable) — and otherwise names the first instruction that
// does not, with its index ("division by a non-constant (instruction 3 of 9)", "sqrt of a
// non-constant …"). The rules of the analytic methods (solvers/analytic.cpp) and of the exact
// oracle (solvers/exact.cpp) are tables over this one walk.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "expr/op.h"
#include "expr/tape.h"

namespace certray::solvers {

/// What an op accepts of an operand that varies along the ray.
enum class Along : std::uint8_t {
    Passes,   ///< it may vary (the result varies with it)
    Refused,  ///< it must be constant along the ray
    Never,    ///< the op may not appear (checked on the first operand's rule)
};

/// The rule of one op for its two operands.
struct OpRule {
    Along a = Along::Passes;
    Along b = Along::Passes;
};

/// The first instruction of `tape` that breaks `rule` (see the file contract), or "".
inline std::string why_not_along(const expr::Tape& tape, OpRule (*rule)(expr::Op)) {
    const std::vector<expr::Instr>& ssa = tape.ssa();
    std::vector<char> varying(ssa.size(), 0);
    for (std::size_t i = 0; i < ssa.size(); ++i) {
        const expr::Instr& in = ssa[i];
        const auto where = [&] {
            return " (instruction " + std::to_string(i + 1) + " of " + std::to_string(ssa.size()) +
                   ")";
        };
        if (in.op == expr::Op::VarX || in.op == expr::Op::VarY || in.op == expr::Op::VarZ) {
            varying[i] = 1;
            continue;
        }
        const int n = expr::arity(in.op);
        const bool va = n >= 1 && varying[in.a];
        const bool vb = n >= 2 && in.op != expr::Op::Pow && varying[in.b];  // Pow's b: exponent
        const OpRule r = rule(in.op);
        if (r.a == Along::Never) {
            return std::string(expr::name(in.op)) + ", not a polynomial operation" + where();
        }
        if (vb && r.b == Along::Refused) {
            return (in.op == expr::Op::Div ? std::string("division by")
                                           : std::string(expr::name(in.op)) + " of") +
                   " a non-constant" + where();
        }
        if (va && r.a == Along::Refused) {
            return std::string(expr::name(in.op)) + " of a non-constant" + where();
        }
        varying[i] = va || vb;
    }
    return {};
}

}  // namespace certray::solvers
