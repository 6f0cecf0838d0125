// expr/batch_code.cpp — compile_batch: a tape's instructions as the batch walk runs them.
#include "expr/batch_code.h"

#include <cstdint>
#include <vector>

#include "expr/eval.h"

namespace certray::expr::detail {

// Three passes over the register form. The first rewrites each add, sub, mul, div, min and max
// that reads a register last written by a Const into its immediate form (the second operand
// first; with both constant, the first stays a register read), and marks a Const needed when
// anything else reads its value, or when it is the output. The second drops the Consts not
// needed: nothing reads their registers before the next write. The third, backwards with the
// registers live after each instruction, writes each op byte as walk_carry's key: the code, whether
// a or b is the previous instruction's result (held in vector registers), and whether the result
// may stay unstored — when the next instruction reads it and nothing after that does.
void compile_batch(const Tape& tape, BatchCode& out) {
    constexpr std::uint32_t kNone = ~0u;
    const std::vector<Instr>& in = tape.instrs();
    const std::size_t n = in.size();
    thread_local std::vector<std::uint32_t> const_at;  // register → index of its Const, or kNone
    thread_local std::vector<unsigned char> needed;    // per instruction: a Const someone reads
    const_at.assign(tape.registers(), kNone);
    needed.assign(n, 0);
    out.instrs.assign(in.begin(), in.end());
    const auto imm_form = [](Op op, bool imm_second) -> unsigned {
        switch (op) {
            case Op::Add:
                return kAddRI;
            case Op::Mul:
                return kMulRI;
            case Op::Sub:
                return imm_second ? kSubRI : kSubIR;
            case Op::Div:
                return imm_second ? kDivRI : kDivIR;
            case Op::Min:
                return imm_second ? kMinRI : kMinIR;
            case Op::Max:
                return imm_second ? kMaxRI : kMaxIR;
            default:
                return 0;  // no immediate form
        }
    };
    for (std::size_t i = 0; i < n; ++i) {
        Instr& x = out.instrs[i];
        const int reads = arity(x.op);
        const std::uint32_t ka = reads >= 1 ? const_at[x.a] : kNone;
        const std::uint32_t kb = reads == 2 ? const_at[x.b] : kNone;
        if (code(x.op) >= kOwnCodes) {  // a scalar op: its Op into imm, its code into the op byte
            x.imm = static_cast<double>(code(x.op));
            x.op = static_cast<Op>(batch_code(x.op));
        }
        const unsigned second = imm_form(x.op, true), first = imm_form(x.op, false);
        if (kb != kNone && second != 0) {
            x.imm = in[kb].imm;
            x.op = static_cast<Op>(second);
            if (ka != kNone) needed[ka] = 1;
        } else if (ka != kNone && first != 0) {
            x.imm = in[ka].imm;
            x.op = static_cast<Op>(first);
            x.a = x.b;
            if (kb != kNone) needed[kb] = 1;
        } else {
            if (ka != kNone) needed[ka] = 1;
            if (kb != kNone) needed[kb] = 1;
        }
        const_at[in[i].out] = in[i].op == Op::Const ? static_cast<std::uint32_t>(i) : kNone;
    }
    if (n != 0) needed[n - 1] = 1;  // the output is stored, whatever it is
    std::size_t w = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (in[i].op != Op::Const || needed[i]) out.instrs[w++] = out.instrs[i];
    }
    out.instrs.resize(w);
    std::vector<Instr>& prog = out.instrs;
    thread_local std::vector<unsigned char> live;  // per register: read after this instruction
    live.assign(tape.registers(), 0);
    live[tape.output()] = 1;
    thread_local std::vector<unsigned char> keep;  // per instruction: its result stays unstored
    keep.assign(w, 0);
    const auto reads = [](const Instr& x) { return code_reads(code(x.op)); };
    for (std::size_t j = w; j-- > 0;) {
        const Instr& x = prog[j];
        const int k = reads(x);
        if (j > 0) {
            const std::uint32_t prev = prog[j - 1].out;
            const bool next_reads = (k >= 1 && x.a == prev) || (k == 2 && x.b == prev);
            keep[j - 1] = next_reads && (x.out == prev || !live[prev]);
        }
        live[x.out] = 0;
        if (k >= 1) live[x.a] = 1;
        if (k == 2) live[x.b] = 1;
    }
    for (std::size_t i = 0; i < w; ++i) {
        Instr& x = prog[i];
        const int k = reads(x);
        const bool has_prev = i > 0;
        const std::uint32_t prev = has_prev ? prog[i - 1].out : 0;
        const unsigned aa = has_prev && k >= 1 && x.a == prev;
        const unsigned ba = has_prev && k == 2 && x.b == prev;
        x.op = static_cast<Op>(key(code(x.op), aa, ba, keep[i] != 0));
    }
    out.serial = tape.serial();
}

}  // namespace certray::expr::detail
