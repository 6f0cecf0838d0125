// expr/tape.cpp — compiling a Graph to SSA and allocating registers by linear scan.
#include "expr/tape.h"

#include <atomic>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace certray::expr {
namespace {

std::uint64_t next_serial() noexcept {
    static std::atomic<std::uint64_t> counter{0};
    return counter.fetch_add(1, std::memory_order_relaxed) + 1;
}

}  // namespace

Tape::Tape(Tape&& o) noexcept
    : ssa_(std::move(o.ssa_)),
      instrs_(std::move(o.instrs_)),
      registers_(std::exchange(o.registers_, 0)),
      output_(std::exchange(o.output_, 0)),
      serial_(std::exchange(o.serial_, 0)) {}

Tape& Tape::operator=(Tape&& o) noexcept {
    if (this != &o) {
        ssa_ = std::move(o.ssa_);
        instrs_ = std::move(o.instrs_);
        o.ssa_.clear();
        o.instrs_.clear();
        registers_ = std::exchange(o.registers_, 0);
        output_ = std::exchange(o.output_, 0);
        serial_ = std::exchange(o.serial_, 0);
    }
    return *this;
}

Tape::Tape(const Graph& g) {
    if (!g.output().valid()) throw std::invalid_argument("Tape: the graph has no output");
    const std::vector<NodeId> order = g.topological_order();
    std::unordered_map<std::uint32_t, std::uint32_t> index;  // node id → SSA index
    index.reserve(order.size());
    ssa_.reserve(order.size());
    for (NodeId id : order) {
        const Node& n = g.node(id);
        Instr in{n.op, static_cast<std::uint32_t>(ssa_.size()), 0, 0, 0.0};
        const int k = arity(n.op);
        if (k >= 1) in.a = index.at(n.a.value);
        if (k == 2) in.b = index.at(n.b.value);
        if (n.op == Op::Pow) in.b = n.exponent;
        if (n.op == Op::Const) in.imm = n.constant;
        index.emplace(id.value, in.out);
        ssa_.push_back(in);
    }
    // The output must be the last instruction: topological_order ends with the root.
    if (ssa_.empty() || index.at(g.output().value) != ssa_.size() - 1) {
        throw std::logic_error("Tape: the topological order does not end at the output");
    }
    allocate_registers();
}

Tape Tape::from_ssa(std::vector<Instr> ssa) {
    if (ssa.empty()) throw std::invalid_argument("Tape: empty SSA list");
    Tape t;
    t.ssa_ = std::move(ssa);
    t.allocate_registers();
    return t;
}

bool Tape::uses_var(int axis) const noexcept {
    const Op want = axis == 0 ? Op::VarX : axis == 1 ? Op::VarY : Op::VarZ;
    for (const Instr& in : ssa_) {
        if (in.op == want) return true;
    }
    return false;
}

// Linear scan: an SSA value occupies a register from its definition to its last use. Operand
// registers whose last use is this instruction are released before the output is assigned, so the
// output may overwrite an operand (the evaluator reads operands before it writes).
void Tape::allocate_registers() {
    const std::size_t n = ssa_.size();
    std::vector<std::uint32_t> last_use(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        last_use[i] = static_cast<std::uint32_t>(i);
        const Instr& in = ssa_[i];
        const int k = arity(in.op);
        if (k >= 1) last_use[in.a] = static_cast<std::uint32_t>(i);
        if (k == 2) last_use[in.b] = static_cast<std::uint32_t>(i);
    }
    last_use[n - 1] = static_cast<std::uint32_t>(n);  // the output lives past the end
    std::vector<std::uint32_t> reg(n, 0);
    std::vector<std::uint32_t> free_regs;
    std::uint32_t count = 0;
    instrs_.clear();
    instrs_.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        Instr in = ssa_[i];
        const int k = arity(in.op);
        if (k >= 1) {
            const std::uint32_t a = in.a;
            in.a = reg[a];
            if (last_use[a] == i) free_regs.push_back(reg[a]);
        }
        if (k == 2) {
            const std::uint32_t b = in.b;
            in.b = reg[b];
            if (last_use[b] == i && b != ssa_[i].a) free_regs.push_back(reg[b]);
        }
        std::uint32_t r;
        if (!free_regs.empty()) {
            r = free_regs.back();
            free_regs.pop_back();
        } else {
            r = count++;
        }
        reg[i] = r;
        in.out = r;
        // A value nobody reads (dead code cannot occur in a compiled graph, but can after
        // pruning) frees its register at once.
        if (last_use[i] == i) free_regs.push_back(r);
        instrs_.push_back(in);
    }
    registers_ = count;
    output_ = reg[n - 1];
    serial_ = next_serial();
}

}  // namespace certray::expr
