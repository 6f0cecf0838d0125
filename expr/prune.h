// expr/prune.h — region pruning: a shorter tape that equals f on a box.
//
// Contract: for every point q of the box, eval(prune(t, box).tape, q) and eval(t, q) are the same
// real number (and the pruned tape's interval result over the box is contained in the full one's).
// A min/max branch is dropped only where interval evaluation proves it inactive on the whole box
// *and* the dropped branch is defined there (dropping an undefined branch would make f defined
// where it is not). A subexpression whose enclosure over the box is one point, defined on the
// whole box, becomes that constant. Reference: Fidget's tape simplification, libfive's per-region
// tape shortening (docs/theory/tape.md).
#pragma once

#include <array>
#include <cstddef>

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

}  // namespace certray::expr
