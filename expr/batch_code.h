// expr/batch_code.h — internal to the batch walk (eval_batch.cpp, batch_code.cpp): the op codes
// of a tape's batch code beyond Op's, and how a dispatch key is made of them.
//
// Contract: a batch code instruction (expr/eval.h, BatchCode) is a tape instruction whose op byte
// is the key code·8 + a·4 + b·2 + keep: `code` an Op or one of the immediate forms below (operand
// a a register, the other operand the instruction's `imm`), a/b set when that operand is the
// previous instruction's result, keep set when the result need not be stored (its only reader is
// the next instruction).
#pragma once

#include "expr/op.h"

namespace certray::expr::detail {

// The ops up to Pow (codes 0 … kOwnCodes − 1) have codes of their own. The later ops (Floor …
// Or, issue 14) share two codes, kScalar1 (unary) and kScalar2 (binary), computed lane by lane
// with the scalar double functions; their Op is kept in the instruction's `imm` in batch code.
constexpr unsigned kOwnCodes = 19;
static_assert(static_cast<unsigned>(Op::Pow) + 1 == kOwnCodes);
// R: the register operand a; I: the immediate. Add and mul commute bit for bit in IEEE arithmetic
// (NaN for NaN), so each has one form; the others keep the tape's operand order.
constexpr unsigned kAddRI = kOwnCodes, kSubRI = kOwnCodes + 1, kSubIR = kOwnCodes + 2,
                   kMulRI = kOwnCodes + 3, kDivRI = kOwnCodes + 4, kDivIR = kOwnCodes + 5,
                   kMinRI = kOwnCodes + 6, kMinIR = kOwnCodes + 7, kMaxRI = kOwnCodes + 8,
                   kMaxIR = kOwnCodes + 9, kScalar1 = kOwnCodes + 10, kScalar2 = kOwnCodes + 11,
                   kCodeCount = kOwnCodes + 12;
static_assert(kCodeCount <= 32, "the walk's operand masks are 32 bits; keys must fit a byte");

/// The code of an op of its own (< kOwnCodes), or a code as stored in an op byte.
constexpr unsigned code(Op op) { return static_cast<unsigned>(op); }
/// The batch code of a tape op: its own, or kScalar1 / kScalar2.
constexpr unsigned batch_code(Op op) {
    const unsigned c = code(op);
    return c < kOwnCodes ? c : (arity(op) == 1 ? kScalar1 : kScalar2);
}
constexpr bool is_imm(unsigned c) { return c >= kAddRI && c <= kMaxIR; }
constexpr bool is_scalar(unsigned c) { return c == kScalar1 || c == kScalar2; }
/// How many operand registers code c reads.
constexpr int code_reads(unsigned c) {
    return is_imm(c) ? 1 : c == kScalar1 ? 1 : c == kScalar2 ? 2 : arity(static_cast<Op>(c));
}

/// The dispatch key of an instruction of code c.
constexpr unsigned key(unsigned c, bool a_carried, bool b_carried, bool keep) {
    return c * 8 + (a_carried ? 4u : 0u) + (b_carried ? 2u : 0u) + (keep ? 1u : 0u);
}

}  // namespace certray::expr::detail
