// tracers/region_tapes.cpp — the region octree of pruned tapes (see region_tapes.h).
#include "tracers/region_tapes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "expr/prune.h"
#include "tracers/octree.h"

namespace certray::tracers {
namespace {

using Box = RegionTapes::Box;

/// `box` inflated (tracers/octree.h) and cut to `within` (where the parent's tape holds), so a
/// child's tape is pruned only where its parent's equals f.
Box valid_box(const Box& box, const Box& within) {
    Box r = inflate(box);
    for (int i = 0; i < 3; ++i) {
        r[i] = Interval(std::max(r[i].lower(), within[i].lower()),
                        std::min(r[i].upper(), within[i].upper()));
    }
    return r;
}

}  // namespace

RegionTapes::RegionTapes(const expr::Tape& tape, const Box& bounds, const RegionOptions& options)
    : tape_(tape), bounds_(bounds) {
    const auto start = std::chrono::steady_clock::now();
    for (const Interval& b : bounds) {
        if (b.is_empty() || !std::isfinite(b.lower()) || !std::isfinite(b.upper()) ||
            !(b.lower() < b.upper())) {
            throw std::invalid_argument("RegionTapes: the bounds must be finite and non-empty");
        }
    }
    stats_.full_instructions = tape.size();
    // Per cell while building: its box (not inflated), its valid box, its level.
    std::vector<Box> box{bounds}, valid{inflate(bounds)};
    std::vector<int> level{0};
    Cell root;
    for (int i = 0; i < 3; ++i) {
        root.lo[i] = valid[0][i].lower();
        root.hi[i] = valid[0][i].upper();
    }
    tapes_.push_back(tape.size() > 0 ? expr::prune(tape, valid[0]).tape : tape);
    stats_.instructions = tapes_.back().size();
    cells_.push_back(root);
    for (std::size_t c = 0; c < cells_.size(); ++c) {
        const expr::Tape& parent = tapes_[cells_[c].tape];
        if (level[c] >= options.max_depth || parent.size() <= options.min_split ||
            cells_.size() + 8 > options.max_cells ||
            stats_.instructions + 8 * parent.size() > options.max_instructions) {
            continue;
        }
        std::array<double, 3> mid;
        for (int i = 0; i < 3; ++i) mid[i] = 0.5 * box[c][i].lower() + 0.5 * box[c][i].upper();
        std::array<Box, 8> child_box, child_valid;
        std::array<expr::PruneResult, 8> pruned;
        bool gained = false;
        for (int k = 0; k < 8; ++k) {
            for (int i = 0; i < 3; ++i) {
                child_box[k][i] = (k >> i & 1) ? Interval(mid[i], box[c][i].upper())
                                               : Interval(box[c][i].lower(), mid[i]);
            }
            child_valid[k] = valid_box(child_box[k], valid[c]);
            pruned[k] = expr::prune(parent, child_valid[k]);
            gained = gained || pruned[k].after < parent.size();
        }
        if (!gained) continue;  // no shorter tape below: the cell stays a leaf
        const std::uint32_t parent_tape = cells_[c].tape;
        cells_[c].mid = mid;
        cells_[c].first_child = static_cast<std::uint32_t>(cells_.size());
        for (int k = 0; k < 8; ++k) {
            Cell ch;
            for (int i = 0; i < 3; ++i) {
                ch.lo[i] = child_valid[k][i].lower();
                ch.hi[i] = child_valid[k][i].upper();
            }
            if (pruned[k].after < tapes_[parent_tape].size()) {
                ch.tape = static_cast<std::uint32_t>(tapes_.size());
                stats_.instructions += pruned[k].after;
                tapes_.push_back(std::move(pruned[k].tape));
            } else {
                ch.tape = parent_tape;
            }
            cells_.push_back(ch);
            box.push_back(child_box[k]);
            valid.push_back(child_valid[k]);
            level.push_back(level[c] + 1);
        }
    }
    stats_.cells = cells_.size();
    stats_.distinct_tapes = tapes_.size();
    for (std::size_t c = 0; c < cells_.size(); ++c) {
        if (cells_[c].first_child != 0) continue;
        ++stats_.leaves;
        stats_.mean_leaf_instructions +=
            std::ldexp(static_cast<double>(tapes_[cells_[c].tape].size()), -3 * level[c]);
    }
    stats_.build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

const expr::Tape& RegionTapes::at(const Box& q) const {
    auto inside = [&q](const Cell& c) {
        for (int i = 0; i < 3; ++i) {
            if (!(q[i].lower() >= c.lo[i] && q[i].upper() <= c.hi[i])) return false;
        }
        return !q[0].is_empty() && !q[1].is_empty() && !q[2].is_empty();
    };
    const Cell* c = &cells_[0];
    if (!inside(*c)) return tape_;
    while (c->first_child != 0) {
        int k = 0;
        for (int i = 0; i < 3; ++i) {
            if (0.5 * q[i].lower() + 0.5 * q[i].upper() >= c->mid[i]) k |= 1 << i;
        }
        const Cell& child = cells_[c->first_child + k];
        if (!inside(child)) break;
        c = &child;
    }
    return tapes_[c->tape];
}

const expr::Tape& RegionTapes::at(const std::array<double, 3>& p) const {
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) return tape_;
    return at(Box{Interval(p[0]), Interval(p[1]), Interval(p[2])});
}

}  // namespace certray::tracers
