// tracers/tile_walker.h — one thread's walk down the 2D interval quadtree (internal to
// tracers/image2d.cpp).
//
// Contract: open(tape, r) writes every pixel of the rectangle r of the image with the
// classification of the double value of f at its centre (image2d.h), given an SSA list `tape`
// that equals f, as doubles, at every centre of r (the full tape, or one pruned to a tile around
// r under the rule below). Tiles are evaluated four at a time, one QuadInterval walk over the
// boxes spanned by their pixel centres (the same doubles the pixels are sampled at); a tile is
// filled from its enclosure, or the list pruned to it from its lane (expr::prune_ssa), only when
// every intermediate enclosure of its lane is bounded and defined (see verdict() in the .cpp).
// Leaves of at most kBatch pixels are one Batch walk of their pruned list (over half the lanes
// when they fill only half: the 8×8 tiles). Buffers are per depth
// and per walker: nothing is allocated once they have grown.
// Reference: Duff 1992 (interval quadtrees); Keeter 2020 (per-tile pruning from the choices of the
// tile's own evaluation); docs/theory/rendering.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "expr/eval.h"
#include "expr/prune.h"
#include "expr/tape.h"
#include "interval/batch.h"
#include "tracers/image2d.h"
#include "tracers/quad_interval.h"

namespace certray::tracers::detail {

/// An SSA list in the sense of expr::prune_ssa (each instruction writes its own slot).
using Ssa = std::vector<expr::Instr>;

/// The pixels [i0, i0 + w) × [j0, j0 + h); w, h ≥ 1.
struct Rect {
    unsigned i0, j0, w, h;
};

/// What an enclosure says of a tile: every pixel inside, every pixel outside, or open.
enum class Verdict : std::uint8_t { Inside, Outside, Open };

/// A tile as one thread last settled it: its verdict and, when open, the list its pixels
/// evaluate (`own`, or a list of a tile above it). `id` names the tile (tracers/image2d.cpp).
struct Settled {
    std::uint64_t id = ~std::uint64_t{0};
    Verdict verdict = Verdict::Open;
    const Ssa* tape = nullptr;
    Ssa own;
};

/// Everything a walker allocates, kept between renders (tracers/image2d.cpp pools them), so that
/// a render reuses memory instead of faulting in fresh pages.
struct WalkerScratch {
    /// The buffers of one depth of open(): the enclosures of the walk over a tile's quarters,
    /// and the list pruned to the quarter being opened.
    struct Level {
        std::vector<QuadInterval> values;
        Ssa tape;
    };
    /// Deeper than any quadtree: each level halves the sides of a tile of at most 2³² pixels.
    static constexpr unsigned kMaxDepth = 40;

    std::vector<Level> levels = std::vector<Level>(kMaxDepth);  ///< never resized
    std::vector<UpInterval> values;  ///< the enclosures of settle()'s walks
    std::vector<Settled> path;       ///< per level of tiles above the threads' (image2d.cpp)
    expr::PruneWorkspace prune_ws;
    std::vector<Batch> slots;  ///< Batch slots of a leaf's SSA list
    expr::Evaluator<Batch> batch;
};

/// One thread's walk: the image, the pixel centres and a scratch; counters.
class TileWalker {
  public:
    /// `xs`, `ys`: the pixel centres (image2d.h); `img`: the image whose pixels are written.
    TileWalker(const std::vector<double>& xs, const std::vector<double>& ys, Image2d& img,
               WalkerScratch& scratch);

    /// Classifies every pixel of `r` with `tape` (see the file contract). `depth` picks the
    /// buffers: a call at depth d uses those of d and deeper ones.
    void open(const Ssa& tape, const Rect& r, unsigned depth = 0);

    /// Evaluates the tile `r` alone with `tape` and returns its verdict; when open, `sub` is the
    /// list its pixels and subtiles evaluate: `out`, pruned to r, or `tape` itself when pruning
    /// is not allowed or drops nothing. Writes no pixel.
    Verdict settle(const Ssa& tape, const Rect& r, Ssa& out, const Ssa*& sub);

    /// Writes every pixel of `r` with a decided verdict.
    void fill(const Rect& r, Verdict v);

    /// The brute force: the pixel centres of `r` (at most kBatch) with the full,
    /// register-allocated tape.
    void leaf_full(const expr::Tape& tape, const Rect& r);

    std::uint64_t tiles_filled = 0;  ///< tiles decided by their enclosure
    std::uint64_t leaf_batches = 0;  ///< Batch walks
    std::uint64_t inside = 0;        ///< pixels written Inside
    std::uint64_t undefined = 0;     ///< pixels written Undefined

  private:
    /// One QuadInterval walk of `tape` over the boxes of the tiles r[0, m), m ≤ 4, into
    /// `values` (lanes past m repeat r[0]). Returns the lanes (bit k) whose every intermediate
    /// enclosure is bounded and defined.
    unsigned evaluate(const Ssa& tape, const Rect* r, int m, std::vector<QuadInterval>& values);
    /// The at most kBatch pixel centres of `r` in one Batch walk of the SSA list `tape`.
    void leaf(const Ssa& tape, const Rect& r);
    /// Writes every pixel of `r`.
    void fill(const Rect& r, Pixel2d value);
    /// Loads the centres of `r` into the lanes (lanes past the tile repeat its first centre).
    void load_centres(const Rect& r);
    /// Classifies the pixels of `r` from the lanes of `f`.
    void store(const Rect& r, const Batch& f);
    /// The box spanned by the pixel centres of `r`.
    UpInterval x_range(const Rect& r) const;
    UpInterval y_range(const Rect& r) const;

    const std::vector<double>& xs_;
    const std::vector<double>& ys_;
    Image2d& img_;
    WalkerScratch& s_;
    std::array<Batch, 3> centres_{Batch{}, Batch{}, Batch{0.0}};  ///< x, y (and z = 0) per lane
};

}  // namespace certray::tracers::detail
