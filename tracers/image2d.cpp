// tracers/image2d.cpp — the 2D interval quadtree (see image2d.h).
#include "tracers/image2d.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "expr/eval.h"
#include "expr/prune.h"
#include "interval/batch.h"
#include "interval/interval.h"

namespace certray::tracers {
namespace {

/// Observes an interval evaluation: clears `finite` when any intermediate enclosure is unbounded,
/// empty or not defined on the box.
struct FiniteObserver {
    bool finite = true;
    void operator()(const expr::Instr& in, const UpInterval* r) noexcept {
        const UpInterval& v = r[in.out];
        finite = finite && v.defined && std::isfinite(v.lower()) && std::isfinite(v.upper());
    }
};

/// One thread's walk over tiles: its evaluators and counters.
class TileWalker {
  public:
    TileWalker(const std::vector<double>& xs, const std::vector<double>& ys, Image2d& img)
        : xs_(xs), ys_(ys), img_(img) {}

    /// Classifies the pixels [i0, i0 + w) × [j0, j0 + h) of `tape`'s image.
    void tile(const expr::Tape& tape, unsigned i0, unsigned j0, unsigned w, unsigned h) {
        // The box spanned by the tile's pixel centres: the same doubles the pixels are sampled at,
        // so every centre lies in it (centres are monotone in i and j).
        const std::array<Interval, 3> box{Interval(xs_[i0], xs_[i0 + w - 1]),
                                          Interval(ys_[j0 + h - 1], ys_[j0]), Interval(0.0)};
        bool finite = false;
        const Interval v = enclose(tape, box, finite);
        // Every intermediate enclosure bounded and defined on the box: by induction over the tape,
        // every double intermediate at a centre lies in its enclosure (a rounded operation stays
        // inside the outward-rounded range, which is finite, so nothing overflows to ±inf and no
        // NaN appears), hence f's double value there has v's sign. An unbounded intermediate
        // (an overflow: exp(1e300)) breaks this — the double becomes inf, then maybe NaN — so such
        // a tile is never decided, nor pruned, from its enclosure.
        if (finite) {
            if (v.upper() < 0) return fill(i0, j0, w, h, Pixel2d::Inside);
            if (v.lower() >= 0) return fill(i0, j0, w, h, Pixel2d::Outside);
        }
        if (std::size_t{w} * h <= static_cast<std::size_t>(kBatch)) return leaf(tape, i0, j0, w, h);
        // Pruning keeps the double values for the same reason (a dropped min/max branch is
        // certainly the other side at every centre), so it too needs bounded enclosures.
        expr::PruneResult p;
        if (finite) p = expr::prune(tape, box);
        const expr::Tape& sub = finite && p.after < p.before ? p.tape : tape;
        const unsigned w1 = (w + 1) / 2, h1 = (h + 1) / 2;
        tile(sub, i0, j0, w1, h1);
        if (w > w1) tile(sub, i0 + w1, j0, w - w1, h1);
        if (h > h1) tile(sub, i0, j0 + h1, w1, h - h1);
        if (w > w1 && h > h1) tile(sub, i0 + w1, j0 + h1, w - w1, h - h1);
    }

    /// Evaluates at most kBatch pixel centres in one walk of `tape` (lanes past the tile repeat
    /// its first centre).
    void leaf(const expr::Tape& tape, unsigned i0, unsigned j0, unsigned w, unsigned h) {
        int lane = 0;
        for (unsigned j = j0; j < j0 + h; ++j) {
            for (unsigned i = i0; i < i0 + w; ++i, ++lane) {
                px_[lane] = xs_[i];
                py_[lane] = ys_[j];
            }
        }
        for (int k = lane; k < kBatch; ++k) {
            px_[k] = px_[0];
            py_[k] = py_[0];
        }
        const Batch f = batch_(tape, {px_, py_, zero_});
        lane = 0;
        for (unsigned j = j0; j < j0 + h; ++j) {
            for (unsigned i = i0; i < i0 + w; ++i, ++lane) {
                img_.pixels[std::size_t{j} * img_.width + i] = classify(f[lane]);
            }
        }
        ++leaf_batches;
    }

    std::uint64_t tiles_filled = 0;
    std::uint64_t leaf_batches = 0;

  private:
    /// The enclosure of f over the box; `finite` tells whether every intermediate was bounded.
    Interval enclose(const expr::Tape& tape, const std::array<Interval, 3>& box, bool& finite) {
        if (regs_.size() < tape.registers()) regs_.resize(tape.registers());
        RoundingScope scope;
        const std::array<UpInterval, 3> q{UpInterval(box[0]), UpInterval(box[1]),
                                          UpInterval(box[2])};
        FiniteObserver obs;
        expr::detail::run<UpInterval>(tape.instrs(), q, regs_.data(), std::ref(obs));
        finite = obs.finite;
        return Interval(regs_[tape.output()]);
    }

    void fill(unsigned i0, unsigned j0, unsigned w, unsigned h, Pixel2d value) {
        for (unsigned j = j0; j < j0 + h; ++j) {
            Pixel2d* row = img_.pixels.data() + std::size_t{j} * img_.width;
            std::fill(row + i0, row + i0 + w, value);
        }
        ++tiles_filled;
    }

    const std::vector<double>& xs_;
    const std::vector<double>& ys_;
    Image2d& img_;
    std::vector<UpInterval> regs_;  ///< interval registers (the Evaluator's loop, observed)
    expr::Evaluator<Batch> batch_;
    Batch px_, py_, zero_{0.0};
};

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

    const unsigned side = options.root_tile;
    const unsigned tiles_x = (img.width + side - 1) / side;
    const unsigned tiles_y = (img.height + side - 1) / side;
    const std::size_t tiles = std::size_t{tiles_x} * tiles_y;
    std::atomic<std::size_t> next{0};
    std::atomic<std::uint64_t> filled{0}, batches{0};
    std::mutex mutex;
    std::exception_ptr error;

    auto worker = [&] {
        try {
            TileWalker walker(xs, ys, img);
            for (;;) {
                const std::size_t t = next.fetch_add(1, std::memory_order_relaxed);
                if (t >= tiles) break;
                const unsigned i0 = static_cast<unsigned>(t % tiles_x) * side;
                const unsigned j0 = static_cast<unsigned>(t / tiles_x) * side;
                const unsigned w = std::min(side, img.width - i0);
                const unsigned h = std::min(side, img.height - j0);
                if (options.use_quadtree) {
                    walker.tile(tape, i0, j0, w, h);
                } else {
                    for (unsigned j = j0; j < j0 + h; ++j) {
                        for (unsigned i = i0; i < i0 + w; i += kBatch) {
                            walker.leaf(tape, i, j, std::min<unsigned>(kBatch, i0 + w - i), 1);
                        }
                    }
                }
            }
            filled += walker.tiles_filled;
            batches += walker.leaf_batches;
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!error) error = std::current_exception();
            next.store(tiles);
        }
    };
    const unsigned threads = std::clamp<unsigned>(
        options.threads > 0 ? options.threads : std::thread::hardware_concurrency(), 1,
        static_cast<unsigned>(std::min<std::size_t>(tiles, 256)));
    std::vector<std::thread> pool;
    for (unsigned k = 1; k < threads; ++k) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);

    for (Pixel2d p : img.pixels) {
        img.inside += p == Pixel2d::Inside;
        img.undefined += p == Pixel2d::Undefined;
    }
    img.tiles_filled = filled.load();
    img.leaf_batches = batches.load();
    img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return img;
}

}  // namespace certray::tracers
