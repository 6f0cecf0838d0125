// tracers/image2d.cpp — the 2D interval quadtree (see image2d.h): the tiles dealt to threads, the
// tiles above them, the threads.
//
// Threads take square tiles of side `root_tile` in Z order from a TaskQueue (each its own range,
// then helping from the back of the others') and open them with a TileWalker (tile_walker.h: each
// tile is evaluated once, four at a time, on the SSA list its parent pruned to it, and pruned from
// that same evaluation). The tiles above them, up to one covering the image, each thread settles
// for itself along its path from the top: a little work done twice on two threads, against
// storing the pruned lists of shared tiles (on this machine a fresh page costs ~35 µs, more than
// the walks). Walker buffers are pooled between renders. Reference: Keeter 2020, "Massively
// parallel rendering of complex closed-form implicit surfaces" (tiles evaluated and their tapes
// shortened level by level).
#include "tracers/image2d.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "tracers/parallel.h"
#include "tracers/tile_walker.h"

namespace certray::tracers {
namespace {

using detail::Rect;
using detail::Settled;
using detail::Ssa;
using detail::TileWalker;
using detail::Verdict;
using detail::WalkerScratch;

void check_options(const expr::Tape& tape, const Image2dOptions& o) {
    if (o.width == 0 || o.height == 0) throw std::invalid_argument("render_2d: empty image size");
    for (const auto& r : {o.x, o.y}) {
        if (!(std::isfinite(r[0]) && std::isfinite(r[1]) && r[0] < r[1])) {
            throw std::invalid_argument("render_2d: bounds need finite lo < hi");
        }
    }
    if (tape.uses_var(2)) throw std::invalid_argument("render_2d: the scene reads z (it is 3D)");
    if (o.root_tile < 8) throw std::invalid_argument("render_2d: root tile side must be >= 8");
}

/// The tiles of side root·2^k, from k = 0 (the tiles threads take) up to the top level, one
/// tile over the whole image. Tile (k, x, y) covers pixels from (x, y)·root·2^k, clipped to the
/// image. Each thread settles the tiles above its level-0 tiles itself (a scalar walk and a
/// pruning each, cached in WalkerScratch::path along the path from the top), so threads share
/// nothing but the image — whose pixels they write in disjoint level-0 tiles — and the queue.
class TilePyramid {
  public:
    TilePyramid(const Ssa& full, unsigned width, unsigned height, unsigned root)
        : full_(full), width_(width), height_(height) {
        for (unsigned k = 0;; ++k) {
            const std::uint64_t s = std::uint64_t{root} << k;
            const auto nx = static_cast<unsigned>((width + s - 1) / s);
            const auto ny = static_cast<unsigned>((height + s - 1) / s);
            levels_.push_back({s, nx, ny});
            if (nx == 1 && ny == 1) break;
        }
        // Level-0 tiles in Z order (by their quadrant in the top tile first, then in the next
        // level down, …), so that the tiles a thread takes one after the other mostly share the
        // tiles above them, which it has settled already.
        const auto top = static_cast<unsigned>(levels_.size()) - 1;
        for (unsigned ty = 0; ty < levels_[0].ny; ++ty) {
            for (unsigned tx = 0; tx < levels_[0].nx; ++tx) {
                std::uint64_t key = 0;
                for (unsigned k = 0; k < top; ++k) {  // which subtile of its level-(k+1) parent
                    key |= std::uint64_t{((tx >> k) & 1u) | (((ty >> k) & 1u) << 1)} << (2 * k);
                }
                order_.push_back({key, tx, ty});
            }
        }
        std::sort(order_.begin(), order_.end(),
                  [](const Entry& a, const Entry& b) { return a.key < b.key; });
    }

    /// Number of level-0 tiles.
    std::size_t size() const { return order_.size(); }

    /// The pixels of the n-th level-0 tile (in Z order).
    Rect rect(std::size_t n) const { return rect(0, order_[n].tx, order_[n].ty); }

