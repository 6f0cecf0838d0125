// expr/tape.h — expr::Tape: a Graph compiled to linear SSA with a small register file.
//
// Contract: evaluating the tape's instructions in order computes the graph's output at a point (or
// over a box) exactly as the graph defines it. Each instruction reads registers written by earlier
// instructions; registers are reused once their value is dead (linear scan over last uses), so the
// scratch space an evaluation needs is `registers()` values, not one per node.
// The SSA form is kept beside the register form, so a tape can be pruned (prune.h) and
// re-allocated. Reference: Fidget's `VmData` / libfive's tape (docs/theory/tape.md).
#pragma once

#include <cstdint>
#include <vector>

#include "expr/graph.h"
#include "expr/op.h"

namespace certray::expr {

/// One instruction: out = op(a, b). For Const, `imm` holds the constant; for Pow, `n` the exponent.
struct Instr {
    Op op;
    std::uint32_t out;  ///< register written
    std::uint32_t a;    ///< register of the first operand (unary, binary, Pow)
    std::uint32_t b;    ///< register of the second operand (binary); exponent for Pow
    double imm;         ///< the constant of a Const instruction
};

/// The instruction list of a compiled expression. Cheap to copy; immutable after construction.
class Tape {
  public:
    Tape() = default;
    Tape(const Tape&) = default;
    Tape& operator=(const Tape&) = default;
    /// A moved-from tape is empty, with serial 0.
    Tape(Tape&& o) noexcept;
    Tape& operator=(Tape&& o) noexcept;
    /// Compiles the part of `g` reachable from its output. Throws std::invalid_argument when the
    /// graph has no output.
    explicit Tape(const Graph& g);

    /// Instructions in evaluation order (register form).
    const std::vector<Instr>& instrs() const noexcept { return instrs_; }
    /// Number of registers an evaluation needs.
    std::uint32_t registers() const noexcept { return registers_; }
    /// Register holding the result after the last instruction.
    std::uint32_t output() const noexcept { return output_; }
    /// Number of instructions (the tape length reported by pruning).
    std::size_t size() const noexcept { return instrs_.size(); }
    /// True when the instruction list reads variable `axis` (0 = x, 1 = y, 2 = z).
    bool uses_var(int axis) const noexcept;

    /// The SSA form: the same instructions with operands naming instruction indices.
    const std::vector<Instr>& ssa() const noexcept { return ssa_; }
    /// Builds a tape from an SSA list (operands are indices of earlier instructions; the last
    /// instruction is the output), allocating registers.
    static Tape from_ssa(std::vector<Instr> ssa);

    /// An identity for caches of what is derived from the instructions (the batch walk's code,
    /// expr/eval.h): copies share it, tapes built separately never do, an empty tape has 0.
    std::uint64_t serial() const noexcept { return serial_; }

  private:
    void allocate_registers();

    std::vector<Instr> ssa_;
    std::vector<Instr> instrs_;
    std::uint32_t registers_ = 0;
    std::uint32_t output_ = 0;
    std::uint64_t serial_ = 0;
};

}  // namespace certray::expr
