// tracers/region_tapes.cpp — the region octree of pruned tapes, built to a depth up front and
// deeper on demand (see region_tapes.h).
#include "tracers/region_tapes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "expr/prune.h"
#include "tracers/octree.h"

namespace certray::tracers {
namespace {

using Box = RegionTapes::Box;

// A child slot's state: not built yet, being built by one thread, or built (its pointer then
// final: a cell, or null where the child is not kept).
constexpr std::uint8_t kUnbuilt = 0, kBuilding = 1, kBuilt = 2;

// A cell whose tape is no shorter than its parent's (the root's: than the full tape) is kept, on
// its parent's tape, at most this many levels in a row: a choice that only a grandchild's cell
// decides is still found (the molecule's smooth unions prune nothing at level 1, a third of the
// tape at level 2), while pruning that gains nothing stops.
constexpr int kStaleLevels = 2;

/// True when pruning can shorten `tape` on some box: it holds a choice (min, max, and, or).
/// Otherwise only a subexpression constant on the box could fold, which a model without choices
/// (a polynomial) does not have below its bounds: such a tape keeps one cell.
bool has_choices(const expr::Tape& tape) {
    for (const expr::Instr& in : tape.instrs()) {
        if (in.op == expr::Op::Min || in.op == expr::Op::Max || in.op == expr::Op::And ||
            in.op == expr::Op::Or) {
            return true;
        }
    }
    return false;
}

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

/// One cell. Everything but the child slots is written before the cell is published and never
/// after; a slot's pointer is written before its state becomes kBuilt (release), and read after
/// the state is seen kBuilt (acquire).
struct RegionTapes::Node {
    std::array<double, 3> lo{}, hi{};  ///< where its tape holds (the inflated cell)
    std::array<double, 3> mid{};       ///< the split point of its children
    Box box;                           ///< the cell, not inflated
    Box valid;                         ///< the inflated cell, as a box
    int level = 0;
    int stale = 0;        ///< levels in a row, this one included, whose tape is no shorter
    bool splits = false;  ///< its tape holds choices and is longer than min_split
    expr::Tape own;       ///< the pruned tape, when shorter than the parent's
    const expr::Tape* tape = &own;  ///< own, or the parent's tape
    mutable std::array<std::atomic<std::uint8_t>, 8> state{};
    mutable std::array<std::atomic<const Node*>, 8> child{};

    Node(const Box& cell, const Box& inflated, int lvl, expr::Tape t)
        : box(cell), valid(inflated), level(lvl), own(std::move(t)) {
        for (int i = 0; i < 3; ++i) {
            lo[i] = valid[i].lower();
            hi[i] = valid[i].upper();
            mid[i] = 0.5 * box[i].lower() + 0.5 * box[i].upper();
        }
    }

    /// Child k's cell (bit i of k: the upper half along axis i).
    Box child_box(int k) const {
        Box b;
        for (int i = 0; i < 3; ++i) {
            b[i] =
                (k >> i & 1) ? Interval(mid[i], box[i].upper()) : Interval(box[i].lower(), mid[i]);
        }
        return b;
    }