    /// Classifies the pixels of the n-th level-0 tile; `path` is the thread's cache of settled
    /// tiles above it (cleared by begin()).
    void run(std::size_t n, TileWalker& walker, std::vector<Settled>& path) const {
        const Entry& e = order_[n];
        const auto top = static_cast<unsigned>(levels_.size()) - 1;
        const Ssa* tape = &full_;
        Verdict v = Verdict::Open;
        // The tiles above, from the top down. Not the top tile itself (the whole image): its
        // quarters evaluate the full tape, which spares a copy of a list that the whole image
        // seldom shortens, and the memory for it.
        for (unsigned k = top > 0 ? top - 1 : 0; k >= 1; --k) {
            const unsigned x = e.tx >> k, y = e.ty >> k;
            const std::uint64_t id = std::uint64_t{y} * levels_[k].nx + x;
            Settled& s = path[k];
            if (s.id != id) {
                s.id = id;
                s.verdict = v;  // decided above: so is this tile
                s.tape = nullptr;
                if (v == Verdict::Open) {
                    s.verdict = walker.settle(*tape, rect(k, x, y), s.own, s.tape);
                }
                // The entries below were settled from the one replaced: stale.
                for (unsigned j = 1; j < k; ++j) path[j].id = ~std::uint64_t{0};
            }
            v = s.verdict;
            tape = s.tape;
        }
        const Rect r = rect(0, e.tx, e.ty);
        if (v == Verdict::Open) {
            walker.open(*tape, r);
        } else {
            walker.fill(r, v);
        }
    }

    /// Prepares a thread's path cache for this pyramid.
    void begin(std::vector<Settled>& path) const {
        path.resize(std::max(path.size(), levels_.size()));
        for (Settled& s : path) s.id = ~std::uint64_t{0};
    }

  private:
    struct Level {
        std::uint64_t side;
        unsigned nx, ny;
    };
    struct Entry {
        std::uint64_t key;
        unsigned tx, ty;
    };

    Rect rect(unsigned k, unsigned x, unsigned y) const {
        const std::uint64_t s = levels_[k].side, i0 = x * s, j0 = y * s;
        return {static_cast<unsigned>(i0), static_cast<unsigned>(j0),
                static_cast<unsigned>(std::min<std::uint64_t>(s, width_ - i0)),
                static_cast<unsigned>(std::min<std::uint64_t>(s, height_ - j0))};
    }

    const Ssa& full_;
    unsigned width_, height_;
    std::vector<Level> levels_;
    std::vector<Entry> order_;
};

/// The level-0 tiles, in Z order, dealt to the threads: thread k owns the k-th of as many
/// contiguous ranges and takes tiles from its front; a thread whose range is empty takes them from
/// the back of the range with the most left. A thread thus walks the Z order forwards, or
/// backwards when helping, and the tiles it takes one after the other share the tiles above them,
/// which it has settled already (TilePyramid::run's path): threads settle few tiles twice.
class TaskQueue {
  public:
    TaskQueue(std::size_t tasks, unsigned threads)
        : threads_(threads), ranges_(std::make_unique<Range[]>(threads)) {
        if (tasks >= (std::uint64_t{1} << 32))
            throw std::invalid_argument("render_2d: too many tiles");
        for (unsigned k = 0; k < threads; ++k) {
            ranges_[k].r.store(pack(tasks * k / threads, tasks * (k + 1) / threads));
        }
    }

    /// The next tile for thread k; false when every range is empty.
    bool next(unsigned k, std::size_t& task) {
        std::uint64_t r = ranges_[k].r.load(std::memory_order_relaxed);
        while (front(r) < back(r)) {  // own range: from the front
            if (ranges_[k].r.compare_exchange_weak(r, pack(front(r) + 1, back(r)))) {
                task = front(r);
                return true;
            }
        }
        for (;;) {  // help: from the back of the fullest range
            unsigned best = threads_;
            std::uint64_t most = 0;
            for (unsigned j = 0; j < threads_; ++j) {
                const std::uint64_t q = ranges_[j].r.load(std::memory_order_relaxed);
                if (front(q) < back(q) && back(q) - front(q) > most) {
                    most = back(q) - front(q);
                    best = j;
                }
            }
            if (best == threads_) return false;
            std::uint64_t q = ranges_[best].r.load(std::memory_order_relaxed);
            if (front(q) < back(q) &&
                ranges_[best].r.compare_exchange_weak(q, pack(front(q), back(q) - 1))) {
                task = back(q) - 1;
                return true;
            }
        }
    }

    /// Empties every range (a thread failed).
    void stop() {
        for (unsigned k = 0; k < threads_; ++k) ranges_[k].r.store(0);
    }

