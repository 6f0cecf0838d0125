// tracers/region_tapes.h — tapes pruned per region of space, for the point, gradient and local
// Lipschitz evaluations of the approximate tracers.
//
// Contract: an octree over the scene bounds, built once (up front, in the constructor) and read
// by any number of threads; each cell keeps a tape pruned from its parent's by one interval
// evaluation over the cell inflated by 2⁻²⁰ of its size (expr::prune; the root's from the full
// tape over the inflated bounds). By prune's contract a cell's tape is the same real function as
// f at every point of its inflated cell, and its enclosure over any box inside it is contained in
// the full tape's; `at(box)` returns the tape of the deepest cell whose inflated box contains the
// whole query box, and the full tape when no cell does (a box that reaches outside the bounds). So
// replacing f's tape by at(box) in an evaluation over `box` (a point, a point's box, a local
// Lipschitz box) changes no real value; double evaluations agree wherever the cell's interval
// enclosures were bounded and defined (expr/prune.h). A cell is split only while its tape is
// longer than `min_split` instructions, some child's tape is shorter than its own, and the budget
// of cells and stored instructions allows: a model without min/max (a polynomial) keeps one cell.
// Reference: Fidget's and libfive's per-region tape shortening (docs/theory/tape.md);
// docs/theory/sphere_tracing.md ("Region-pruned tapes").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"

namespace certray::tracers {

/// The budget of a RegionTapes.
struct RegionOptions {
    /// Deepest level (the root cell is level 0).
    int max_depth = 4;
    /// Most cells in the tree.
    std::size_t max_cells = 4681;  // 1 + 8 + 64 + 512 + 4096: every cell to level 4
    /// Most instructions stored over all distinct tapes (a bound on memory: 48 bytes each, the
    /// register and the SSA form; 2²⁰ instructions: 48 MiB).
    std::size_t max_instructions = std::size_t{1} << 20;
    /// A cell whose tape is this short is not split.
    std::size_t min_split = 16;
};

/// What a RegionTapes holds.
struct RegionStats {
    std::size_t cells = 0, leaves = 0, distinct_tapes = 0;
    std::size_t instructions = 0;       ///< summed over the distinct tapes
    std::size_t full_instructions = 0;  ///< the full tape's length
    double mean_leaf_instructions = 0;  ///< over the leaves, weighted by volume
    double build_seconds = 0;
};

/// Region-pruned tapes of one scene (see the file contract). Thread-safe after construction.
class RegionTapes {
  public:
    using Box = std::array<Interval, 3>;

    /// Prunes `tape` (which must outlive this object) over `bounds` (finite, non-empty) and its
    /// cells, within `options`' budget.
    RegionTapes(const expr::Tape& tape, const Box& bounds, const RegionOptions& options = {});
    RegionTapes(const RegionTapes&) = delete;
    RegionTapes& operator=(const RegionTapes&) = delete;

    /// A tape equal to f at every point of `box` (see the file contract): the shortest one held
    /// for a cell containing the box, else the full tape.
    const expr::Tape& at(const Box& box) const;
    /// at() for the exact point p.
    const expr::Tape& at(const std::array<double, 3>& p) const;

    /// The full tape.
    const expr::Tape& tape() const noexcept { return tape_; }
    const Box& bounds() const noexcept { return bounds_; }
    const RegionStats& stats() const noexcept { return stats_; }

  private:
    struct Cell {
        std::array<double, 3> lo{}, hi{};  ///< where its tape holds (the inflated cell)
        std::array<double, 3> mid{};       ///< the split point of its children
        std::uint32_t first_child = 0;     ///< 0: a leaf (the root is never a child)
        std::uint32_t tape = 0;            ///< index into tapes_
    };

    const expr::Tape& tape_;
    Box bounds_;
    std::vector<Cell> cells_;
    std::deque<expr::Tape> tapes_;  // stable references while the tree grows
    RegionStats stats_;
};

}  // namespace certray::tracers
