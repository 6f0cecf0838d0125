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

// R: the register operand a; I: the immediate. Add and mul commute bit for bit in IEEE arithmetic
// (NaN for NaN), so each has one form; the others keep the tape's operand order.
constexpr unsigned kAddRI = kOpCount, kSubRI = kOpCount + 1, kSubIR = kOpCount + 2,
                   kMulRI = kOpCount + 3, kDivRI = kOpCount + 4, kDivIR = kOpCount + 5,
                   kMinRI = kOpCount + 6, kMinIR = kOpCount + 7, kMaxRI = kOpCount + 8,
                   kMaxIR = kOpCount + 9, kCodeCount = kOpCount + 10;
static_assert(kCodeCount <= 32, "the walk's operand masks are 32 bits");

constexpr unsigned code(Op op) { return static_cast<unsigned>(op); }
constexpr bool is_imm(unsigned c) { return c >= kOpCount; }

/// The dispatch key of an instruction of code c.
constexpr unsigned key(unsigned c, bool a_carried, bool b_carried, bool keep) {
    return c * 8 + (a_carried ? 4u : 0u) + (b_carried ? 2u : 0u) + (keep ? 1u : 0u);
}

}  // namespace certray::expr::detail
