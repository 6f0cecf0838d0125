// tracers/region_tapes.h — tapes pruned per region of space, for the point, gradient and local
// Lipschitz evaluations of the approximate tracers.
//
// Contract: an octree over the scene bounds, read by any number of threads; each cell keeps a tape
// pruned from its parent's by one interval evaluation over the cell inflated by 2⁻²⁰ of its size
// and cut to the parent's inflated cell (expr::prune; the root's from the full tape over the
// inflated bounds). By prune's contract a cell's tape is the same real function as f at every point
// of its inflated cell, and its enclosure over any box inside it is contained in the full tape's;
// `at(box)` returns the tape of the deepest cell whose inflated box contains the whole query box,
// and the full tape when no cell does (a box that reaches outside the bounds). So replacing f's
// tape by at(box) in an evaluation over `box` (a point, a point's box, a local Lipschitz box)
// changes no real value; double evaluations agree wherever the cell's interval enclosures were
// bounded and defined (expr/prune.h).
//
// The tree is the one that splitting every cell would give, to `max_depth`, except that a child
// whose tape is not shorter than its parent's is kept (on its parent's tape) at most two levels
// in a row, and a cell whose tape has at most `min_split` instructions or no choice (min, max,
// and, or) is not split: a model without min/max (a polynomial) keeps one cell. The constructor
// builds the tree to `eager_depth` (breadth first, while the stored instructions stay within
// `eager_instructions`); a child it did not build (deeper, or refused by that budget) is built
// when at() first needs it (the query box lies in the child's inflated cell), by the calling
// thread, and published once complete: other threads that need the same child wait for it, so no
// reader ever sees a half-built cell. Within the budget (`max_cells`, `max_instructions`) at(box)
// is therefore a function of the box alone, whatever the order or the threads of the queries;
// once the budget is spent no further cell is built and at() returns the deepest cell built (the
// same real function).
// Cells are never freed before the RegionTapes: a returned tape lives as long as it.
// Reference: Fidget's and libfive's per-region tape shortening (docs/theory/tape.md);
// docs/theory/sphere_tracing.md ("Region-pruned tapes").
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"

namespace certray::tracers {

/// The budget of a RegionTapes.
struct RegionOptions {
    /// Deepest level (the root cell is level 0), reached lazily below `eager_depth` or where the
    /// eager budget ran out. 4 measured best on the molecule under the instruction budget (5 as
    /// fast with twice the memory, 6 slower: its budget spent on cells the rays meet once;
    /// docs/benchmarks.md, "Region tapes near the rays").
    int max_depth = 4;
    /// Levels built by the constructor (within `eager_instructions`); deeper ones on demand.
    int eager_depth = 4;
    /// Most cells in the tree.
    std::size_t max_cells = std::size_t{1} << 16;
    /// Most instructions stored over all cells' tapes, lazily built ones included (a bound on
    /// memory: 48 bytes each, the register and the SSA form; 2²³ instructions: 384 MiB).
    std::size_t max_instructions = std::size_t{1} << 23;
    /// Most instructions the constructor stores (2²⁰: 48 MiB).
    std::size_t eager_instructions = std::size_t{1} << 20;
    /// A cell whose tape is this short is not split.
    std::size_t min_split = 16;
};

/// What a RegionTapes holds at the time of the call (lazily built cells included).
struct RegionStats {
    std::size_t cells = 0, leaves = 0, distinct_tapes = 0;
    std::size_t lazy_cells = 0;         ///< cells built by at(), after the constructor
    int depth = 0;                      ///< the deepest level built
    std::size_t instructions = 0;       ///< summed over the distinct tapes
    std::size_t full_instructions = 0;  ///< the full tape's length
    /// Over the bounds, weighted by volume: the tape length at() gives a point query there.
    double mean_leaf_instructions = 0;
    double build_seconds = 0;  ///< the constructor's
};

/// Region-pruned tapes of one scene (see the file contract). Thread-safe: at() and stats() may be
/// called from any number of threads at once.
class RegionTapes {
  public:
    using Box = std::array<Interval, 3>;

    /// Prunes `tape` (which must outlive this object) over `bounds` (finite, non-empty) and its
    /// cells to `options.eager_depth`, within `options`' budget.
    RegionTapes(const expr::Tape& tape, const Box& bounds, const RegionOptions& options = {});
    RegionTapes(const RegionTapes&) = delete;
    RegionTapes& operator=(const RegionTapes&) = delete;
    ~RegionTapes();

    /// A tape equal to f at every point of `box` (see the file contract): the tape of the deepest
    /// cell containing the box (built now if within the budget), else the full tape.
    const expr::Tape& at(const Box& box) const;
    /// at() for the exact point p.
    const expr::Tape& at(const std::array<double, 3>& p) const;

    /// The full tape.
    const expr::Tape& tape() const noexcept { return tape_; }
    const Box& bounds() const noexcept { return bounds_; }
    /// The largest side of a cell at the deepest level (the bounds' largest side / 2^max_depth).
    double leaf_size() const noexcept;
    RegionStats stats() const;

  private:
    struct Node;

    /// Child k of `parent` (its inflated cell `valid`), pruned and counted against the budget of
    /// `max_instructions` instructions; null when it would not be shorter or the budget is spent.
    const Node* build_child(const Node& parent, int k, const Box& valid,
                            std::size_t max_instructions) const;

    const expr::Tape& tape_;
    Box bounds_;
    RegionOptions options_;
    std::unique_ptr<Node> root_;
    double build_seconds_ = 0;
    // The budget: reserved (atomically) before a child is pruned, settled after.
    mutable std::atomic<std::size_t> cells_{0}, instructions_{0}, lazy_cells_{0};
    mutable std::mutex owned_mutex_;                    // guards owned_
    mutable std::vector<std::unique_ptr<Node>> owned_;  // every cell but the root
};

}  // namespace certray::tracers
