// tracers/tile_walker.cpp — one thread's walk down the 2D interval quadtree (see tile_walker.h).
#include "tracers/tile_walker.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "interval/interval.h"

namespace certray::tracers::detail {
namespace {

/// True when x is bounded, non-empty and defined on its box (no branch: run per instruction).
inline bool usable(const UpInterval& x) {
    constexpr double kMax = std::numeric_limits<double>::max();
    return x.defined & (std::abs(x.lower()) <= kMax) & (std::abs(x.upper()) <= kMax);
}

/// Observes a QuadInterval walk: bit k of `finite` is cleared when an intermediate enclosure of
/// lane k is unbounded, empty or not defined on its box.
struct FiniteObserver {
    unsigned finite = 0xf;
    void operator()(const expr::Instr& in, const QuadInterval* r) noexcept {
        const QuadInterval& q = r[in.out];
        finite &= unsigned{usable(q.v[0])} | unsigned{usable(q.v[1])} << 1 |
                  unsigned{usable(q.v[2])} << 2 | unsigned{usable(q.v[3])} << 3;
    }
};

/// Observes a walk over UpIntervals like FiniteObserver, for the one lane.
struct ScalarFiniteObserver {
    bool finite = true;
    void operator()(const expr::Instr& in, const UpInterval* r) noexcept {
        finite &= usable(r[in.out]);
    }
};

/// The decision from the enclosure f of f over a tile. When every intermediate enclosure is
/// bounded and defined on the box (`finite`), by induction over the tape every double
/// intermediate at a centre lies in its enclosure (a rounded operation stays inside the
/// outward-rounded range, which is finite, so nothing overflows to ±inf and no NaN appears), hence
/// f's double value there has the enclosure's sign. An unbounded intermediate (an overflow:
/// exp(1e300)) breaks this — the double becomes inf, then maybe NaN — so such a tile is never
/// decided, nor pruned, from its enclosure. Pruning keeps the double values at the centres for the
/// same reason (a dropped min/max branch is certainly on the other side at every centre, a folded
/// constant is the only double in its enclosure), so it too needs `finite`.
Verdict verdict(const UpInterval& f, bool finite) {
    if (finite && f.upper() < 0) return Verdict::Inside;
    if (finite && f.lower() >= 0) return Verdict::Outside;
    return Verdict::Open;
}

}  // namespace

TileWalker::TileWalker(const std::vector<double>& xs, const std::vector<double>& ys, Image2d& img,
                       WalkerScratch& scratch)
    : xs_(xs), ys_(ys), img_(img), s_(scratch) {}

// The box spanned by the tile's pixel centres: the same doubles the pixels are sampled at, so
// every centre lies in it (centres are monotone in i and j; y decreases as j grows).
UpInterval TileWalker::x_range(const Rect& r) const { return {xs_[r.i0], xs_[r.i0 + r.w - 1]}; }
UpInterval TileWalker::y_range(const Rect& r) const { return {ys_[r.j0 + r.h - 1], ys_[r.j0]}; }

Verdict TileWalker::settle(const Ssa& tape, const Rect& r, Ssa& out, const Ssa*& sub) {
    if (s_.values.size() < tape.size()) s_.values.resize(tape.size());
    ScalarFiniteObserver obs;
    {
        RoundingScope scope;
        const std::array<UpInterval, 3> box{x_range(r), y_range(r), UpInterval(0.0)};
        expr::detail::run<UpInterval>(tape, box, s_.values.data(), std::ref(obs));
    }
    const Verdict v = verdict(s_.values[tape.back().out], obs.finite);
    sub = v == Verdict::Open && obs.finite &&
                  expr::prune_ssa(tape, s_.values.data(), s_.prune_ws, out)
              ? &out
              : &tape;
    return v;
}

unsigned TileWalker::evaluate(const Ssa& tape, const Rect* r, int m,
                              std::vector<QuadInterval>& values) {
    if (values.size() < tape.size()) values.resize(tape.size());
    RoundingScope scope;
    std::array<QuadInterval, 3> box;
    for (int k = 0; k < QuadInterval::kLanes; ++k) {
        const Rect& t = r[k < m ? k : 0];
        box[0].v[k] = x_range(t);
        box[1].v[k] = y_range(t);
        box[2].v[k] = UpInterval(0.0);
    }
    FiniteObserver obs;
    expr::detail::run<QuadInterval>(tape, box, values.data(), std::ref(obs));
    return obs.finite;
}

void TileWalker::open(const Ssa& tape, const Rect& r, unsigned depth) {
    if (std::size_t{r.w} * r.h <= static_cast<std::size_t>(kBatch)) return leaf(tape, r);
    // The quarters: sides halved, rounded up.
    const unsigned w1 = (r.w + 1) / 2, h1 = (r.h + 1) / 2;
    std::array<Rect, 4> quarter;
    int m = 0;
    quarter[m++] = {r.i0, r.j0, w1, h1};
    if (r.w > w1) quarter[m++] = {r.i0 + w1, r.j0, r.w - w1, h1};
    if (r.h > h1) quarter[m++] = {r.i0, r.j0 + h1, w1, r.h - h1};
    if (r.w > w1 && r.h > h1) quarter[m++] = {r.i0 + w1, r.j0 + h1, r.w - w1, r.h - h1};
    WalkerScratch::Level& level = s_.levels[depth];
    const unsigned finite = evaluate(tape, quarter.data(), m, level.values);
    const QuadInterval& f = level.values[tape.back().out];
    for (int k = 0; k < m; ++k) {
        const bool lane_finite = (finite >> k) & 1u;
        const Verdict v = verdict(f.v[k], lane_finite);
        if (v != Verdict::Open) {
            fill(quarter[k], v);
            continue;
        }
        // level.tape is rewritten for each quarter, once the previous one is done.
        const bool pruned = lane_finite && expr::prune_ssa(tape, &level.values[0].v[k], s_.prune_ws,
                                                           level.tape, lane_stride);
        open(pruned ? level.tape : tape, quarter[k], depth + 1);
    }
}

void TileWalker::leaf(const Ssa& tape, const Rect& r) {
    if (s_.slots.size() < tape.size()) s_.slots.resize(tape.size());
    load_centres(r);
    expr::detail::run_batch(tape.data(), tape.data() + tape.size(), centres_.data(),
                            s_.slots.data(), static_cast<int>(r.w * r.h));
    store(r, s_.slots[tape.back().out]);
}

void TileWalker::leaf_full(const expr::Tape& tape, const Rect& r) {
    load_centres(r);
    store(r, s_.batch(tape, centres_));
}

void TileWalker::fill(const Rect& r, Verdict v) {
    fill(r, v == Verdict::Inside ? Pixel2d::Inside : Pixel2d::Outside);
}

void TileWalker::fill(const Rect& r, Pixel2d value) {
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        Pixel2d* row = img_.pixels.data() + std::size_t{j} * img_.width;
        std::fill(row + r.i0, row + r.i0 + r.w, value);
    }
    ++tiles_filled;
    if (value == Pixel2d::Inside) inside += std::uint64_t{r.w} * r.h;
}

void TileWalker::load_centres(const Rect& r) {
    int lane = 0;
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        for (unsigned i = r.i0; i < r.i0 + r.w; ++i, ++lane) {
            centres_[0][lane] = xs_[i];
            centres_[1][lane] = ys_[j];
        }
    }
    for (int k = lane; k < kBatch; ++k) {
        centres_[0][k] = centres_[0][0];
        centres_[1][k] = centres_[1][0];
    }
}

void TileWalker::store(const Rect& r, const Batch& f) {
    int lane = 0;
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        Pixel2d* row = img_.pixels.data() + std::size_t{j} * img_.width;
        for (unsigned i = r.i0; i < r.i0 + r.w; ++i, ++lane) {
            const Pixel2d p = classify(f[lane]);
            row[i] = p;
            inside += p == Pixel2d::Inside;
            undefined += p == Pixel2d::Undefined;
        }
    }
    ++leaf_batches;
}

}  // namespace certray::tracers::detail
