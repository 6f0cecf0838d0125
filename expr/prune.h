// expr/prune.h — region pruning: a shorter tape that equals f on a box.
//
// Contract: for every point q of the box, eval(prune(t, box).tape, q) and eval(t, q) are the same
// real number (and the pruned tape's interval result over the box is contained in the full one's).
// A min/max branch is dropped only where interval evaluation proves it inactive on the whole box
// *and* the dropped branch is defined there (dropping an undefined branch would make f defined
// where it is not). A subexpression whose enclosure over the box is one point, defined on the
// whole box, becomes that constant; an add or sub with an operand that is 0 (and defined) on the
// whole box becomes its other operand (x + 0 = 0 + x = x − 0 = x: the same real function and
// enclosure; in double only a zero result's sign may differ, −0 + 0 being +0). When
// PruneWorkspace::absolute_values is set, a max(x, −x) that
// pruning leaves (the two operands reached
// through different chains of choices) becomes |x|: the same real function, whose enclosure is
// ≥ 0 where the interval max of x and −x is not (a model that touches 0 along a plane, as
// max(c − x, x − c) does, is then proven ≥ 0 there). Reference: Fidget's tape simplification,
// libfive's per-region tape shortening (docs/theory/tape.md).
//
// Two forms: prune(tape, box) evaluates and returns a new Tape (allocates); prune_ssa() prunes an
// SSA list from the enclosures of an interval evaluation the caller has already done (in SSA form:
// one slot per instruction), into a caller-owned list, in one backward pass without allocating once
// its buffers have grown — the form a quadtree uses to evaluate each tile once and prune from that
// same evaluation (Fidget's `VmData::simplify`: choices and renaming in one reverse walk).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"

namespace certray::expr {

/// The outcome of pruning: the shorter tape, the lengths before and after, and the enclosure of f
/// over the box that the pruning decisions came from.
struct PruneResult {
    Tape tape;
    std::size_t before = 0;
    std::size_t after = 0;
    Interval value;
};

/// Prunes `tape` to the box (x, y, z intervals).
PruneResult prune(const Tape& tape, const std::array<Interval, 3>& box);

/// Scratch space of prune_ssa, reused across calls (grows to the longest list seen).
struct PruneWorkspace {
    std::vector<std::uint32_t> bind;  ///< per slot of the input: its slot in the output, or none
    std::vector<Instr> emitted;       ///< the pruned list as it is written, back to front
    /// Also rewrite max(x, −x) as |x| (see the file contract). Off by default: it costs a pass
    /// over the pruned list (7 % of prospero's 2D image, which has no such pattern); the 3D
    /// coherent walk and prune() turn it on.
    bool absolute_values = false;
    /// Make a subexpression whose enclosure over the box is one point that constant (see the file
    /// contract). Off: kept, so that the pruned list's derivatives stay f's at the box's points
    /// wherever its choices are strict — a constant has none, and on a box of zero width in an axis
    /// (a heightmap ray's box is a point in x and y) that axis's variable is one point. The 3D
    /// coherent walk turns it off: its hits' normals are the gradients of its lists.
    bool fold_points = true;
    std::vector<std::uint32_t> alias;   ///< per slot of the output: the slot it copies, or itself
    std::vector<std::uint32_t> neg_of;  ///< per slot of the output: x when it is −x, else none
};

/// Prunes an SSA list to a box, given the enclosures over that box of an evaluation of the list
/// that the caller has done: `values[s · stride]` is the enclosure of the value of slot s, as
/// detail::run<UpInterval>(ssa, box, values) leaves it for stride 1 (a stride > 1 reads one lane
/// of an evaluation of several boxes at once).
///
/// An SSA list here: each instruction writes its own slot `out` (slots distinct and < n, the
/// list's length), operands name the slots of earlier instructions, and the last instruction is
/// the output — Tape::ssa() is one (slot i = instruction i), and so is every list written to `out`
/// (slots numbered from the output backwards, so not in list order).
///
/// Applies the rules of the file contract (a min/max with both operands the same slot counts as
/// a choice), so the list written to `out` (replaced) equals `ssa` at every point of the box, and
/// its enclosure over the box is contained in the output's. When moreover every enclosure in
/// `values` is bounded and defined, the double evaluations of both lists agree at every point of
/// the box (as numbers: a constant folded from [−0, 0] may carry the other sign of zero), since
/// each double intermediate then lies in its enclosure. A dropped min/max keeps no copy of the
/// chosen operand unless a kept instruction also reads that operand; then it becomes min(x, x)
/// (= x, as doubles and as intervals; Fidget's CopyReg), dropped by a later pruning once that
/// reader is gone. Returns false when nothing can be dropped or folded (`out` is then untouched:
/// use `ssa`). `out` must not be `ssa`. Allocates nothing once `ws` and `out` have the capacity of
/// `ssa`.
bool prune_ssa(const std::vector<Instr>& ssa, const UpInterval* values, PruneWorkspace& ws,
               std::vector<Instr>& out, std::size_t stride = 1);

/// An SSA list folded to a box (fold_ssa): `list` computes f from the variables and from the
/// slots of `fixed`, which no instruction of `list` writes: the caller writes each slot's
/// enclosure there before every walk (in every lane, decoration included).
struct FoldedList {
    std::vector<Instr> list;
    std::vector<std::pair<std::uint32_t, UpInterval>> fixed;
    std::vector<std::uint8_t> state;  ///< fold_ssa's scratch (per slot of the list it folds)
};

/// Folds an SSA list to a box: each subexpression whose enclosure over the box (values[s], as for
/// prune_ssa with stride 1) is defined, bounded and at most `width` wide becomes an input fixed at
/// that enclosure, and what only it read is dropped (the output itself is never folded).
///
/// An inclusion, not an equality: for every sub-box (or point) B of the box, the interval walk of
/// `out.list` over B, its fixed slots filled, encloses f over B — each fixed value holds its
/// subexpression's value at every point of the box, every other op is the list's own — and its
/// decoration says "defined and continuous" only where f is (a folded subexpression is so on the
/// whole box). What the folded list loses is the width of its inputs: a point's enclosure is
/// as wide as the fixed values make it. Its tangent list (expr/tangent.h) takes the fixed slots
/// as inputs of derivative 0: the derivative along a direction with them held fixed, which gives
/// mean value forms that hold for f on segments of the box (f(t) = h(t, s(t)) with s(t) in the
/// fixed enclosures S, and h(t, s) ∈ h(c, S) + ∂h/∂t·(t − c)) — but not f's own derivative: an
/// interval Newton step or a sign of f′ needs the list itself. Returns the number of instructions
/// dropped (0: nothing folded, `out.list` and `out.fixed` are cleared). `ssa` is an SSA list as
/// for prune_ssa. Allocates nothing once `out` has grown to the size of `ssa`.
std::size_t fold_ssa(const std::vector<Instr>& ssa, const UpInterval* values, double width,
                     FoldedList& out);

}  // namespace certray::expr
