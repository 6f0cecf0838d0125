// tracers/image2d.h — the 2D image of a scene (no z): the sign of f at each pixel centre, in
// double, computed by an interval quadtree.
//
// Contract: pixel (i, j) of a W×H image over [xmin, xmax]×[ymin, ymax] is sampled at its centre
// (pixel_center_x(i), pixel_center_y(j)) — i from the left, j from the top row down — and is
// Inside exactly when the double evaluation of f there is < 0, Undefined when it is NaN, and
// Outside otherwise (f ≥ 0, or +inf). The result equals that brute-force double evaluation pixel
// for pixel: a tile is filled without looking at its pixels only when the interval enclosure of f
// over the box spanned by the tile's pixel centres (the same doubles, computed by the same
// functions) is defined and continuous there and certainly < 0 (Inside) or certainly ≥ 0 (Outside);
// every other tile is split, with the tape pruned to its box (expr::prune_ssa, from the choices of
// that same evaluation), down to tiles of at most kBatch pixels, which are evaluated at their
// centres in one Batch walk (bit for bit the double evaluator). Tiles are evaluated four at a
// time (tracers/quad_interval.h, tracers/tile_walker.h); threads take square tiles of side
// `root_tile` in Z order (tracers/image2d.cpp). Walker buffers are kept between calls (about 1 MB
// per thread ever used), so that repeated renders fault in no fresh memory.
// Reference: Duff 1992 (interval quadtrees for implicit curves); Keeter 2020 (tiles with tapes
// shortened per tile); Fidget's and libfive's 2D renderers; docs/theory/rendering.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "expr/tape.h"
#include "tracers/progress.h"

namespace certray::tracers {

/// What a pixel of a 2D image shows.
enum class Pixel2d : std::uint8_t { Outside = 0, Inside = 1, Undefined = 2 };

/// Where and how large the 2D image is, and how it is computed.
struct Image2dOptions {
    std::array<double, 2> x{-1.0, 1.0};  ///< [xmin, xmax]
    std::array<double, 2> y{-1.0, 1.0};  ///< [ymin, ymax]
    unsigned width = 1024;
    unsigned height = 1024;
    unsigned threads = 0;     ///< worker threads; 0: one per hardware thread
    unsigned root_tile = 64;  ///< side of the tiles handed to threads (≥ 8; a power of two is best)
    bool use_quadtree = true;  ///< false: evaluate every pixel centre (the brute force, batched)
    WorkProgress* progress = nullptr;  ///< when set, advanced tile by tile (tracers/progress.h)
};

/// The classified pixels (row-major, top row first) and their counts.
struct Image2d {
    unsigned width = 0;
    unsigned height = 0;
    std::vector<Pixel2d> pixels;
    std::uint64_t inside = 0;        ///< pixels with f < 0
    std::uint64_t undefined = 0;     ///< pixels where f is NaN
    std::uint64_t tiles_filled = 0;  ///< tiles decided by one interval evaluation
    std::uint64_t leaf_batches = 0;  ///< Batch walks (≤ kBatch pixel centres each)
    double seconds = 0;              ///< wall-clock time of render_2d

    Pixel2d at(unsigned i, unsigned j) const { return pixels[std::size_t{j} * width + i]; }
};

/// x of the centre of pixel column i: xmin + (i + 0.5)·((xmax − xmin)/W), in double. Monotone
/// non-decreasing in i (each step is a monotone rounded operation).
double pixel_center_x(const Image2dOptions& o, unsigned i);
/// y of the centre of pixel row j (row 0 at the top): ymax − (j + 0.5)·((ymax − ymin)/H), in
/// double. Monotone non-increasing in j.
double pixel_center_y(const Image2dOptions& o, unsigned j);

/// Classifies every pixel (see the file contract). `tape` must not read z. Throws
/// std::invalid_argument for an empty size, bounds that are not finite with lo < hi, or a tape that
/// reads z.
Image2d render_2d(const expr::Tape& tape, const Image2dOptions& options);

/// The classification of one double value of f.
inline Pixel2d classify(double f) {
    return f < 0 ? Pixel2d::Inside : (f != f ? Pixel2d::Undefined : Pixel2d::Outside);
}

}  // namespace certray::tracers