  private:
    struct alignas(64) Range {
        std::atomic<std::uint64_t> r{0};  ///< front in the low 32 bits, back (exclusive) high
    };
    static std::uint64_t pack(std::uint64_t f, std::uint64_t b) { return f | (b << 32); }
    static std::uint64_t front(std::uint64_t r) { return r & 0xffffffffu; }
    static std::uint64_t back(std::uint64_t r) { return r >> 32; }

    unsigned threads_;
    std::unique_ptr<Range[]> ranges_;
};

/// Walker scratches kept between renders: a render takes one per thread and gives it back. At
/// most one per hardware thread (at least 4) is kept; more threads' scratches are freed.
class ScratchPool {
  public:
    std::unique_ptr<WalkerScratch> take() {
        std::lock_guard lock(mutex_);
        if (free_.empty()) return std::make_unique<WalkerScratch>();
        std::unique_ptr<WalkerScratch> s = std::move(free_.back());
        free_.pop_back();
        return s;
    }
    void give(std::unique_ptr<WalkerScratch> s) {
        std::lock_guard lock(mutex_);
        if (free_.size() < std::max(4u, std::thread::hardware_concurrency())) {
            free_.push_back(std::move(s));
        }
    }

  private:
    std::mutex mutex_;
    std::vector<std::unique_ptr<WalkerScratch>> free_;
};

ScratchPool& scratch_pool() {
    static ScratchPool pool;
    return pool;
}

}  // namespace

double pixel_center_x(const Image2dOptions& o, unsigned i) {
    return o.x[0] + (i + 0.5) * ((o.x[1] - o.x[0]) / o.width);
}

double pixel_center_y(const Image2dOptions& o, unsigned j) {
    return o.y[1] - (j + 0.5) * ((o.y[1] - o.y[0]) / o.height);
}

Image2d render_2d(const expr::Tape& tape, const Image2dOptions& options) {
    check_options(tape, options);
    const auto start = std::chrono::steady_clock::now();
    Image2d img;
    img.width = options.width;
    img.height = options.height;
    img.pixels.assign(std::size_t{img.width} * img.height, Pixel2d::Outside);
    std::vector<double> xs(img.width), ys(img.height);
    for (unsigned i = 0; i < img.width; ++i) xs[i] = pixel_center_x(options, i);
    for (unsigned j = 0; j < img.height; ++j) ys[j] = pixel_center_y(options, j);

    TilePyramid pyramid(tape.ssa(), img.width, img.height, options.root_tile);
    const std::size_t tiles = pyramid.size();
    const unsigned threads = std::clamp<unsigned>(
        options.threads > 0 ? options.threads : std::thread::hardware_concurrency(), 1,
        static_cast<unsigned>(std::min<std::size_t>(tiles, 256)));
    TaskQueue queue(tiles, threads);
    if (options.progress) options.progress->total.store(tiles, std::memory_order_relaxed);
    std::atomic<std::uint64_t> filled{0}, batches{0}, inside{0}, undefined{0};
    std::mutex mutex;
    std::exception_ptr error;

    auto worker = [&](unsigned k) {
        try {
            std::unique_ptr<WalkerScratch> scratch = scratch_pool().take();
            TileWalker walker(xs, ys, img, *scratch);
            pyramid.begin(scratch->path);
            std::size_t t = 0;
            while (queue.next(k, t)) {
                if (options.use_quadtree) {
                    pyramid.run(t, walker, scratch->path);
                } else {
                    // The brute force: every pixel centre, in row pieces of at most kBatch.
                    const Rect r = pyramid.rect(t);
                    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
                        for (unsigned i = r.i0; i < r.i0 + r.w; i += kBatch) {
                            walker.leaf_full(tape,
                                             {i, j, std::min<unsigned>(kBatch, r.i0 + r.w - i), 1});
                        }
                    }
                }
                if (options.progress)
                    options.progress->done.fetch_add(1, std::memory_order_relaxed);
            }
            filled += walker.tiles_filled;
            batches += walker.leaf_batches;
            inside += walker.inside;
            undefined += walker.undefined;
            scratch_pool().give(std::move(scratch));
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!error) error = std::current_exception();
            queue.stop();
        }
    };
    run_workers(threads, worker);
    if (error) std::rethrow_exception(error);

    // Every pixel is written exactly once (disjoint tiles), by a fill or a leaf that counted it.
    img.inside = inside.load();
    img.undefined = undefined.load();
    img.tiles_filled = filled.load();
    img.leaf_batches = batches.load();
    img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return img;
}

}  // namespace certray::tracers