    /// True when the query box q (non-empty) lies in the inflated cell.
    bool holds(const Box& q) const {
        for (int i = 0; i < 3; ++i) {
            if (!(q[i].lower() >= lo[i] && q[i].upper() <= hi[i])) return false;
        }
        return true;
    }
};

RegionTapes::RegionTapes(const expr::Tape& tape, const Box& bounds, const RegionOptions& options)
    : tape_(tape), bounds_(bounds), options_(options) {
    const auto start = std::chrono::steady_clock::now();
    for (const Interval& b : bounds) {
        if (b.is_empty() || !std::isfinite(b.lower()) || !std::isfinite(b.upper()) ||
            !(b.lower() < b.upper())) {
            throw std::invalid_argument("RegionTapes: the bounds must be finite and non-empty");
        }
    }
    const Box valid = inflate(bounds);
    root_ = std::make_unique<Node>(bounds, valid, 0,
                                   tape.size() > 0 ? expr::prune(tape, valid).tape : tape);
    root_->stale = root_->own.size() < tape.size() ? 0 : 1;
    root_->splits = root_->own.size() > options_.min_split && has_choices(root_->own);
    cells_ = 1;
    instructions_ = root_->own.size();
    // Breadth first to eager_depth; a child refused by the eager budget stays unbuilt (at() may
    // build it later, within max_instructions).
    std::vector<const Node*> level{root_.get()}, next;
    for (int depth = 0; depth < std::min(options_.eager_depth, options_.max_depth); ++depth) {
        next.clear();
        for (const Node* n : level) {
            if (!n->splits) continue;
            for (int k = 0; k < 8; ++k) {
                const Node* c = build_child(*n, k, valid_box(n->child_box(k), n->valid),
                                            options_.eager_instructions);
                if (c == nullptr && instructions_ + n->tape->size() > options_.eager_instructions) {
                    continue;  // refused for the budget, not for its length
                }
                n->child[k].store(c, std::memory_order_relaxed);
                n->state[k].store(kBuilt, std::memory_order_relaxed);
                if (c) next.push_back(c);
            }
        }
        std::swap(level, next);
    }
    lazy_cells_ = 0;
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

RegionTapes::~RegionTapes() = default;

const RegionTapes::Node* RegionTapes::build_child(const Node& parent, int k, const Box& valid,
                                                  std::size_t max_instructions) const {
    // Reserve a cell and the parent's length (the child is no longer), then settle.
    const std::size_t n = parent.tape->size();
    if (cells_.fetch_add(1) >= options_.max_cells) {
        cells_.fetch_sub(1);
        return nullptr;
    }
    if (instructions_.fetch_add(n) + n > max_instructions) {
        instructions_.fetch_sub(n);
        cells_.fetch_sub(1);
        return nullptr;
    }
    expr::PruneResult p;
    try {
        p = expr::prune(*parent.tape, valid);
    } catch (...) {
        instructions_.fetch_sub(n);
        cells_.fetch_sub(1);
        throw;
    }
    const bool shorter = p.after < n;
    if (!shorter && parent.stale >= kStaleLevels) {  // the parent's cell answers for it
        instructions_.fetch_sub(n);
        cells_.fetch_sub(1);
        return nullptr;
    }
    instructions_.fetch_sub(shorter ? n - p.after : n);
    auto node = std::make_unique<Node>(parent.child_box(k), valid, parent.level + 1,
                                       shorter ? std::move(p.tape) : expr::Tape());
    if (shorter) {
        node->splits = node->own.size() > options_.min_split && has_choices(node->own);
    } else {  // kept on its parent's tape: a grandchild may be shorter
        node->tape = parent.tape;
        node->stale = parent.stale + 1;
        node->splits = parent.splits;
    }
    const Node* c = node.get();
    const std::lock_guard<std::mutex> lock(owned_mutex_);
    owned_.push_back(std::move(node));
    return c;
}

double RegionTapes::leaf_size() const noexcept {
    double side = 0;
    for (const Interval& b : bounds_) side = std::max(side, b.upper() - b.lower());
    return std::ldexp(side, -options_.max_depth);
}

const expr::Tape& RegionTapes::at(const Box& q) const {
    if (q[0].is_empty() || q[1].is_empty() || q[2].is_empty() || !root_->holds(q)) return tape_;
    const Node* c = root_.get();
    while (c->level < options_.max_depth && c->splits) {
        int k = 0;
        for (int i = 0; i < 3; ++i) {
            if (0.5 * q[i].lower() + 0.5 * q[i].upper() >= c->mid[i]) k |= 1 << i;
        }
        std::atomic<std::uint8_t>& state = c->state[k];
        std::uint8_t s = state.load(std::memory_order_acquire);
        if (s != kBuilt) {
            // Build the child only if the query would descend into it.
            const Box valid = valid_box(c->child_box(k), c->valid);
            for (int i = 0; i < 3; ++i) {
                if (!(q[i].lower() >= valid[i].lower() && q[i].upper() <= valid[i].upper())) {
                    return *c->tape;
                }
            }
            if (s == kUnbuilt &&
                state.compare_exchange_strong(s, kBuilding, std::memory_order_acquire)) {
                const Node* built = nullptr;
                try {
                    built = build_child(*c, k, valid, options_.max_instructions);
                } catch (...) {  // publish "no child" so that no thread waits for ever
                    state.store(kBuilt, std::memory_order_release);
                    state.notify_all();
                    throw;
                }
                if (built) lazy_cells_.fetch_add(1, std::memory_order_relaxed);
                c->child[k].store(built, std::memory_order_relaxed);
                state.store(kBuilt, std::memory_order_release);
                state.notify_all();
            } else {
                // Another thread builds it: wait, so that the answer does not depend on timing.
                while (s != kBuilt) {
                    state.wait(s, std::memory_order_acquire);
                    s = state.load(std::memory_order_acquire);
                }
            }
        }
        const Node* child = c->child[k].load(std::memory_order_relaxed);
        if (child == nullptr || !child->holds(q)) break;
        c = child;
    }
    return *c->tape;
}

const expr::Tape& RegionTapes::at(const std::array<double, 3>& p) const {
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) return tape_;
    return at(Box{Interval(p[0]), Interval(p[1]), Interval(p[2])});
}

RegionStats RegionTapes::stats() const {
    RegionStats st;
    st.full_instructions = tape_.size();
    st.build_seconds = build_seconds_;
    st.lazy_cells = lazy_cells_.load();
    std::vector<const Node*> stack{root_.get()};
    while (!stack.empty()) {
        const Node* n = stack.back();
        stack.pop_back();
        ++st.cells;
        if (n->tape == &n->own) {
            ++st.distinct_tapes;
            st.instructions += n->own.size();
        }
        st.depth = std::max(st.depth, n->level);
        // The part of the cell no built child covers answers with this cell's tape.
        double uncovered = std::ldexp(1.0, -3 * n->level);
        for (int k = 0; k < 8; ++k) {
            if (n->state[k].load(std::memory_order_acquire) != kBuilt) continue;
            if (const Node* c = n->child[k].load(std::memory_order_relaxed)) {
                stack.push_back(c);
                uncovered -= std::ldexp(1.0, -3 * c->level);
            }
        }
        if (uncovered == std::ldexp(1.0, -3 * n->level)) ++st.leaves;
        st.mean_leaf_instructions += uncovered * static_cast<double>(n->tape->size());
    }
    return st;
}

}  // namespace certray::tracers
