// tracers/coherent.cpp — the coherent walk: per root tile, a front-to-back descent over screen
// rectangles × parameter segments (see coherent.h; docs/theory/coherent.md).
//
// Invariant of node(r, a, b): every open ray of r (its pixel not yet answered) is proven free of
// zeros on [tmin, max(tmin, a)), and the list it is given equals f at every point of every open
// ray of r for t in [a, b]. node() leaves every open ray of r proven free of zeros up to b (or
// answered).
#include "tracers/coherent.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <boost/container/vector.hpp>
#include <cassert>
#include <cfenv>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "expr/derived.h"
#include "expr/eval.h"
#include "expr/eval_dual_batch.h"
#include "expr/eval_interval_batch.h"
#include "expr/prune.h"
#include "expr/tangent.h"
#include "interval/dual.h"
#include "interval/interval.h"
#include "solvers/solid.h"
#include "tracers/parallel.h"
#include "tracers/segment_box.h"

namespace certray::tracers {
namespace {

using Ssa = std::vector<expr::Instr>;
using Box = std::array<UpInterval, 3>;

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Deepest node: past it a node is a leaf whatever its size (the solver bisects further).
constexpr unsigned kMaxDepth = 80;

/// A box of a batched evaluation (Walker::eval_lanes): [lo[c], hi[c]] per axis, from ray_bounds.
struct LaneBox {
    double lo[3], hi[3];
};

/// The box of ray_box(ray, p, q), as a LaneBox.
[[gnu::always_inline]] inline LaneBox lane_box(const Ray& ray, double p, double q) {
    LaneBox b;
    ray_bounds(ray, p, q, b.lo, b.hi);
    return b;
}

/// Something tried while it pays in a root tile (the mean value form of a box, tile pieces): the
/// first `First` tries, then while at least one try in `Share` wins, and one in `Every` otherwise,
/// to notice when it pays again. Each root tile starts afresh (the same answers in any thread).
template <unsigned First, unsigned Every, unsigned Share = 4>
struct PayingTrial {
    unsigned tries = 0, wins = 0, passed = 0;
    bool attempt() {
        if (tries < First || Share * wins >= tries || ++passed % Every == 0) {
            ++tries;
            return true;
        }
        return false;
    }
    void reset() { tries = wins = passed = 0; }
    /// Whether it is tried every time now (the first tries, or while it wins).
    bool paying() const { return tries < First || Share * wins >= tries; }
};

/// The tangent list of a smooth tangent list `tl` (expr/tangent.h applied twice): run over a
/// segment's box with both lists' seeds holding the ray's direction d, its slots tl.value and
/// tl.derivative hold g and g′ and its `derivative` slot g″, for g(t) = f(o + t·d). tl's list
/// gets two negations that copy its derivative into its last slot (the second list differentiates
/// the last one). None where tl is absent or has kinks.
std::optional<expr::TangentList> second_order_list(const std::optional<expr::TangentList>& tl) {
    if (!tl || !tl->smooth) return std::nullopt;
    std::vector<expr::Instr> list = tl->list;
    const std::uint32_t neg = tl->slots, copy = tl->slots + 1;
    expr::Instr n{};
    n.op = expr::Op::Neg;
    n.a = tl->derivative;
    n.out = neg;
    list.push_back(n);
    n.a = neg;
    n.out = copy;
    list.push_back(n);
    auto second = expr::tangent_list(list);
    if (second && !second->smooth) return std::nullopt;
    return second;
}

/// The pixels [i0, i0 + w) × [j0, j0 + h) of the image.
struct Rect {
    unsigned i0, j0, w, h;
};

/// A pixel of the current root tile: its ray and whether it is still open (meets the bounds and
/// has no answer yet).
struct Px {
    Ray ray;
    bool open = false;
    std::uint8_t splits = 0;  ///< undecided leaf segments split again for this ray so far
};

/// How often one ray's undecided leaf segment is split again (with a tape pruned to each half)
/// before the per-ray solver takes the rest of the ray.
constexpr std::uint8_t kMaxSplits = 24;

/// The buffers of one depth of the descent: the slot enclosures of the node's box evaluation,
/// the list pruned to that box, and the register tape a leaf builds from it.
/// A list's tangent list (expr/tangent.h; none when the list has an op without a rule) and its
/// kind (expr::tangent_kind), each made once asked for; forgotten when the list is rewritten.
struct TangentCache {
    std::optional<expr::TangentList> tangent;
    bool known = false;
    std::optional<expr::TangentKind> kind;
    const expr::TangentList* of(const Ssa& list) {
        if (!known) {
            tangent = expr::tangent_list(list);
            known = true;
        }
        return tangent ? &*tangent : nullptr;
    }
    expr::TangentKind kind_of(const Ssa& list) {
        if (!kind) kind = expr::tangent_kind(list);
        return *kind;
    }
    void forget() {
        known = false;
        kind.reset();
    }
};

struct Level {
    std::vector<UpInterval> values;
    /// Walker::split_screen: the slot enclosures of the quarters walked in lanes, each swapped
    /// into `values` when its descent comes.
    std::array<std::vector<UpInterval>, 4> quarters;
    Ssa list;
    expr::Tape tape;
    /// A ray scanned with others (Walker::scan_together), waiting to be settled.
    struct Scanned {
        unsigned i, j;
        Ray s;
        RayResult res;
        std::size_t begin = 0, end = 0;  ///< its pieces: Walker::pieces_[begin, end)
        // Built in place (emplace_back) and filled there: a local copy written field by field
        // and then copied 16 bytes at a time stalled store forwarding (a fifth of
        // scan_together's samples on Barth's sextic). `ray` over [tmin, tmax], not answered.
        Scanned(unsigned pi, unsigned pj, const Ray& ray, double tmin, double tmax)
            : i(pi), j(pj), s(ray) {
            s.tmin = tmin;
            s.tmax = tmax;
            res.status = Status::Miss;
        }
    };
    std::vector<Scanned> scanned;
    TangentCache tangent;  ///< of `list`
    /// The list that this level's scan in lanes walks (Walker::fold): folded to the node's box
    /// (expr::fold_ssa), or empty (the list itself).
    expr::FoldedList folded;
    TangentCache folded_tangent;  ///< of folded.list
};

/// The inputs (x, y, z) and registers of the walks in lanes: IntervalLanes (double bounds) or
/// IntervalLanesF (binary32 bounds, CoherentOptions::float_lanes).
template <class L>
struct LaneFile {
    std::array<L, 3> in;
    std::vector<L> regs;
};

/// Whether the ops that the binary32 walk takes in double (expr::binary32_kernel: pow, tan,
/// floor and the other ops without a vector kernel) are at most a sixth of the instructions of
/// `list`: where they are many, that costs more than eight lanes save (the gyroid's quarter of sin
/// and cos, before they had binary32 kernels: 7% more time; docs/benchmarks.md, session 19).
bool mostly_arithmetic(const Ssa& list) {
    const auto n = std::count_if(list.begin(), list.end(), [](const expr::Instr& in) {
        return !expr::binary32_kernel(in.op);
    });
    return 6 * static_cast<std::size_t>(n) <= list.size();
}

bool splittable(double a, double b) {
    const double m = 0.5 * a + 0.5 * b;
    return a < m && m < b;
}

bool has_choices(const Ssa& list) {
    return std::any_of(list.begin(), list.end(), [](const expr::Instr& in) {
        return in.op == expr::Op::Min || in.op == expr::Op::Max;
    });
}

/// How many pieces w wide a scan cuts segment s into.
int pieces_of(const Ray& s, double w) { return static_cast<int>(std::ceil((s.tmax - s.tmin) / w)); }

/// Whether pieces_of(s, w) < m for a nonempty s (s.tmin < s.tmax), w > 0 and m − 1 a power of
/// two, without the division: in any rounding mode the quotient rounds to at most m − 1 exactly
/// when the length is at most (m − 1)·w (exact: m − 1 is a power of two).
bool fewer_pieces(const Ray& s, double w, int m) { return s.tmax - s.tmin <= (m - 1) * w; }

/// Piece k of the n pieces of segment s, w wide, front to back (the last one ends at s.tmax); it
/// may be empty (lo ≥ hi) where rounding left nothing for it.
std::pair<double, double> piece(const Ray& s, double w, int k, int n) {
    const double lo = k == 0 ? s.tmin : std::min(s.tmax, s.tmin + k * w);
    const double hi = k + 1 == n ? s.tmax : std::min(s.tmax, s.tmin + (k + 1) * w);
    return {lo, hi};
}

/// A register tape from a list written by prune_ssa (slots in any order): renumbered so that slot
/// i is instruction i, as Tape::from_ssa wants.
expr::Tape tape_of(const Ssa& list) {
    Ssa ssa = list;
    std::vector<std::uint32_t> index(ssa.size());
    for (std::size_t i = 0; i < ssa.size(); ++i) {
        expr::Instr& in = ssa[i];
        const int k = expr::arity(in.op);
        if (k >= 1) in.a = index[in.a];
        if (k == 2) in.b = index[in.b];
        index[in.out] = static_cast<std::uint32_t>(i);
        in.out = static_cast<std::uint32_t>(i);
    }
    return expr::Tape::from_ssa(std::move(ssa));
}

/// Hits waiting for their normals (Walker::flush_normals): fewer take a Dual walk each (a walk of
/// lanes costs more for one or two points: measured on the gyroid).
constexpr int kFewNormals = 3;

/// One thread's walk: root tiles in, answers written to the image's pixels.
class Walker {
  public:
    Walker(const expr::Tape& tape, const CoherentOptions& options, const PixelRays& rays,
           PixelAnswers& answers, std::vector<RayResult>* results)
        : tape_(tape),
          options_(options),
          rays_(rays),
          ans_(answers),
          results_(results),
          solid_(options.surface == Surface::Solid),
          mean_value_rays_(options.mean_value_rays.value_or(16)),
          adaptive_(!options.mean_value_rays.has_value()),
          certified_(options.certified),
          choices_(has_choices(tape.ssa())),
          t_splits_(rays.projection() != Projection::Ortho || tape.uses_var(2)),
          levels_(kMaxDepth),
          tape_tangent_(expr::tangent_list(tape.ssa())),
          tape_second_(options.second_order_forms ? second_order_list(tape_tangent_)
                                                  : std::nullopt),
          float_lanes_(options.float_lanes && mostly_arithmetic(tape.ssa())) {
        if (rays.projection() != Projection::List && options.render.aov != Aov::Depth &&
            options.depth_pixels > 0) {
            // A pixel's footprint: its angle times t (pinhole), or its side (ortho).
            const double depth = options.depth_pixels * rays.pixel_pitch();
            if (rays.angular()) {
                certified_.hit_width = std::max(certified_.hit_width, depth);
            } else {
                certified_.hit_width_absolute = std::max(certified_.hit_width_absolute, depth);
            }
        }
        solid_options_.budget = certified_.budget;
        solid_options_.hit_width = certified_.hit_width;
        solid_options_.hit_width_absolute = certified_.hit_width_absolute;
        prune_ws_.absolute_values = true;
        prune_ws_.fold_points = false;  // the lists' gradients are the hits' normals
    }

    /// Answers every pixel of the root tile r. True where every pixel is a Miss with no evaluation
    /// of its own, answered without building the rays (ortho_tile_free, PixelRays::misses).
    bool tile(const Rect& r);
    /// The last root tile's answers (tile()), of its size: pixel (i, j) of the tile at (i, j).
    const PixelAnswers& tile_answers() const { return mine_; }
    /// tile()'s walk over the rays of r.
    void walk_tile(const Rect& r);

    CoherentStats stats;
    /// The last root tile's pixels counted by status, and its most evaluations of a pixel (tile()).
    RenderStats tile_counts;
    EvalCounts evals;

  private:
    /// Pixel (i, j)'s index in the root tile (row by row).
    std::size_t slot(unsigned i, unsigned j) const {
        return std::size_t{j - root_.j0} * root_.w + (i - root_.i0);
    }
    Px& px(unsigned i, unsigned j) { return px_[slot(i, j)]; }
    /// The hull of the open rays of a rectangle, and the count of answered rays when it was taken.
    struct Hull {
        double olo[3] = {kInf, kInf, kInf}, ohi[3] = {-kInf, -kInf, -kInf};
        double dlo[3] = {kInf, kInf, kInf}, dhi[3] = {-kInf, -kInf, -kInf};
        double tlo = kInf, thi = -kInf;
        unsigned count = 0;
        std::uint64_t answered = 0;
        /// Takes in n rays with parameters in [tl, th], origins in [ol, oh] and directions in
        /// [dl, dh] (per axis), the origins and directions only where they vary across the rays
        /// (VaryO, VaryD; Walker::varying).
        template <bool VaryO, bool VaryD>
        void add(unsigned n, double tl, double th, const double* ol, const double* oh,
                 const double* dl, const double* dh) {
            count += n;
            tlo = std::min(tlo, tl);
            thi = std::max(thi, th);
            for (int c = 0; c < 3; ++c) {
                if constexpr (VaryO) {
                    olo[c] = std::min(olo[c], ol[c]);
                    ohi[c] = std::max(ohi[c], oh[c]);
                }
                if constexpr (VaryD) {
                    dlo[c] = std::min(dlo[c], dl[c]);
                    dhi[c] = std::max(dhi[c], dh[c]);
                }
            }
        }
        template <bool VaryO, bool VaryD>
        void add(const Ray& r) {
            add<VaryO, VaryD>(1, r.tmin, r.tmax, r.o.data(), r.o.data(), r.d.data(), r.d.data());
        }
        template <bool VaryO, bool VaryD>
        void add(const Hull& h) {
            add<VaryO, VaryD>(h.count, h.tlo, h.thi, h.olo, h.ohi, h.dlo, h.dhi);
        }
    };
    /// f(vary_o, vary_d) with std::bool_constant arguments: whether the rays' origins and
    /// directions vary across the image. A pinhole's rays share their origin, a heightmap's their
    /// direction: a hull takes that one from any ray (the same bits).
    template <class F>
    void varying(F&& f) const {
        switch (rays_.projection()) {
            case Projection::Pinhole:
                f(std::false_type{}, std::true_type{});
                break;
            case Projection::Ortho:
                f(std::true_type{}, std::false_type{});
                break;
            case Projection::List:
                f(std::true_type{}, std::true_type{});
                break;
        }
    }
    void node(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
              unsigned depth, const Hull* given = nullptr);
    /// The open rays of r whose segments meet [a, b]: their count and the hull of their origins,
    /// directions and parameter ranges. Over the blocks of kBlock × kBlock pixels that r covers
    /// whole, a block whose open rays all meet [a, b] gives its cached hull (Block) instead of a
    /// pass over its pixels: the same hull (minima and maxima in another order; a bound of 0
    /// reached as +0 and −0 may take the other sign).
    Hull hull_of(const Rect& r, double a, double b);
    /// The hull of the open rays of a block of the root tile, each ray's whole segment, kept
    /// while none of them is answered (answer() marks it stale): their count, the hull of their
    /// origins and directions, the least and greatest tmin and tmax.
    struct Block {
        Hull hull;
        double max_tmin = -kInf, min_tmax = kInf;
        const Px* first = nullptr;  ///< its first open ray
        unsigned open = 0;          ///< its open rays (kept by tile() and answer())
        bool stale = true;
    };
    /// Side of a Block in pixels.
    static constexpr unsigned kBlock = 4;
    std::vector<Block> blocks_;
    unsigned blocks_w_ = 0;  ///< blocks per row of the root tile
    Block& block_of(unsigned i, unsigned j) {
        return blocks_[std::size_t{(j - root_.j0) / kBlock} * blocks_w_ + (i - root_.i0) / kBlock];
    }
    /// Block b (its top left pixel (i0, j0)) taken afresh from its pixels.
    void take_block(Block& b, unsigned i0, unsigned j0);
    /// `tape`: the register tape of `list`, or null (built into `level` when a solver needs it).
    void leaf(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
              Level& level, unsigned depth);
    /// An image's leaf segment s in pieces as wide as the depth a hit may have, front to back,
    /// with `list` (equal to f on s): Miss if every piece is proven free; a Hit [p, q] on the
    /// first piece that is not, when a point evaluation proves it (solid: g(q) < 0, or g < 0 on
    /// all of it: [p, p]; zero: g defined and continuous on [p, q] with g(p), g(q) of strict
    /// opposite signs); otherwise Unknown with t_lo = p, where the solver takes over. A few
    /// evaluations where the solver's Newton steps and bisections would spend about ten.
    /// `width`: the pieces' width (0: piece_width(s)), `finer`: how many times an undecided
    /// piece may still be scanned again in quarters (after_points).
    RayResult scan(const Ssa& list, const Ray& s, double width = 0, int finer = 2);
    /// The rest of a leaf's work on pixel (i, j) whose segment s (the ray within the node's
    /// [a, b]) got `res`: from scan() when `scanned` (an Unknown there runs the solver from its
    /// t_lo), else from the solver. A Miss proves s free and leaves the pixel open; an Unknown is
    /// split again or handed to the per-ray solver on the rest of the ray; anything else is the
    /// pixel's answer.
    void settle(unsigned i, unsigned j, const Ray& s, RayResult res, bool scanned, const Ssa& list,
                const expr::Tape*& tape, Level& level, unsigned depth);
    /// scan() for the open rays of r that meet [a, b] (at most CoherentOptions::together_rays, or
    /// smooth_together_rays where the list has a tangent list; each segment at most kMaxPieces
    /// pieces long) all at once: every piece of every ray is one lane of one batched evaluation,
    /// then the points that the pieces' decisions need are a second one.
    /// Each ray is decided as scan() decides it (the same enclosures, bit for bit; with the
    /// list's tangent list, the mean value forms from lanes too, on every later undecided piece),
    /// settled as leaf() settles it. False, with nothing evaluated, when a ray's segment is too
    /// long; `folded_only`: also (the fold's evaluations aside) when the list does not fold to
    /// the node's box.
    bool scan_together(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                       Level& level, unsigned depth, const Hull& hull, bool folded_only = false);
    /// A node's rectangle and parameter range, scanned with others (scan_groups).
    struct ScanGroup {
        Rect r;
        double a, b;
        const Hull* hull;  ///< its open rays' hull (the tile pieces and fold of one group)
    };
    /// scan_together() for the open rays of up to four nodes of one list at once, each over its
    /// own [a, b] (their rays disjoint): the groups whose segments are all short enough, as a
    /// bit mask (none evaluated otherwise). The list is folded, and the tile pieces taken, only
    /// for one group.
    unsigned scan_groups(const ScanGroup* groups, int n, const Ssa& list, const expr::Tape* tape,
                         Level& level, unsigned depth, bool folded_only);
    /// Whether descend() scans a node of `count` open rays of `list` (kept at `depth`) together
    /// (scan_together) before it splits it.
    bool scans_together(unsigned count, const Ssa& list, unsigned depth) {
        const unsigned plain =
            list.size() >= kLongList ? options_.long_together_rays : options_.together_rays;
        return count <= plain ||
               (count <= options_.smooth_together_rays && options_.lane_mean_value &&
                tangent_kind(list, depth) == expr::TangentKind::Smooth);
    }
    /// scan_together()'s segment forms (CoherentOptions::segment_forms) on the rays of
    /// level.scanned not yet decided, where `list` (kept at `depth`) is smooth and the root tile's
    /// trial allows: a segment proven free is left empty (no pieces); with monotone_segments, the
    /// strictly monotone ones go to decide_monotone().
    void take_segment_forms(const Ssa& list, unsigned depth, Level& level);
    /// The strictly monotone segments in monotone_, decided by points of `list`: proven free,
    /// answered (a Hit a piece deep), or left to their pieces from the bracket's lo.
    void decide_monotone(const Ssa& list, Level& level);
    /// Ray z's segment proven free (no pieces; counted in stats).
    void prove_free(Level::Scanned& z) {
        z.s.tmin = z.s.tmax;
        ++stats.segment_forms;
    }
    /// Enclosures of `list` over the boxes boxes[0, n) into out[0, n); with `fold`, of its
    /// folded list where it has one (Level::folded: the boxes must lie in its node's box).
    void eval_lanes(const Ssa& list, const LaneBox* boxes, std::size_t n,
                    std::vector<UpInterval>& out, const Level* fold = nullptr);
    /// Writes the fixed values of level.folded into lanes 0 … m − 1 of their slots.
    template <class L>
    void load_fixed(LaneFile<L>& file, const Level& level, int m);
    template <class L>
    void eval_lanes_in(LaneFile<L>& file, const Ssa& list, const LaneBox* boxes, std::size_t n,
                       std::vector<UpInterval>& out, const Level* fold);
    template <class L>
    void eval_tangent_lanes_in(LaneFile<L>& file, const expr::TangentList& tl, const LaneBox* boxes,
                               const std::array<double, 3>* dirs, std::size_t n,
                               std::vector<UpInterval>& values, std::vector<UpInterval>& slopes,
                               const Level* fold, const expr::TangentList* second,
                               std::vector<UpInterval>* curvatures);
    /// A mean value form as a line in t: for every ray of a node and every point t of its [a, b],
    /// f(o + t·d) ∈ p + (t − tc)·q (ok: the form applies). mean_value() and ray_form() give it
    /// beside the form's enclosure, which is that of the same terms grouped otherwise.
    struct LinearForm {
        UpInterval p, q;
        double tc = 0;
        bool ok = false;
    };
    /// [a, b] narrowed to where the line `lin` lets f vanish (the solid: be negative), for the
    /// rays of a node whose box over [a, b] the form did not prove (upward mode held): the part
    /// cut off at either end is proven free by the line's enclosure over it. Sets a > b where
    /// the line proves the whole segment free. (CoherentOptions::clip_forms.)
    void clip_to_line(const LinearForm& lin, double& a, double& b) const;
    /// The node mean value form's inputs and lanes (mean_value, split_screen): the box x of a
    /// node's rays over [a, b], its centre c = oc + tc·dc (rounded outward), and the form's
    /// lanes (ray_form_lanes): g[0..2] the gradient's components over x, g[3] the derivative along
    /// dc, m f's enclosure at c; ok false where the walk proves nothing (f not defined and
    /// continuous on x, an unbounded component).
    struct RayForm {
        std::array<UpInterval, 3> x, c;
        double oc[3], dc[3], tc;
        UpInterval g[4], m;
        bool ok;
    };
    /// x, c, oc, dc and tc of the form over the rays of a hull over [a, b] (upward mode held).
    static void prepare_form(RayForm& f, double a, double b, const double* olo, const double* ohi,
                             const double* dlo, const double* dhi);
    /// The form from its lanes: m + Σ_k g_k·(O_k − oc_k) + T·Σ_k g_k·(D_k − dc_k) + g_3·(T − tc),
    /// empty where the lanes proved nothing.
    static UpInterval ray_form(const RayForm& f, double a, double b, const double* olo,
                               const double* ohi, const double* dlo, const double* dhi,
                               LinearForm* lin = nullptr);
    /// The lanes of n forms (n ≤ kMaxForms) in one walk of `tl`: five lanes each, the centre's
    /// last.
    static constexpr int kMaxForms = 4;
    /// Counts a node's mean value form on a list of `length` instructions: a gradient and an
    /// interval evaluation (two box walks' worth).
    void count_form(std::size_t length) {
        stats.box_evals += 2;
        stats.box_instructions += 2 * length;
        ++evals.gradient;
        ++evals.interval;
    }
    void ray_form_lanes(const expr::TangentList& tl, RayForm* forms, int n);
    template <class L>
    void ray_form_lanes_in(LaneFile<L>& file, const expr::TangentList& tl, RayForm* forms, int n);
    RayForm forms_[kMaxForms];              ///< split_screen()'s forms
    std::vector<UpInterval> split_values_;  ///< split_screen()'s enclosures
    /// level.folded for the scan in lanes of `sub` over `box`, from level.values: `sub` is the
    /// list the node evaluated into level.values, or level.list, that list pruned by the
    /// node's prune_ssa (prune_ws_ as it left it). The subexpressions narrower than kFoldWidth
    /// times f's enclosure become inputs where the folded list's value at the box's centre stays
    /// within kFoldCentre of it (three tries, each a 32nd of the width before); empty otherwise.
    void fold(const Ssa& sub, const std::array<UpInterval, 3>& box, Level& level);
    /// Whether fold() may fold `list` (CoherentOptions::fold_lists).
    bool may_fold(const Ssa& list) const {
        return options_.fold_lists != 0 && list.size() >= options_.fold_lists;
    }
    /// tangent_kind() and tangent() of what the scan of `list` at this level walks in lanes: the
    /// folded list's where the level has one.
    expr::TangentKind lane_tangent_kind(const Ssa& list, unsigned depth, Level& level);
    const expr::TangentList* lane_tangent(const Ssa& list, unsigned depth, Level& level);
    /// Loads boxes[0, m) into lanes 0 … m − 1 of file.in (m ≤ kIntervalLanes): each axis the
    /// interval ray_box gives (empty where a bound is NaN or lo > hi).
    template <class L>
    void load_lanes(LaneFile<L>& file, const LaneBox* boxes, int m);
    /// The tangent list of `list` (expr/tangent.h), or null when it has none; kept with the
    /// level whose list it is (`depth` or above).
    const expr::TangentList* tangent(const Ssa& list, unsigned depth);
    /// What tangent list `list` has (expr::tangent_kind), kept as tangent().
    expr::TangentKind tangent_kind(const Ssa& list, unsigned depth);
    /// The level whose list `list` is (`depth` or above), or null.
    Level* owner_of(const Ssa& list, unsigned depth);
    /// Enclosures of f and of its derivative along each lane's direction dirs[k] over the boxes
    /// boxes[0, n), by the tangent list `tl`, into values[0, n) and slopes[0, n).
    /// `fold`: `tl` is the tangent list of fold->folded's list (its fixed values are loaded).
    /// `second` (second_order_list(tl)): its list is walked instead, and g″ along the directions
    /// goes into curvatures[0, n) too.
    void eval_tangent_lanes(const expr::TangentList& tl, const LaneBox* boxes,
                            const std::array<double, 3>* dirs, std::size_t n,
                            std::vector<UpInterval>& values, std::vector<UpInterval>& slopes,
                            const Level* fold = nullptr, const expr::TangentList* second = nullptr,
                            std::vector<UpInterval>* curvatures = nullptr);
    /// Solid: every open ray of r that meets [a, b] enters {f < 0} at its first parameter in
    /// [a, b] (the box there is proven inside, and g ≥ 0 is proven before): a Hit [t, t].
    void inside(const Rect& r, double a, double b, const Ssa& list);
    /// For the heightmap camera: true when the root tile r is proven free on its whole depth by
    /// one box evaluation over its rays (counted), without building its rays.
    bool ortho_tile_free(const Rect& r);
    /// The box over which ortho_tile_free() left the full tape's enclosures in levels_[0] (the
    /// root node's, which node() then takes instead of walking the tape again).
    std::optional<Box> root_box_;
    /// The mean value form over the box: F(c) + Σ G_i·(X_i − c_i), with G the gradient
    /// enclosure over the box X and c its centre; empty when it does not apply (f not proven
    /// defined and continuous on the box, or an unbounded gradient).
    /// `tl`: the list's tangent list when it is smooth (expr/tangent.h), which takes the form of
    /// several rays in five lanes of one walk instead of a Dual<UpInterval, 3> walk; or null.
    UpInterval mean_value(const Ssa& list, double a, double b, const double* olo, const double* ohi,
                          const double* dlo, const double* dhi,
                          const expr::TangentList* tl = nullptr, LinearForm* lin = nullptr);
    /// What an enclosure F of f over a box proves for the surface asked for (Unusable: a form
    /// that does not apply, segment_form).
    enum class Proof { None, Excluded, Inside, Unusable };
    /// The rest of node() once its box's enclosures (level.values, and `proven`: what they or the
    /// mean value form prove) are known: an answer, a scan, a split or a leaf.
    void descend(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                 unsigned depth, const Hull& hull, Proof proven);
    /// node() on the four quarters of r (visited in order), at `depth`: their boxes evaluated in
    /// lanes of one walk (each quarter's slot enclosures kept from them where the descent prunes
    /// or folds), their mean value forms in lanes of another (CoherentOptions::
    /// children_in_lanes): the same enclosures and forms, bit for bit.
    void split_screen(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                      unsigned depth);
    Proof proof(const UpInterval& f) const {
        if (!solid_) return possibly_zero(f) ? Proof::None : Proof::Excluded;
        // f ≥ 0 wherever it is defined on the box: no point of the solid {f defined, f < 0}.
        if (f.is_empty() || f.lower() >= 0) return Proof::Excluded;
        return f.defined && f.upper() < 0 ? Proof::Inside : Proof::None;
    }
    /// What a node's mean value form `form` (empty: it does not apply) and its line `lin` give
    /// a node over [a, b] that its box left undecided: `proven`, and [a, b] clipped to the line
    /// (clip_forms). True where that paid: the box proven, or a quarter of [a, b] or more cut off.
    bool take_form(const UpInterval& form, const LinearForm& lin, Proof& proven, double& a,
                   double& b) {
        if (!form.is_empty()) proven = proof(form);
        if (proven != Proof::None) return true;
        if (!lin.ok || !options_.clip_forms) return false;
        const double width = b - a;
        const double a0 = a, b0 = b;
        clip_to_line(lin, a, b);
        if (!(a <= b)) proven = Proof::Excluded;
        stats.clipped += proven != Proof::None || a != a0 || b != b0;
        return proven != Proof::None || b - a <= 0.75 * width;
    }
    /// Writes a Hit [lo, hi] into res.
    static void hit_of(RayResult& res, double lo, double hi) {
        res.status = Status::Hit;
        res.t_lo = lo;
        res.t_hi = hi;
        res.t = 0.5 * lo + 0.5 * hi;
    }
    static bool finite(const UpInterval& v) {
        return !v.is_empty() && std::isfinite(v.lower()) && std::isfinite(v.upper());
    }
    /// +1 or −1: v is defined and of that strict sign; else 0.
    static int strict_sign(const UpInterval& v) {
        if (v.is_empty() || !v.defined) return 0;
        return v.lower() > 0 ? 1 : v.upper() < 0 ? -1 : 0;
    }
    /// What the mean value form in t proves on the segment [p, q] of one ray, from its lanes of a
    /// tangent list's walk: e the enclosure of f over the segment's box, g1 that of the derivative
    /// along the ray there, m that of f at the middle of [p, q]; Unusable (nothing counted) when
    /// the form does not apply (f not proven defined and continuous on the box, or G′ unbounded),
    /// else its evaluations counted in res.
    Proof segment_form(const UpInterval& e, const UpInterval& g1, const UpInterval& m, double p,
                       double q, RayResult& res) const {
        if (!e.defined || !finite(g1) || m.is_empty() || !m.defined) return Proof::Unusable;
        ++res.evals.gradient;
        ++res.evals.interval;
        const UpInterval t(p, q);
        return proof(m + g1 * (t - UpInterval(midpoint(t))));
    }
    /// For a scanned piece [p, q] of s that the plain enclosure and the point tests left
    /// undecided: what the mean value form in t proves on it (None if it does not apply), its
    /// evaluations counted in res.
    Proof piece_mean_value(const Ssa& list, const Ray& s, double p, double q, RayResult& res);
    /// scan()'s last resort on the first piece [p, q] of s that neither its enclosure nor the
    /// point tests decided (res: Unknown from p): the mean value form in t, tighter on a short
    /// piece than the plain enclosure. Proven free: the scan of the rest [q, s.tmax]; proven
    /// inside (solid): Hit [p, p]; else res.
    /// `form`: what the form proves on [p, q] when it was taken already (scan_together's lanes).
    RayResult after_points(const Ssa& list, const Ray& s, double p, double q, RayResult res,
                           int finer = 2, const Proof* form = nullptr);
    /// The certified answer on one ray segment, for the surface asked for.
    RayResult solve(const expr::Tape& tape, const Ray& ray) const {
        return solid_ ? solvers::solid_first_entry(tape, ray, solid_options_)
                      : solvers::certified_first_root(tape, ray, certified_);
    }
    /// Counts the evaluations `e` that proved pixel (i, j)'s ray free of zeros on a segment.
    void spend(unsigned i, unsigned j, const EvalCounts& e);
    /// Writes the answer `res` of pixel (i, j) on its ray and closes the pixel.
    /// A Hit's normal is the gradient of `list` at the hit when its t lies in [a, b] (`list`
    /// equals f there, and so do its derivatives: the walk prunes without folding points,
    /// PruneWorkspace::fold_points), else of the full tape. Where `list` is the list of the scan
    /// or inside box in progress (defer_list_, DeferNormals), the normal waits for
    /// flush_normals(), with the other hits on it.
    void answer(unsigned i, unsigned j, Px& p, const RayResult& res, const Ssa& list, double a,
                double b);
    /// While one is in scope, the hits answered on `list` wait for their normals (when
    /// batch_normals is on); its end computes them and restores the enclosing scope's list.
    struct DeferNormals {
        Walker& w;
        const Ssa* outer;
        DeferNormals(Walker& walker, const Ssa& list) : w(walker), outer(walker.defer_list_) {
            w.defer_list_ = w.options_.batch_normals ? &list : nullptr;
        }
        DeferNormals(const DeferNormals&) = delete;
        DeferNormals& operator=(const DeferNormals&) = delete;
        ~DeferNormals() {
            w.flush_normals();
            w.defer_list_ = outer;
        }
    };
    /// The normals of the hits answer() left waiting: one walk of Dual<double, 3> lanes of their
    /// list over their points (expr/eval_dual_batch.h: each the same bits as a walk of its own).
    void flush_normals();
    /// Writes the normal of the root tile's pixel in slot k from the gradient g, turned to face the
    /// ray's direction d (in round-to-nearest).
    void set_normal(std::size_t k, const Vec3& g, const Vec3& d);
    /// o + t·d, where a hit's normal is taken (in round-to-nearest, as render_3d takes it).
    static Vec3 point_at(const Ray& ray, double t) {
        return {ray.o[0] + t * ray.d[0], ray.o[1] + t * ray.d[1], ray.o[2] + t * ray.d[2]};
    }
    /// The gradient of `list` at q, by a Dual<double, 3> walk (in round-to-nearest).
    Dual<double, 3> list_gradient(const Ssa& list, const Vec3& q);

    const expr::Tape& tape_;
    const CoherentOptions& options_;
    const PixelRays& rays_;
    PixelAnswers& ans_;
    std::vector<RayResult>* results_;  ///< every answer, when the caller asks
    const bool solid_;                 ///< the solid surface (else the zero set)
    const unsigned mean_value_rays_;   ///< CoherentOptions::mean_value_rays, resolved
    /// The mean value form is tried while it pays in the current root tile (unset option).
    const bool adaptive_;
    /// This root tile's mean value forms (a win: the form proves what the interval form did not),
    /// worth their cost (about four box evaluations) while they win: the first 16 tries, then
    /// one in eight when they do not.
    PayingTrial<16, 8> mean_values_;
    /// This root tile's tile pieces (scan_together; a win: they answered a ray, proved every ray
    /// of the node free, or spared four vectors' worth of pieces): the first 4, then while one
    /// try in four wins, else one in 16.
    PayingTrial<4, 16> tile_trial_;
    /// This root tile's mean value forms in lanes on lists with kinks (scan_together; a win: they
    /// proved at least half the pieces they were taken on): the first 4, then one in 16 (the
    /// molecule's forms prove 16% of such pieces, the bear's 67%).
    PayingTrial<4, 16> kink_forms_;
    /// The root tile's segment forms so far: segments tried, and those their plain enclosure
    /// proved free (take_segment_forms() walks those enclosures first while that is 3 in 10).
    std::size_t plain_tried_ = 0, plain_free_ = 0;
    /// This root tile's folds (fold(); a win: a fold, which drops an eighth of the list or more):
    /// the first 4, then while half of them win, else one in 16. The molecule's lists of thousands
    /// of instructions drop little, and a fold costs about four walks of the list.
    PayingTrial<4, 16, 2> fold_trial_;
    /// Whether to try the mean value form on a box of `count` rays whose list is `list` (kept
    /// at `depth`): beyond 16 rays only where the list has a tangent list without kinks, which
    /// gives the form from five lanes.
    bool try_mean_value(unsigned count, const Ssa& list, unsigned depth) {
        if (!adaptive_) return count <= mean_value_rays_;
        if (count <= 16) return mean_values_.attempt();
        if (tangent_kind(list, depth) != expr::TangentKind::Smooth) return false;
        return wide_forms_.attempt();
    }
    /// Counts a try of the form on a box of `count` rays (`won`: it proved the box).
    void mean_value_tried(unsigned count, bool won) {
        (count <= 16 ? mean_values_.wins : wide_forms_.wins) += won;
        stats.wide_forms += count > 16 && won;
    }
    /// With the option unset, the forms of boxes of more than 16 rays on smooth lists, tried
    /// apart from the smaller ones while one in three wins: the first, then one in 16 (Chmutov's
    /// sextic wins 42% of them and its heightmap takes a third less time; Barth's 12%,
    /// docs/benchmarks.md, session 13). Lists with kinks keep 16 rays: their forms are Dual walks
    /// (the colonnade took 28% longer).
    PayingTrial<1, 16, 3> wide_forms_;
    solvers::CertifiedOptions certified_;  ///< options.certified with the image's depth width
    solvers::SolidOptions solid_options_;
    const bool choices_;  ///< the tape has min/max: pruning can shorten it
    /// Splitting in t can tighten a box: false for heightmap rays over a tape without z, whose
    /// boxes do not change along t.
    const bool t_splits_;
    std::vector<Level> levels_;
    expr::PruneWorkspace prune_ws_;
    Rect root_{0, 0, 0, 0};
    std::vector<Px> px_;
    /// The root tile's answers (tile()), its pixel (i, j) at slot (j − j0)·w + (i − i0): status,
    /// hit t, evaluations and normal; copied into the image's answers where they are kept.
    PixelAnswers mine_;
    std::vector<Ray> row_rays_;  ///< tile()'s rays of a row, and which meet the bounds
    boost::container::vector<bool> row_in_;
    std::uint64_t answered_ = 0;  ///< rays answered so far (hulls taken before are stale)
    std::vector<Dual<UpInterval, 3>> duals_;
    std::vector<Dual<UpInterval, 1>> duals1_;
    std::vector<UpInterval> centre_;
    std::vector<UpInterval> scan_;       ///< scan()'s registers
    std::vector<Dual<double, 3>> grad_;  ///< answer()'s registers
    /// The list of the scan in progress (its content does not change before the scan returns:
    /// deeper levels prune into their own lists), and that of the hits waiting for their normals.
    const Ssa* defer_list_ = nullptr;
    const Ssa* pending_list_ = nullptr;
    /// The hits waiting for their normals (flush_normals).
    std::size_t pending_px_[expr::kDualLanes];           ///< their pixels' slots
    double pending_t_[expr::kDualLanes];                 ///< their hits' parameters
    const Ray* pending_ray_[expr::kDualLanes];           ///< their rays (the pixels')
    std::array<double, 3> pending_q_[expr::kDualLanes];  ///< flush_normals()'s points
    int pending_ = 0;
    std::vector<expr::DualLanes> dual_regs_;  ///< flush_normals()'s registers
    /// The width a piece of scan() may have: certified_'s absolute width, or its relative width
    /// times the parameter (0: no scan).
    double piece_width(const Ray& s) const {
        return std::max(certified_.hit_width_absolute,
                        certified_.hit_width * std::max(0.0, s.tmin));
    }
    /// split_screen() walks the quarters of a node in lanes where its list has at most this many
    /// instructions.
    static constexpr std::size_t kLanesList = 256;
    /// A list this long scans CoherentOptions::long_together_rays together.
    static constexpr std::size_t kLongList = 200;
    /// At most this many pieces a leaf segment is scanned in; longer ones go to the solver.
    static constexpr int kMaxPieces = 8;
    /// The lanes of a binary32 vector on AVX-512 (tile pieces' trial: what a walk's vector holds).
    static constexpr int kWalkLanes = 16;
    /// fold(): the subexpressions at most this fraction of f's width over the node's box wide
    /// become inputs (CoherentOptions::fold_lists) ...
    static constexpr double kFoldWidth = 1e-3;
    /// ... where the folded list's enclosure at the box's centre is at most this fraction of it.
    static constexpr double kFoldCentre = 1e-3;
    /// A segment of at least this many pieces gets its segment form (CoherentOptions::
    /// segment_forms; 4 until session 22: the lanes of a walk cost little next to the walk, and
    /// with 2 Chmutov's heightmap takes 0.90 of the time).
    static constexpr int kSegmentFormPieces = 2;
    static_assert(std::has_single_bit(unsigned{kSegmentFormPieces - 1}), "fewer_pieces()");
    /// ... and a list of at least this many instructions (the colonnade's pruned lists of about
    /// 10 took 10% longer with the forms alone at any length; with the monotone segments, lists of
    /// 8 and more pay or break even: docs/benchmarks.md, session 16).
    static constexpr std::size_t kSegmentFormList = 8;
    /// scan_together()'s lanes: the boxes, their enclosures, and per lane the ray's pixel and
    /// the piece [p, q].
    std::vector<LaneBox> lanes_;
    std::vector<LaneBox> points_;  ///< the second and third batches' boxes
    std::vector<UpInterval> lane_values_;
    std::vector<UpInterval> lane_slopes_;   ///< eval_tangent_lanes()'s derivatives
    std::vector<UpInterval> piece_values_;  ///< per piece: the enclosure of f over it
    std::vector<Proof> piece_proof_;        ///< per piece: what its enclosures prove
    /// The lanes of the mean value forms: undecided pieces, then their centres, and their rays'
    /// directions; per piece its lane there, or none.
    std::vector<LaneBox> form_boxes_;
    std::vector<std::array<double, 3>> dirs_;
    std::vector<std::size_t> form_of_;
    /// The tangent list of the tape's own list (expr/tangent.h), or none.
    const std::optional<expr::TangentList> tape_tangent_;
    /// The second-order list of the tape's own (second_order_list), or none.
    const std::optional<expr::TangentList> tape_second_;
    /// take_segment_forms()'s segments left to the second-order form (try_second_order()): the
    /// ray (in level.scanned) and, per segment, its lanes' results.
    std::vector<std::size_t> second_rays_;
    std::vector<LaneBox> second_boxes_;
    std::vector<std::array<double, 3>> second_dirs_;
    std::vector<UpInterval> second_g_, second_g1_, second_g2_;
    /// This root tile's second-order forms (a win: they prove every segment tried free, so that
    /// none of them needs its pieces): the first 8 scans, then while one in four wins, else one
    /// in 16.
    PayingTrial<8, 16> second_trial_;
    /// The second-order form on the segments in second_rays_ (see take_segment_forms()).
    void try_second_order(const Ssa& list, Level& level);
    /// The walks in lanes in binary32 bounds (CoherentOptions::float_lanes).
    const bool float_lanes_;
    struct Piece {
        unsigned i, j;
        double p, q;
    };
    /// scan_together()'s rays: pixel and segment.
    struct Segment {
        unsigned i, j;
        double tmin, tmax;
    };
    std::vector<Segment> segments_;
    /// scan_together()'s strictly monotone segments (CoherentOptions::monotone_segments): the
    /// ray (in level.scanned), its bracket [lo, hi] and g's strict sign at lo (the solid: 1, for
    /// g(lo) ≥ 0).
    struct Monotone {
        std::size_t ray;
        double lo, hi;
        int sign;
        bool decreasing;  ///< g′ < 0 on the segment (else > 0)
        /// g at the segment's middle tc, from its form's lanes
        double tc;
        UpInterval centre;
        bool high = false;  ///< decide_monotone(): the zero, if any, lies after tc (b decides)
        /// G′ ⊇ g′ over [lo, hi], of one strict sign
        UpInterval slope;
        /// decide_monotone(): a zero to bracket (the zero set, or the solid's decreasing g), and
        /// the part [step_lo, step_hi] of the half on its side that the Newton step from tc
        /// leaves (newton_brackets; else the half)
        bool bracket = false;
        double step_lo = 0, step_hi = 0;
    };
    std::vector<Monotone> monotone_;
    std::vector<Monotone> ready_;  ///< decide_monotone()'s brackets from the steps alone
    /// scan_together()'s tile pieces: their boxes, enclosures and ends (piece k is
    /// [tile_t_[k], tile_t_[k + 1]]).
    std::vector<LaneBox> tile_boxes_;
    std::vector<UpInterval> tile_values_;
    std::array<double, 2 * kMaxPieces + 1> tile_t_{};
    std::vector<Piece> pieces_;
    std::vector<std::size_t> first_piece_, point_lane_;
    /// scan_together()'s rays waiting for the quarters of their piece (first_piece_): the piece
    /// as a segment, its quarters' lanes [box, box + count), the first one not proven free (or
    /// count), its point lanes [points, points + m) and the quarters' own result.
    struct Waiting {
        std::size_t ray;
        Ray seg{};
        std::size_t box = 0, count = 0, first = 0, points = 0;
        int m = 0;
        RayResult res{};
    };
    std::vector<Waiting> waiting_, still_;
    std::vector<LaneBox> quarter_boxes_;
    std::vector<std::pair<double, double>> quarter_t_;
    std::vector<UpInterval> quarter_values_, quarter_points_, quarter_slopes_;
    std::vector<std::array<double, 3>> quarter_dirs_;
    std::vector<UpInterval> fold_values_;  ///< fold()'s enclosures of the pruned list's slots
    std::vector<UpInterval> fold_regs_;    ///< fold()'s registers (the folded list at the centre)
    LaneFile<expr::IntervalLanes> d64_;
    LaneFile<expr::IntervalLanesF> f32_;
};

RayResult Walker::scan(const Ssa& list, const Ray& s, double width, int finer) {
    if (scan_.size() < list.size()) scan_.resize(list.size());
    const double w = width > 0 ? width : piece_width(s);
    const int n = pieces_of(s, w);
    RayResult res;
    res.status = Status::Miss;
    const auto g = [&](double p, double q) {  // in the walk's upward mode
        ++res.evals.interval;
        expr::detail::run<UpInterval>(list, ray_box(s, p, q), scan_.data());
        return scan_[list.back().out];
    };
    const auto proven_neg = [](const UpInterval& v) { return v.defined && v.upper() < 0; };
    const auto proven_pos = [](const UpInterval& v) { return v.defined && v.lower() > 0; };
    for (int k = 0; k < n; ++k) {
        const auto [p, q] = piece(s, w, k, n);
        if (!(p < q)) continue;
        const UpInterval v = g(p, q);
        if (proof(v) == Proof::Excluded) continue;
        res.status = Status::Unknown;
        res.t_lo = p;
        res.t_hi = s.tmax;
        if (solid_) {
            if (proven_neg(v)) {
                res.status = Status::Hit;
                res.t_hi = p;
            } else if (proven_neg(g(q, q))) {
                res.status = Status::Hit;
                res.t_hi = q;
            }
        } else if (v.defined) {
            const UpInterval gp = g(p, p);
            const UpInterval gq = g(q, q);
            if ((proven_neg(gp) && proven_pos(gq)) || (proven_pos(gp) && proven_neg(gq))) {
                res.status = Status::Hit;
                res.t_hi = q;
            }
        }
        if (res.status == Status::Hit) {
            res.t = 0.5 * res.t_lo + 0.5 * res.t_hi;
            return res;
        }
        return after_points(list, s, p, q, res, finer);
    }
    return res;
}

RayResult Walker::after_points(const Ssa& list, const Ray& s, double p, double q, RayResult res,
                               int finer, const Proof* form) {
    Proof again = form != nullptr ? *form : piece_mean_value(list, s, p, q, res);
    if (again == Proof::None && finer > 0) {
        // Scanned again in quarters: a Hit or an Unknown there is the answer (the segment is
        // free before p); a Miss proves [p, q] free.
        Ray piece = s;
        piece.tmin = p;
        piece.tmax = q;
        RayResult fine = scan(list, piece, 0.25 * (q - p), finer - 1);
        fine.evals += res.evals;
        if (fine.status != Status::Miss) {
            if (fine.status == Status::Unknown) fine.t_hi = s.tmax;
            return fine;
        }
        res.evals = fine.evals;
        again = Proof::Excluded;
    }
    if (again == Proof::Excluded) {  // [tmin, q] is free: the rest is scanned afresh
        RayResult rest;
        rest.status = Status::Miss;
        if (q < s.tmax) {
            Ray r = s;
            r.tmin = q;
            rest = scan(list, r);
        }
        rest.evals += res.evals;
        return rest;
    }
    if (again == Proof::Inside) {
        res.status = Status::Hit;
        res.t_hi = p;
        res.t = p;
    }
    return res;
}

Walker::Proof Walker::piece_mean_value(const Ssa& list, const Ray& s, double p, double q,
                                       RayResult& res) {
    // mean_value() counts a node's evaluations; these are the pixel's (added to the walk's
    // when the pixel is spent or answered) and not box evaluations.
    const EvalCounts before = evals;
    const std::uint64_t boxes = stats.box_evals, instructions = stats.box_instructions;
    const UpInterval m = mean_value(list, p, q, s.o.data(), s.o.data(), s.d.data(), s.d.data());
    res.evals.interval += evals.interval - before.interval;
    res.evals.gradient += evals.gradient - before.gradient;
    evals = before;
    stats.box_evals = boxes;
    stats.box_instructions = instructions;
    return m.is_empty() ? Proof::None : proof(m);
}

UpInterval Walker::mean_value(const Ssa& list, double a, double b, const double* olo,
                              const double* ohi, const double* dlo, const double* dhi,
                              const expr::TangentList* tl, LinearForm* lin) {
    const UpInterval none = UpInterval::empty();
    using D = Dual<UpInterval, 3>;
    if (duals_.size() < list.size()) duals_.resize(list.size());
    if (centre_.size() < list.size()) centre_.resize(list.size());
    count_form(list.size());
    const UpInterval t(a, b);
    const std::array<UpInterval, 3> x = segment_box(olo, ohi, dlo, dhi, a, b);
    const bool one_ray = std::equal(olo, olo + 3, ohi) && std::equal(dlo, dlo + 3, dhi);
    if (one_ray) {
        // One ray: the mean value form of g(t) = f(o + t·d) in t, g(tc) + G′(T)·(T − tc), with
        // G′ ⊇ ∇F(X)·d from one walk of Dual<UpInterval, 1> seeded with d (tighter than the form
        // over the box X, which ignores that the points lie on one line, and half the work).
        using D1 = Dual<UpInterval, 1>;
        if (duals1_.size() < list.size()) duals1_.resize(list.size());
        std::array<D1, 3> q;
        std::array<UpInterval, 3> c;
        const double tc = midpoint(t);
        for (int k = 0; k < 3; ++k) {
            const UpInterval o(olo[k]), d(dlo[k]);
            q[k] = D1(x[k], {d});
            c[k] = o + UpInterval(tc) * d;  // holds the real point o + tc·d
        }
        expr::detail::run<D1>(list, q, duals1_.data());
        const D1& g = duals1_[list.back().out];
        if (g.a.is_empty() || !g.a.defined || g.v[0].is_empty() || !std::isfinite(g.v[0].lower()) ||
            !std::isfinite(g.v[0].upper())) {
            return none;
        }
        expr::detail::run<UpInterval>(list, c, centre_.data());
        UpInterval m = centre_[list.back().out];
        if (m.is_empty() || !m.defined) return none;
        if (lin != nullptr) *lin = {m, g.v[0], tc, true};
        return m + g.v[0] * (t - UpInterval(tc));
    }
    // The form in the rays' own coordinates: for the point x = o + t·d of a ray of the node and
    // the centre x_c = oc + tc·dc (a point of the node's set: oc, dc, tc lie in the hulls),
    // x − x_c = (o − oc) + t·(d − dc) + (t − tc)·dc. Along the rays the gradient is dotted with dc
    // before it is widened by the segment's length, which the form over the box (Σ G_k·(X_k −
    // c_k)) cannot do: Barth's sextic, 512² pinhole, 7.2 → 6.7 evaluations per pixel.
    RayForm form;
    prepare_form(form, a, b, olo, ohi, dlo, dhi);
    const std::array<UpInterval, 3>& c = form.c;
    const double tc = form.tc;
    const double* oc = form.oc;
    const double* dc = form.dc;
    if (tl != nullptr) {
        // The same form from the tangent list: five lanes of one walk (ray_form_lanes), the box X
        // with the seeds e_x, e_y, e_z (the gradient's components, as the Dual walk has them) and
        // dc (∇f·dc directly: tighter than Σ G_k·dc_k), and the centre. (A scalar walk of the list
        // for the centre had paid on a first-generation Zen, 3–4%; on AVX2 and the baseline of
        // the Zen 4 of session 22 the lane is 0.96–1.02 of the time.) Interval seeds O − oc and
        // D − dc would lose the cancellations inside each component (twice as wide on Barth's
        // sextic), so those sums are taken over the components.
        ray_form_lanes(*tl, &form, 1);
        return ray_form(form, a, b, olo, ohi, dlo, dhi, lin);
    }
    std::array<D, 3> p;
    for (int k = 0; k < 3; ++k) {
        p[k] = D(x[k]);
        p[k].v[k] = UpInterval(1.0);
    }
    expr::detail::run<D>(list, p, duals_.data());
    const D& g = duals_[list.back().out];
    // Lebourg's mean value theorem (Clarke gradients cover the kinks of abs, min, max) needs f
    // defined and continuous on the whole box and a bounded gradient enclosure.
    if (g.a.is_empty() || !g.a.defined) return none;
    for (int k = 0; k < 3; ++k) {
        if (g.v[k].is_empty() || !std::isfinite(g.v[k].lower()) || !std::isfinite(g.v[k].upper())) {
            return none;
        }
    }
    expr::detail::run<UpInterval>(list, c, centre_.data());
    UpInterval m = centre_[list.back().out];
    if (m.is_empty() || !m.defined) return none;
    UpInterval along(0.0), across(0.0);
    for (int k = 0; k < 3; ++k) {
        m = m + g.v[k] * (UpInterval(olo[k], ohi[k]) - UpInterval(oc[k]));
        across = across + g.v[k] * (UpInterval(dlo[k], dhi[k]) - UpInterval(dc[k]));
        along = along + g.v[k] * UpInterval(dc[k]);
    }
    if (lin != nullptr) *lin = {m + UpInterval(tc) * across, across + along, tc, true};
    return m + t * across + along * (t - UpInterval(tc));
}

bool Walker::tile(const Rect& r) {
    root_ = r;
    mean_values_.reset();  // each tile decides afresh (the same in any thread)
    wide_forms_.reset();
    tile_trial_.reset();
    kink_forms_.reset();
    second_trial_.reset();
    plain_tried_ = plain_free_ = 0;
    fold_trial_.reset();
    root_box_.reset();
    // The tile's answers, a miss until answered: kept here while the walk writes them (a few
    // KiB, in cache) and written into the image's arrays row by row at the end, one pass instead
    // of the defaults and then the answers.
    const std::size_t n = std::size_t{r.w} * r.h;
    mine_.width = r.w;
    mine_.height = r.h;
    mine_.status.assign(n, Status::Miss);
    mine_.t.assign(n, std::numeric_limits<double>::quiet_NaN());
    mine_.evals.assign(n, 0);
    mine_.normal.assign(n, {0.f, 0.f, 0.f});
    const bool empty = (rays_.projection() == Projection::Ortho && ortho_tile_free(r)) ||
                       rays_.misses(r.i0, r.j0, r.w, r.h);  // no ray to build: every pixel a Miss
    if (empty) {
        ++stats.empty_tiles;
    } else {
        walk_tile(r);
    }
    // Counted here, in the tile's own arrays (a few KiB, in cache), in loops the compiler turns
    // into vectors: the pass over the image's arrays after the copy had taken 7% of Barth's 512²
    // heightmap.
    // (An empty tile's: n Misses of no evaluation.)
    tile_counts = RenderStats{};
    if (!empty) {
        for (std::size_t k = 0; k < n; ++k) {
            tile_counts.hit += mine_.status[k] == Status::Hit;
            tile_counts.unknown += mine_.status[k] == Status::Unknown;
        }
        for (std::size_t k = 0; k < n; ++k) {
            tile_counts.max_pixel_evals = std::max(tile_counts.max_pixel_evals, mine_.evals[k]);
        }
    }
    tile_counts.miss = n - tile_counts.hit - tile_counts.unknown;
    if (ans_.status.empty()) return empty;  // the image's answers not kept (RenderOptions::answers)
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        const std::size_t from = std::size_t{j - r.j0} * r.w,
                          to = std::size_t{j} * ans_.width + r.i0;
        std::copy_n(mine_.status.data() + from, r.w, ans_.status.data() + to);
        std::copy_n(mine_.t.data() + from, r.w, ans_.t.data() + to);
        std::copy_n(mine_.evals.data() + from, r.w, ans_.evals.data() + to);
        std::copy_n(mine_.normal.data() + from, r.w, ans_.normal.data() + to);
    }
    return empty;
}

void Walker::walk_tile(const Rect& r) {
    px_.assign(std::size_t{r.w} * r.h, Px{});
    blocks_w_ = (r.w + kBlock - 1) / kBlock;
    blocks_.assign(std::size_t{blocks_w_} * ((r.h + kBlock - 1) / kBlock), Block{});
    double a = kInf, b = -kInf;
    {
        NearestScope env;  // one switch for the tile's rays
        row_rays_.resize(r.w);
        row_in_.resize(r.w);
        for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
            rays_.row_in_scope(r.i0, j, r.w, row_rays_.data(), row_in_.data());
            for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
                Px& p = px(i, j);
                p.ray = row_rays_[i - r.i0];
                // A ray that misses the bounds: Miss, no evaluation.
                p.open = row_in_[i - r.i0];
                if (!p.open) continue;
                ++block_of(i, j).open;
                a = std::min(a, p.ray.tmin);
                b = std::max(b, p.ray.tmax);
            }
        }
    }
    if (a <= b) {
        // One RoundingScope for the whole walk (a mode switch costs more than a box evaluation of
        // a short tape): node() and the mean value form compute UpIntervals in it; their plain
        // double arithmetic only picks split points, whose rounding does not matter; the solver
        // and the normals open a NearestScope of their own.
        RoundingScope up;
        node(r, a, b, tape_.ssa(), &tape_, 0);
        flush_normals();  // (none waits: each scan's wait ends with it)
    }
    // Open rays left are proven free of zeros on their whole segment: Misses (the default).
}

bool Walker::ortho_tile_free(const Rect& r) {
    // A heightmap's rays are a grid, each in scope over the same [0, tmax] straight down: the
    // hull of the tile's rays is that of its corner rays (the coordinates PixelRays computes are
    // monotone in i and j), and the box over the whole depth is the root node's. Where f is
    // proven free of the surface on it, the tile is answered without building its rays.
    Ray c0, c1;
    {
        NearestScope env;  // as tile() builds the rays
        if (!rays_.ray_in_scope(r.i0, r.j0, c0) ||
            !rays_.ray_in_scope(r.i0 + r.w - 1, r.j0 + r.h - 1, c1)) {
            return false;
        }
    }
    double olo[3], ohi[3];
    for (int c = 0; c < 3; ++c) {
        olo[c] = std::min(c0.o[c], c1.o[c]);
        ohi[c] = std::max(c0.o[c], c1.o[c]);
    }
    const double a = std::min(c0.tmin, c1.tmin), b = std::max(c0.tmax, c1.tmax);
    const Ssa& list = tape_.ssa();
    Level& level = levels_[0];
    if (level.values.size() < list.size()) level.values.resize(list.size());
    RoundingScope up;
    root_box_ = segment_box(olo, ohi, c0.d.data(), c0.d.data(), a, b);
    expr::detail::run<UpInterval>(list, *root_box_, level.values.data());
    ++stats.box_evals;
    stats.box_instructions += list.size();
    ++evals.interval;
    if (proof(level.values[list.back().out]) != Proof::Excluded) return false;  // node() goes on
    root_box_.reset();
    ++stats.boxes_excluded;
    return true;
}

Walker::Hull Walker::hull_of(const Rect& r, double a, double b) {
    Hull hull;
    hull.answered = answered_;
    // Whole blocks: r starts on a block's corner and ends on one, or at the root tile's end.
    const bool blocks = options_.block_hulls && (r.i0 - root_.i0) % kBlock == 0 &&
                        (r.j0 - root_.j0) % kBlock == 0 &&
                        (r.w % kBlock == 0 || r.i0 + r.w == root_.i0 + root_.w) &&
                        (r.h % kBlock == 0 || r.j0 + r.h == root_.j0 + root_.h);
    // The origin or direction that does not vary is the first open ray's.
    varying([&](auto vary_o, auto vary_d) {
        const Px* first = nullptr;
        const auto pixels = [&](unsigned i0, unsigned j0, unsigned w, unsigned h) {
            for (unsigned j = j0; j < j0 + h; ++j) {
                for (unsigned i = i0; i < i0 + w; ++i) {
                    const Px& p = px(i, j);
                    if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
                    if (first == nullptr) first = &p;
                    hull.add<vary_o, vary_d>(p.ray);
                }
            }
        };
        if (!blocks) {
            pixels(r.i0, r.j0, r.w, r.h);
        } else {
            for (unsigned bj = r.j0; bj < r.j0 + r.h; bj += kBlock) {
                for (unsigned bi = r.i0; bi < r.i0 + r.w; bi += kBlock) {
                    Block& k = block_of(bi, bj);
                    if (k.open == 0) continue;
                    if (k.stale) take_block(k, bi, bj);
                    if (k.max_tmin <= b && k.min_tmax >= a) {  // every open ray meets [a, b]
                        if (first == nullptr) first = k.first;
                        hull.add<vary_o, vary_d>(k.hull);
                    } else {
                        pixels(bi, bj, std::min(kBlock, r.i0 + r.w - bi),
                               std::min(kBlock, r.j0 + r.h - bj));
                    }
                }
            }
        }
        if (first == nullptr) return;
        for (int c = 0; c < 3; ++c) {
            if constexpr (!vary_o) hull.olo[c] = hull.ohi[c] = first->ray.o[c];
            if constexpr (!vary_d) hull.dlo[c] = hull.dhi[c] = first->ray.d[c];
        }
    });
    return hull;
}

void Walker::take_block(Block& k, unsigned i0, unsigned j0) {
    const unsigned open = k.open;
    k = Block{};
    k.open = open;
    k.stale = false;
    Hull& h = k.hull;
    const unsigned i1 = std::min(i0 + kBlock, root_.i0 + root_.w);
    const unsigned j1 = std::min(j0 + kBlock, root_.j0 + root_.h);
    // As hull_of: the origins where they vary (not a pinhole's), the directions where they do
    // (not a heightmap's); hull_of takes the other one from the first open ray.
    varying([&](auto vary_o, auto vary_d) {
        for (unsigned j = j0; j < j1; ++j) {
            for (unsigned i = i0; i < i1; ++i) {
                const Px& p = px(i, j);
                if (!p.open) continue;
                if (k.first == nullptr) k.first = &p;
                h.add<vary_o, vary_d>(p.ray);
                k.max_tmin = std::max(k.max_tmin, p.ray.tmin);
                k.min_tmax = std::min(k.min_tmax, p.ray.tmax);
            }
        }
    });
}

void Walker::node(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                  unsigned depth, const Hull* given) {
    // The open rays of r that meet [a, b], and the hull of their origins and directions. A
    // parent's hull over the same rectangle serves while no ray has been answered since it was
    // taken: its rays are a superset, so its box still holds them all.
    const Hull hull = given != nullptr && given->answered == answered_ ? *given : hull_of(r, a, b);
    const unsigned count = hull.count;
    if (count == 0) return;
    // Rays start no earlier than tlo and end by thi: nothing of them lies outside [tlo, thi].
    a = std::max(a, hull.tlo);
    b = std::min(b, hull.thi);

    // The box [o] + [a, b]·[d] holds o + t·d for every such ray and t in [a, b] (rounded outward).
    Level& level = levels_[depth];
    const Box box = segment_box(hull.olo, hull.ohi, hull.dlo, hull.dhi, a, b);
    const auto same = [](const Box& x, const Box& y) {
        for (int c = 0; c < 3; ++c) {
            if (x[c].lower() != y[c].lower() || x[c].upper() != y[c].upper()) return false;
        }
        return true;
    };
    if (depth == 0 && list.data() == tape_.ssa().data() && root_box_ && same(*root_box_, box)) {
        // ortho_tile_free() evaluated the full tape over this box into level.values.
    } else {
        if (level.values.size() < list.size()) level.values.resize(list.size());
        expr::detail::run<UpInterval>(list, box, level.values.data());
        ++stats.box_evals;
        stats.box_instructions += list.size();
        ++evals.interval;
    }
    root_box_.reset();
    // Zero: 0 ∉ F (or f undefined on the whole box), no ray meets f = 0 here. Solid: F ≥ 0, no
    // ray enters {f < 0} here; or F < 0, every ray enters at its first point in the box.
    Proof proven = proof(level.values[list.back().out]);
    if (proven == Proof::None && try_mean_value(count, list, depth)) {
        const expr::TangentList* tl =
            tangent_kind(list, depth) == expr::TangentKind::Smooth ? tangent(list, depth) : nullptr;
        LinearForm lin;
        const UpInterval m =
            mean_value(list, a, b, hull.olo, hull.ohi, hull.dlo, hull.dhi, tl, &lin);
        mean_value_tried(count, take_form(m, lin, proven, a, b));
    }
    descend(r, a, b, list, tape, depth, hull, proven);
}

void Walker::descend(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                     unsigned depth, const Hull& hull, Proof proven) {
    if (proven == Proof::Excluded) {
        ++stats.boxes_excluded;
        return;
    }
    if (proven == Proof::Inside) {
        ++stats.boxes_inside;
        inside(r, a, b, list);
        return;
    }
    Level& level = levels_[depth];
    const unsigned count = hull.count;
    const Ssa* sub = &list;
    const expr::Tape* sub_tape = tape;
    if (choices_) level.tangent.forget();  // level.list may be rewritten
    if (choices_ && expr::prune_ssa(list, level.values.data(), prune_ws_, level.list)) {
        sub = &level.list;
        sub_tape = nullptr;
        ++stats.prunes;
    }

    // Smooth lists (a tangent list without kinks) get their scans' forms in lanes and tight:
    // wider scans pay there (kinked ones keep 8: their forms at ties are looser).
    // Long lists too: a walk's cost per instruction is then spread over more lanes.
    const bool together = scans_together(count, *sub, depth);
    if (together && scan_together(r, a, b, *sub, sub_tape, level, depth, hull)) {
        return;
    }
    // More rays still, where the list folds to the node's box: the folded list's walks are
    // shorter, and one box, prune and fold serve them all.
    if (!together && count <= options_.folded_together_rays && may_fold(*sub) &&
        scan_together(r, a, b, *sub, sub_tape, level, depth, hull, true)) {
        ++stats.folded_scans;
        return;
    }
    if (count > 1 && depth + 1 < kMaxDepth) {
        // How far apart the rays are at the far end, plus a pixel: the box's lateral extent.
        double spread_o = 0, spread_d = 0;
        for (int c = 0; c < 3; ++c) {
            spread_o = std::max(spread_o, hull.ohi[c] - hull.olo[c]);
            spread_d = std::max(spread_d, hull.dhi[c] - hull.dlo[c]);
        }
        const double lateral = spread_o + std::fabs(b) * spread_d +
                               rays_.pixel_pitch() * (rays_.angular() ? std::fabs(b) : 1);
        if (t_splits_ && b - a > options_.aspect * lateral && splittable(a, b)) {
            // Near segment first: the far one only sees the rays the near one left open.
            const double m = 0.5 * a + 0.5 * b;
            node(r, a, m, *sub, sub_tape, depth + 1, &hull);
            node(r, m, b, *sub, sub_tape, depth + 1, &hull);
            return;
        }
        if (r.w > 1 || r.h > 1) {
            split_screen(r, a, b, *sub, sub_tape, depth + 1);
            return;
        }
    }
    leaf(r, a, b, *sub, sub_tape, level, depth);
}

void Walker::split_screen(const Rect& r, double a, double b, const Ssa& list,
                          const expr::Tape* tape, unsigned depth) {
    const unsigned w1 = (r.w + 1) / 2, h1 = (r.h + 1) / 2;
    Rect quarter[4];
    int n = 0;
    quarter[n++] = {r.i0, r.j0, w1, h1};
    if (r.w > w1) quarter[n++] = {r.i0 + w1, r.j0, r.w - w1, h1};
    if (r.h > h1) quarter[n++] = {r.i0, r.j0 + h1, w1, r.h - h1};
    if (r.w > w1 && r.h > h1) quarter[n++] = {r.i0 + w1, r.j0 + h1, r.w - w1, r.h - h1};
    // A long list's registers of 64 lanes (a KiB each) outgrow the caches where a walk per quarter
    // stays in them: the molecule's lists of thousands of instructions took 1.1× the time (a limit
    // of 256: the same as a walk per quarter, within the noise).
    if (!options_.children_in_lanes || list.size() > kLanesList) {
        for (int k = 0; k < n; ++k) node(quarter[k], a, b, list, tape, depth);
        return;
    }
    // Each quarter's slot enclosures are level.values at `depth`, which the descent below reads
    // to prune (choices_) and to fold (may_fold): there they are kept from the lanes.
    Level& level = levels_[depth];
    const bool keep_values = choices_ || may_fold(list);
    // The quarters' rays are disjoint: a quarter's hull, taken before the others are walked,
    // is the one node() would take when it comes to it.
    struct Quarter {
        Hull hull;
        double a, b;
        Proof proven;
        int form;  // its lanes in forms, or −1
    };
    Quarter q[4];
    LaneBox boxes[4];
    int live[4];
    int m = 0;
    for (int k = 0; k < n; ++k) {
        q[k].hull = hull_of(quarter[k], a, b);
        if (q[k].hull.count == 0) continue;
        q[k].a = std::max(a, q[k].hull.tlo);
        q[k].b = std::min(b, q[k].hull.thi);
        const Box box =
            segment_box(q[k].hull.olo, q[k].hull.ohi, q[k].hull.dlo, q[k].hull.dhi, q[k].a, q[k].b);
        for (int c = 0; c < 3; ++c) {
            boxes[m].lo[c] = box[c].lower();
            boxes[m].hi[c] = box[c].upper();
        }
        live[m++] = k;
    }
    if (m == 0) return;
    // The boxes' enclosures in double lanes: lane l is bit for bit run<UpInterval>'s over box l.
    eval_lanes_in(d64_, list, boxes, static_cast<std::size_t>(m), split_values_, nullptr);
    if (keep_values) {
        // Lane l of every slot is what node() would leave in level.values for quarter l; kept
        // apart, as the forms' walks and the deeper levels reuse the lane file.
        for (int l = 0; l < m; ++l) {
            std::vector<UpInterval>& v = level.quarters[l];
            if (v.size() < list.size()) v.resize(list.size());
            for (const expr::Instr& in : list) v[in.out] = expr::lane(d64_.regs[in.out], l);
        }
    }
    stats.box_evals += m;
    stats.box_instructions += m * list.size();
    evals.interval += m;
    const expr::TangentList* tl = nullptr;
    bool smooth_known = false;
    int forms = 0;
    for (int l = 0; l < m; ++l) {
        Quarter& z = q[live[l]];
        z.proven = proof(split_values_[l]);
        z.form = -1;
        if (z.proven != Proof::None || !try_mean_value(z.hull.count, list, depth)) continue;
        if (!smooth_known) {
            smooth_known = true;
            if (tangent_kind(list, depth) == expr::TangentKind::Smooth) tl = tangent(list, depth);
        }
        const Hull& h = z.hull;
        const bool one_ray =
            std::equal(h.olo, h.olo + 3, h.ohi) && std::equal(h.dlo, h.dlo + 3, h.dhi);
        if (tl != nullptr && !one_ray) {
            prepare_form(forms_[forms], z.a, z.b, h.olo, h.ohi, h.dlo, h.dhi);
            z.form = forms++;
            continue;
        }
        LinearForm lin;
        const UpInterval f = mean_value(list, z.a, z.b, h.olo, h.ohi, h.dlo, h.dhi, tl, &lin);
        mean_value_tried(h.count, take_form(f, lin, z.proven, z.a, z.b));
    }
    if (forms > 0) {
        ray_form_lanes(*tl, forms_, forms);
        for (int l = 0; l < m; ++l) {
            Quarter& z = q[live[l]];
            if (z.form < 0) continue;
            const Hull& h = z.hull;
            count_form(list.size());
            LinearForm lin;
            const UpInterval f =
                ray_form(forms_[z.form], z.a, z.b, h.olo, h.ohi, h.dlo, h.dhi, &lin);
            mean_value_tried(h.count, take_form(f, lin, z.proven, z.a, z.b));
        }
    }
    // The quarters that descend() would scan at once, scanned together (merged_scans): their
    // rays are disjoint, and one list without a prune or fold serves them all, so each phase of
    // the scan is one walk for all of them where it was one per quarter.
    unsigned merged = 0;
    if (options_.merged_scans && !keep_values && m >= 2 &&
        !(options_.tile_pieces && tile_trial_.paying())) {
        ScanGroup groups[4];
        int of[4];
        int g = 0;
        for (int l = 0; l < m; ++l) {
            const Quarter& z = q[live[l]];
            if (z.proven != Proof::None || !scans_together(z.hull.count, list, depth)) continue;
            groups[g] = {quarter[live[l]], z.a, z.b, &z.hull};
            of[g++] = l;
        }
        if (g >= 2) {
            const unsigned taken = scan_groups(groups, g, list, tape, level, depth, false);
            stats.merged_scans += std::popcount(taken) >= 2;
            for (int k = 0; k < g; ++k) merged |= (taken >> k & 1u) << of[k];
        }
    }
    for (int l = 0; l < m; ++l) {
        if (merged >> l & 1u) continue;
        Quarter& z = q[live[l]];
        z.hull.answered = answered_;  // the rays answered since are the other quarters'
        if (keep_values) level.values.swap(level.quarters[l]);
        descend(quarter[live[l]], z.a, z.b, list, tape, depth, z.hull, z.proven);
    }
}

void Walker::leaf(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                  Level& level, unsigned depth) {
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
            Px& p = px(i, j);
            if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
            // [tmin, a) is proven free of zeros, and `list` equals f on the ray for t in [a, b].
            Ray s = p.ray;
            s.tmin = std::max(a, p.ray.tmin);
            s.tmax = std::min(b, p.ray.tmax);
            const double w = piece_width(s);
            // A segment a few depths long is scanned in pieces, the solver only where that does
            // not decide.
            const bool scanned = w > 0 && s.tmax - s.tmin <= kMaxPieces * w;
            settle(i, j, s, scanned ? scan(list, s) : RayResult{}, scanned, list, tape, level,
                   depth);
        }
    }
}

void Walker::settle(unsigned i, unsigned j, const Ray& s, RayResult res, bool scanned,
                    const Ssa& list, const expr::Tape*& tape, Level& level, unsigned depth) {
    // The register tape only when a solver runs (a scan walks the list itself).
    const auto solver_tape = [&]() -> const expr::Tape& {
        if (tape == nullptr) {
            level.tape = tape_of(list);
            tape = &level.tape;
        }
        return *tape;
    };
    Px& p = px(i, j);
    ++stats.leaf_solves;
    // Where the list has choices, an undecided segment is split with a tape pruned to each half
    // (below) before the solver is tried on it: the scan has taken its pieces, points, forms and
    // quarters, and the solver on the same list seldom decides more (Fidget's colonnade: 585 such
    // rays, 185 evaluations each, none decided; the halves' prunes decide them).
    const bool split_first =
        choices_ && p.splits < kMaxSplits && depth + 1 < kMaxDepth && splittable(s.tmin, s.tmax);
    if (!scanned) {
        res = solve(solver_tape(), s);
    } else if (res.status != Status::Unknown || split_first) {
        ++stats.scans;
    } else {
        const EvalCounts spent = res.evals;
        Ray rest = s;
        rest.tmin = res.t_lo;
        res = solve(solver_tape(), rest);
        res.evals += spent;
    }
    if (res.status == Status::Miss) {  // free of zeros up to b: the walk goes on
        spend(i, j, res.evals);
        return;
    }
    if (res.status == Status::Unknown && split_first) {
        // Undecided on the segment with this tape: each half gets its own box evaluation and a
        // tape pruned to it, where the choices that blurred the sign may resolve
        // (max(x, −min(x, y)) at the edge of a plane where f touches 0, say).
        ++p.splits;
        ++stats.splits;
        spend(i, j, res.evals);
        const double m = 0.5 * s.tmin + 0.5 * s.tmax;
        const Rect one{i, j, 1, 1};  // this ray alone
        node(one, s.tmin, m, list, tape, depth + 1);
        if (p.open) node(one, m, s.tmax, list, tape, depth + 1);
        return;  // answered by the halves, or proven free of zeros up to s.tmax
    }
    if (res.status == Status::Unknown && s.tmax < p.ray.tmax) {
        // Undecided in this segment: the per-ray solver on the rest of the ray (full tape) may
        // still prove a zero further along, as it would on the whole ray.
        ++stats.fallbacks;
        Ray rest = p.ray;
        rest.tmin = s.tmin;
        const EvalCounts spent = res.evals;
        res = solve(tape_, rest);
        res.evals += spent;
    }
    answer(i, j, p, res, list, s.tmin, s.tmax);
}

void Walker::prepare_form(RayForm& f, double a, double b, const double* olo, const double* ohi,
                          const double* dlo, const double* dhi) {
    f.x = segment_box(olo, ohi, dlo, dhi, a, b);
    f.tc = midpoint(UpInterval(a, b));
    for (int k = 0; k < 3; ++k) {
        f.oc[k] = std::clamp(0.5 * olo[k] + 0.5 * ohi[k], olo[k], ohi[k]);
        f.dc[k] = std::clamp(0.5 * dlo[k] + 0.5 * dhi[k], dlo[k], dhi[k]);
        f.c[k] = UpInterval(f.oc[k]) + UpInterval(f.tc) * UpInterval(f.dc[k]);  // oc + tc·dc
    }
}

UpInterval Walker::ray_form(const RayForm& f, double a, double b, const double* olo,
                            const double* ohi, const double* dlo, const double* dhi,
                            LinearForm* lin) {
    UpInterval m = f.m;
    if (!f.ok || m.is_empty() || !m.defined) return UpInterval::empty();
    const UpInterval t(a, b);
    UpInterval across(0.0);
    // A coordinate that does not vary (a pinhole's origin, a heightmap's direction) adds
    // G_k·[0, 0]: nothing, the term is passed.
    for (int k = 0; k < 3; ++k) {
        if (olo[k] != ohi[k]) m = m + f.g[k] * (UpInterval(olo[k], ohi[k]) - UpInterval(f.oc[k]));
        if (dlo[k] != dhi[k]) {
            across = across + f.g[k] * (UpInterval(dlo[k], dhi[k]) - UpInterval(f.dc[k]));
        }
    }
    if (lin != nullptr) {
        // At a point t, t·G·(d − dc) lies in tc·across + (t − tc)·across: the line's terms.
        *lin = {m + UpInterval(f.tc) * across, across + f.g[3], f.tc, true};
    }
    return m + t * across + f.g[3] * (t - UpInterval(f.tc));
}

void Walker::clip_to_line(const LinearForm& lin, double& a, double& b) const {
    // u = t − tc runs over [u0, u1] ⊇ [a − tc, b − tc]; over a sub-range U of it the line's
    // values are p + U·q, exactly the interval product's (each of p, q, u occurs once), which
    // proves a part free as a box's enclosure does. Where the line may vanish is found in plain
    // doubles (a guess); each cut is kept only where p + U·q over the part cut off proves it.
    const UpInterval& p = lin.p;
    const UpInterval& q = lin.q;
    if (p.is_empty() || q.is_empty() || !std::isfinite(p.lower()) || !std::isfinite(p.upper()) ||
        !std::isfinite(q.lower()) || !std::isfinite(q.upper())) {
        return;
    }
    const double u0 = -(lin.tc - a), u1 = b - lin.tc;  // rounded down, and up (upward mode)
    if (!(u0 < u1)) return;
    const auto may = [&](double u) {  // the line may vanish (the solid: be negative) at u
        const double lo = p.lower() + std::min(u * q.lower(), u * q.upper());
        const double hi = p.upper() + std::max(u * q.lower(), u * q.upper());
        return solid_ ? lo < 0 : lo <= 0 && 0 <= hi;
    };
    // Its ends lie among the roots of the bounds' lines (on u ≥ 0 and on u ≤ 0 each bound is one).
    double cut[7] = {u0, u1};
    int n = 2;
    const auto add = [&](double u) {
        if (u > u0 && u < u1) cut[n++] = u;
    };
    if (u0 < 0 && u1 > 0) add(0);
    for (const double c : {q.lower(), q.upper()}) {
        if (c == 0) continue;
        add(-p.lower() / c);
        if (!solid_) add(-p.upper() / c);
    }
    for (int k = 1; k < n; ++k) {  // a handful: insertion
        for (int l = k; l > 0 && cut[l] < cut[l - 1]; --l) std::swap(cut[l], cut[l - 1]);
    }
    int first = -1, last = -1;  // the first and last cuts where it may vanish, or just after
    for (int k = 0; k < n; ++k) {
        const bool here = may(cut[k]) || (k + 1 < n && may(0.5 * cut[k] + 0.5 * cut[k + 1]));
        const bool before = may(cut[k]) || (k > 0 && may(0.5 * cut[k - 1] + 0.5 * cut[k]));
        if (here && first < 0) first = k;
        if (before) last = k;
    }
    const double margin = 1e-6 * (u1 - u0);
    const auto free = [&](double lo, double hi) {
        return lo <= hi && proof(p + UpInterval(lo, hi) * q) == Proof::Excluded;
    };
    if (first < 0 || last < 0) {
        if (free(u0, u1)) a = kInf, b = -kInf;  // (a guess proven: no point of it may vanish)
        return;
    }
    const double front = cut[first] - margin, back = cut[last] + margin;
    if (cut[first] > u0 && front > u0 && free(u0, front)) {
        a = std::max(a, -(-lin.tc - front));  // tc + front rounded down
    }
    if (cut[last] < u1 && back < u1 && free(back, u1)) {
        b = std::min(b, lin.tc + back);  // rounded up
    }
}

void Walker::ray_form_lanes(const expr::TangentList& tl, RayForm* forms, int n) {
    if (float_lanes_) {
        ray_form_lanes_in(f32_, tl, forms, n);
    } else {
        ray_form_lanes_in(d64_, tl, forms, n);
    }
}

template <class L>
void Walker::ray_form_lanes_in(LaneFile<L>& file, const expr::TangentList& tl, RayForm* forms,
                               int n) {
    // Form k's lanes 5k … 5k + 3 walk its box x with the seeds e_x, e_y, e_z (the gradient's
    // components) and dc (∇f·dc directly, tighter than Σ G_k·dc_k); lane 5k + 4 its centre c
    // with the seed 0 (the tangent list's value lanes are the list's, bit for bit). In binary32
    // lanes the boxes and dc are rounded outward: every lane encloses what the double walk's
    // does, and three forms fill one vector.
    constexpr int kLanes = 5;
    LaneBox boxes[kMaxForms * kLanes];
    const int lanes = n * kLanes;
    for (int f = 0; f < n; ++f) {
        for (int k = 0; k < 3; ++k) {
            for (int l = 0; l < 4; ++l) {
                boxes[f * kLanes + l].lo[k] = forms[f].x[k].lower();
                boxes[f * kLanes + l].hi[k] = forms[f].x[k].upper();
            }
            boxes[f * kLanes + 4].lo[k] = forms[f].c[k].lower();
            boxes[f * kLanes + 4].hi[k] = forms[f].c[k].upper();
        }
    }
    load_lanes(file, boxes, lanes);
    if (file.regs.size() < tl.slots) file.regs.resize(tl.slots);
    for (int k = 0; k < 3; ++k) {
        L& seed = file.regs[tl.seed[k]];
        for (int f = 0; f < n; ++f) {
            for (int l = 0; l < 3; ++l) {
                expr::set_lane(seed, f * kLanes + l, UpInterval(l == k ? 1.0 : 0.0));
            }
            expr::set_lane(seed, f * kLanes + 3, UpInterval(forms[f].dc[k]));
            expr::set_lane(seed, f * kLanes + 4, UpInterval(0.0));
        }
    }
    expr::run_interval_batch(tl.list.data(), tl.list.data() + tl.list.size(), file.in.data(),
                             file.regs.data(), lanes);
    for (int f = 0; f < n; ++f) {
        RayForm& form = forms[f];
        form.m = expr::lane(file.regs[tl.value], f * kLanes + 4);
        const UpInterval v = expr::lane(file.regs[tl.value], f * kLanes);
        form.ok = !v.is_empty() && v.defined;
        for (int l = 0; l < 4 && form.ok; ++l) {
            form.g[l] = expr::lane(file.regs[tl.derivative], f * kLanes + l);
            form.ok = finite(form.g[l]);
        }
    }
}

template <class L>
void Walker::load_lanes(LaneFile<L>& file, const LaneBox* boxes, int m) {
    static_assert(expr::kIntervalLanes <= 64, "one word of decorations per register");
    // The walks hold the upward mode, in which set_bounds_upward rounds binary32 bounds outward
    // without set_bounds' branches (MXCSR's field on x86-64: the x87 word, which fegetround
    // reads there, stays nearest).
#ifdef CERTRAY_X86_64_ROUNDING
    assert((certray::detail::X86RoundingControl::current().mxcsr >> 13 & 3u) == 2u);
#else
    assert(std::fegetround() == FE_UPWARD);
#endif
    for (int c = 0; c < 3; ++c) {
        L& x = file.in[c];
        std::uint64_t def = 0;
        for (int k = 0; k < m; ++k) {
            const double lo = boxes[k].lo[c], hi = boxes[k].hi[c];
            if (lo <= hi) {
                expr::set_bounds_upward(x, k, lo, hi);
                def |= std::uint64_t{1} << k;
            } else {
                expr::set_lane(x, k, UpInterval::empty());
            }
        }
        x.defined[0] = def;
    }
}

void Walker::eval_lanes(const Ssa& list, const LaneBox* boxes, std::size_t n,
                        std::vector<UpInterval>& out, const Level* fold) {
    if (float_lanes_) {
        eval_lanes_in(f32_, list, boxes, n, out, fold);
    } else {
        eval_lanes_in(d64_, list, boxes, n, out, fold);
    }
}

template <class L>
void Walker::eval_lanes_in(LaneFile<L>& file, const Ssa& list, const LaneBox* boxes, std::size_t n,
                           std::vector<UpInterval>& out, const Level* fold) {
    if (fold != nullptr && fold->folded.list.empty()) fold = nullptr;
    const Ssa& walked = fold != nullptr ? fold->folded.list : list;
    // The folded list's slots (and its fixed ones) are the list's: fewer than its length.
    if (file.regs.size() < list.size()) file.regs.resize(list.size());
    if (out.size() < n) out.resize(n);
    const std::uint32_t f = walked.back().out;
    for (std::size_t k0 = 0; k0 < n; k0 += expr::kIntervalLanes) {
        const int m = static_cast<int>(std::min<std::size_t>(expr::kIntervalLanes, n - k0));
        load_lanes(file, boxes + k0, m);
        if (fold != nullptr) load_fixed(file, *fold, m);
        expr::run_interval_batch(walked.data(), walked.data() + walked.size(), file.in.data(),
                                 file.regs.data(), m);
        for (int k = 0; k < m; ++k) out[k0 + k] = expr::lane(file.regs[f], k);
    }
}

template <class L>
void Walker::load_fixed(LaneFile<L>& file, const Level& level, int m) {
    for (const auto& [slot, v] : level.folded.fixed) {
        L& x = file.regs[slot];
        expr::set_bounds(x, 0, v.lower(), v.upper());  // binary32: rounded outward
        std::fill(x.lo + 1, x.lo + m, x.lo[0]);
        std::fill(x.hi + 1, x.hi + m, x.hi[0]);
        x.defined[0] = ~std::uint64_t{0};  // fold_ssa fixes defined enclosures only
    }
}

void Walker::fold(const Ssa& sub, const std::array<UpInterval, 3>& box, Level& level) {
    expr::FoldedList& folded = level.folded;
    folded.list.clear();
    folded.fixed.clear();
    level.folded_tangent.forget();
    if (!may_fold(sub) || !fold_trial_.attempt()) return;
    // The enclosures of sub's slots over the box: level.values (the node's list's), through
    // prune_ssa's renaming where sub is that list pruned (a slot that took over a dropped
    // min/max's has the same values on the box; prune_ws_.bind has a slot per slot of the
    // node's list).
    const std::size_t n = sub.size();
    const UpInterval* values = level.values.data();
    if (&sub == &level.list) {
        fold_values_.assign(n, UpInterval::empty());
        for (std::size_t i = 0; i < prune_ws_.bind.size(); ++i) {
            const std::uint32_t s = prune_ws_.bind[i];
            if (s < n) fold_values_[s] = level.values[i];
        }
        values = fold_values_.data();
    }
    const UpInterval f = values[sub.back().out];
    const double w = f.upper() - f.lower();
    if (!(w > 0) || !std::isfinite(w)) return;
    std::array<UpInterval, 3> centre;
    for (int c = 0; c < 3; ++c) centre[c] = UpInterval(midpoint(box[c]));
    if (fold_regs_.size() < n) fold_regs_.resize(n);
    double width = kFoldWidth * w;
    for (int tries = 0; tries < 3; ++tries, width /= 32) {
        // An eighth of the list or more, or none (a narrower width drops less).
        if (8 * expr::fold_ssa(sub, values, width, folded) < n) break;
        for (const auto& [slot, v] : folded.fixed) fold_regs_[slot] = v;
        expr::detail::run<UpInterval>(folded.list, centre, fold_regs_.data());
        const UpInterval at = fold_regs_[folded.list.back().out];
        if (at.upper() - at.lower() <= kFoldCentre * w) {
            ++stats.folds;
            stats.folded_instructions += n - folded.list.size();
            ++fold_trial_.wins;
            return;
        }
    }
    folded.list.clear();
    folded.fixed.clear();
}

expr::TangentKind Walker::lane_tangent_kind(const Ssa& list, unsigned depth, Level& level) {
    if (level.folded.list.empty()) return tangent_kind(list, depth);
    return level.folded_tangent.kind_of(level.folded.list);
}

const expr::TangentList* Walker::lane_tangent(const Ssa& list, unsigned depth, Level& level) {
    if (level.folded.list.empty()) return tangent(list, depth);
    return level.folded_tangent.of(level.folded.list);
}

const expr::TangentList* Walker::tangent(const Ssa& list, unsigned depth) {
    // The tape's own list, or a level's pruned list (rewritten only where that level prunes,
    // which marks its tangent list unknown); any other list gets none.
    if (&list == &tape_.ssa()) return tape_tangent_ ? &*tape_tangent_ : nullptr;
    Level* owner = owner_of(list, depth);
    if (owner == nullptr) return nullptr;
    return owner->tangent.of(list);
}

Level* Walker::owner_of(const Ssa& list, unsigned depth) {
    for (unsigned k = std::min<unsigned>(depth + 1, kMaxDepth); k-- > 0;) {
        if (&levels_[k].list == &list) return &levels_[k];
    }
    return nullptr;
}

expr::TangentKind Walker::tangent_kind(const Ssa& list, unsigned depth) {
    using K = expr::TangentKind;
    if (&list == &tape_.ssa()) {
        return !tape_tangent_ ? K::None : tape_tangent_->smooth ? K::Smooth : K::Kinked;
    }
    Level* owner = owner_of(list, depth);
    if (owner == nullptr) return K::None;
    return owner->tangent.kind_of(list);
}

void Walker::eval_tangent_lanes(const expr::TangentList& tl, const LaneBox* boxes,
                                const std::array<double, 3>* dirs, std::size_t n,
                                std::vector<UpInterval>& values, std::vector<UpInterval>& slopes,
                                const Level* fold, const expr::TangentList* second,
                                std::vector<UpInterval>* curvatures) {
    if (float_lanes_) {
        eval_tangent_lanes_in(f32_, tl, boxes, dirs, n, values, slopes, fold, second, curvatures);
    } else {
        eval_tangent_lanes_in(d64_, tl, boxes, dirs, n, values, slopes, fold, second, curvatures);
    }
}

template <class L>
void Walker::eval_tangent_lanes_in(LaneFile<L>& file, const expr::TangentList& tl,
                                   const LaneBox* boxes, const std::array<double, 3>* dirs,
                                   std::size_t n, std::vector<UpInterval>& values,
                                   std::vector<UpInterval>& slopes, const Level* fold,
                                   const expr::TangentList* second,
                                   std::vector<UpInterval>* curvatures) {
    // With `second` (second_order_list(tl)), its list is walked: it keeps tl's slots (g and g′)
    // and adds g″ in its derivative slot, into `curvatures`.
    const std::vector<expr::Instr>& walked = second != nullptr ? second->list : tl.list;
    const std::uint32_t slots = second != nullptr ? second->slots : tl.slots;
    if (file.regs.size() < slots) file.regs.resize(slots);
    if (values.size() < n) values.resize(n);
    if (slopes.size() < n) slopes.resize(n);
    if (curvatures != nullptr && curvatures->size() < n) curvatures->resize(n);
    for (std::size_t k0 = 0; k0 < n; k0 += expr::kIntervalLanes) {
        const int m = static_cast<int>(std::min<std::size_t>(expr::kIntervalLanes, n - k0));
        load_lanes(file, boxes + k0, m);
        if (fold != nullptr) load_fixed(file, *fold, m);  // none where the level has no folded list
        // The seeds (both lists' with `second`): each lane's direction, a point (defined),
        // rounded outward.
        const std::uint64_t lanes = m == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << m) - 1;
        for (const expr::TangentList* list : {&tl, second}) {
            if (list == nullptr) continue;
            for (int c = 0; c < 3; ++c) {
                L& seed = file.regs[list->seed[c]];
                for (int k = 0; k < m; ++k) {
                    const double d = dirs[k0 + k][c];
                    expr::set_bounds_upward(seed, k, d, d);
                }
                seed.defined[0] |= lanes;
            }
        }
        expr::run_interval_batch(walked.data(), walked.data() + walked.size(), file.in.data(),
                                 file.regs.data(), m);
        for (int k = 0; k < m; ++k) {
            values[k0 + k] = expr::lane(file.regs[tl.value], k);
            slopes[k0 + k] = expr::lane(file.regs[tl.derivative], k);
            if (curvatures != nullptr) {
                (*curvatures)[k0 + k] = expr::lane(file.regs[second->derivative], k);
            }
        }
    }
}

bool Walker::scan_together(const Rect& r, double a, double b, const Ssa& list,
                           const expr::Tape* tape, Level& level, unsigned depth, const Hull& hull,
                           bool folded_only) {
    const ScanGroup one{r, a, b, &hull};
    return scan_groups(&one, 1, list, tape, level, depth, folded_only) != 0;
}

unsigned Walker::scan_groups(const ScanGroup* groups, int count, const Ssa& list,
                             const expr::Tape* tape, Level& level, unsigned depth,
                             bool folded_only) {
    // The hits of this scan wait for their normals until it returns (a nested scan's own hits
    // until that one returns).
    const DeferNormals defer(*this, list);
    // The rays' segments; none of a group scanned if one of its segments is too long.
    segments_.clear();
    double w_tile = kInf;  // the narrowest piece width (tile pieces: one group)
    unsigned taken = 0;
    for (int g = 0; g < count; ++g) {
        const Rect& r = groups[g].r;
        const double a = groups[g].a, b = groups[g].b;
        const std::size_t mark = segments_.size();
        double w_group = kInf;
        bool short_enough = true;
        for (unsigned j = r.j0; j < r.j0 + r.h && short_enough; ++j) {
            for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
                const Px& p = px(i, j);
                if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
                Ray s = p.ray;
                s.tmin = std::max(a, p.ray.tmin);
                s.tmax = std::min(b, p.ray.tmax);
                const double w = piece_width(s);
                if (!(w > 0 && s.tmax - s.tmin <= kMaxPieces * w)) {
                    short_enough = false;
                    break;
                }
                w_group = std::min(w_group, w);
                segments_.push_back({i, j, s.tmin, s.tmax});
            }
        }
        if (!short_enough) {
            segments_.resize(mark);
            continue;
        }
        w_tile = std::min(w_tile, w_group);
        taken |= 1u << g;
    }
    if (taken == 0) return 0;
    // Scanned: the list its lanes walk, folded to the node's box where that pays (one group).
    if (count == 1) {
        const Hull& hull = *groups[0].hull;
        fold(list, segment_box(hull.olo, hull.ohi, hull.dlo, hull.dhi, groups[0].a, groups[0].b),
             level);
    } else {
        level.folded.list.clear();
        level.folded.fixed.clear();
        level.folded_tangent.forget();
    }
    if (folded_only && level.folded.list.empty()) return 0;
    // Tile pieces: [a, b] cut in pieces of the narrowest width, each one box over all the rays
    // (the hull's), in one batched evaluation. A piece proven free is free on every ray; a ray's
    // first piece not proven free decides it when the piece after it is proven inside (solid:
    // the ray enters {f < 0} in its piece, Hit [p, q]; or at p if the piece itself is inside) or
    // when the pieces either side have strict opposite signs (zero set, f defined and continuous
    // on the piece: Hit [p, q]). Otherwise the ray is scanned alone from that piece on.
    // One node's only (several share no hull; they are scanned together only while the tile
    // pieces do not pay, split_screen()).
    int tiles = 0;
    if (count == 1 && options_.tile_pieces && groups[0].hull->count >= 2 && tile_trial_.attempt()) {
        const Hull& hull = *groups[0].hull;
        const Ray span{{}, {}, groups[0].a, groups[0].b};
        tiles = pieces_of(span, w_tile);
        if (tiles > 2 * kMaxPieces) tiles = 0;
        tile_boxes_.clear();
        for (int k = 0; k < tiles; ++k) {
            const auto [lo, hi] = piece(span, w_tile, k, tiles);
            const auto box = segment_box(hull.olo, hull.ohi, hull.dlo, hull.dhi, lo, hi);
            LaneBox lb;
            for (int c = 0; c < 3; ++c) {
                lb.lo[c] = box[c].lower();
                lb.hi[c] = box[c].upper();
            }
            tile_boxes_.push_back(lb);
            tile_t_[k] = lo;
            tile_t_[k + 1] = hi;
        }
        if (tiles > 0) {
            eval_lanes(list, tile_boxes_.data(), tiles, tile_values_, &level);
            stats.tile_pieces += tiles;
            evals.interval += tiles;
        }
    }

    // Each ray's segment after the tile pieces.
    pieces_.clear();
    level.scanned.clear();
    std::size_t decided = 0;  // rays the tile pieces answered
    std::size_t cleared = 0;  // rays the tile pieces answered or proved free on [a, b]
    int saved = 0;            // pieces of the rays' own that the tile pieces made unnecessary
    for (const Segment& g : segments_) {
        Level::Scanned& z = level.scanned.emplace_back(g.i, g.j, px(g.i, g.j).ray, g.tmin, g.tmax);
        Ray& s = z.s;
        RayResult& res = z.res;
        if (tiles > 0) {
            const int before = pieces_of(s, piece_width(s));
            int k = 0;
            while (k < tiles && tile_t_[k + 1] <= s.tmin) ++k;  // the piece holding s.tmin
            for (; k < tiles && tile_t_[k] < s.tmax; ++k) {
                ++res.evals.interval;
                const Proof pr = proof(tile_values_[k]);
                if (pr == Proof::Excluded) continue;
                const double p = tile_t_[k], q = tile_t_[k + 1];
                const bool next = k + 1 < tiles && s.tmax >= q;  // the ray reaches piece k + 1
                // Its own lambda: calling the `hit` of the decisions below instead, hoisted here,
                // made the colonnade's heightmap 10% slower (measured; code generation).
                const auto hit = [&](double lo, double hi) {
                    res.status = Status::Hit;
                    res.t_lo = lo;
                    res.t_hi = hi;
                    res.t = 0.5 * lo + 0.5 * hi;
                    ++decided;
                };
                if (solid_ && pr == Proof::Inside) {
                    hit(std::max(p, s.tmin), std::max(p, s.tmin));
                } else if (solid_ && next && proof(tile_values_[k + 1]) == Proof::Inside) {
                    hit(std::max(p, s.tmin), q);
                } else if (!solid_ && next && k > 0 && s.tmin <= p && tile_values_[k].defined &&
                           strict_sign(tile_values_[k - 1]) * strict_sign(tile_values_[k + 1]) ==
                               -1) {
                    hit(p, q);  // g(p) and g(q) of strict opposite signs, g continuous between
                }
                s.tmin = std::max(s.tmin, p);  // free before its first piece not proven free
                break;
            }
            if (k == tiles || !(tile_t_[k] < s.tmax)) {
                s.tmin = s.tmax;  // every piece it meets proven free: Miss on [a, b]
            }
            const bool clear = res.status != Status::Miss || !(s.tmin < s.tmax);
            cleared += clear;
            saved += before - (clear ? 0 : pieces_of(s, piece_width(s)));
        }
    }
    stats.tile_decided += decided;
    // A win: the tile pieces answered a ray, left none of the node's rays to scan (the pieces'
    // walks and their points and forms spared), or spared four vectors' worth of pieces. A few
    // pieces spared do not pay: a walk costs about the same for a few lanes fewer
    // (docs/benchmarks.md, session 22).
    tile_trial_.wins +=
        tiles > 0 && (decided > 0 || cleared == segments_.size() || saved >= 4 * kWalkLanes);
    take_segment_forms(list, depth, level);
    // The pieces of every ray not decided yet, as scan() cuts them.
    for (Level::Scanned& z : level.scanned) {
        z.begin = pieces_.size();
        if (z.res.status == Status::Miss && z.s.tmin < z.s.tmax) {
            const double w = piece_width(z.s);
            const int n = pieces_of(z.s, w);
            for (int k = 0; k < n; ++k) {
                const auto [lo, hi] = piece(z.s, w, k, n);
                if (lo < hi) pieces_.push_back({z.i, z.j, lo, hi});
            }
        }
        z.end = pieces_.size();
    }
    // Every piece's enclosure, in one batched evaluation.
    const std::size_t n = pieces_.size();
    if (lanes_.size() < n) lanes_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Piece& c = pieces_[k];
        lanes_[k] = lane_box(px(c.i, c.j).ray, c.p, c.q);
    }
    eval_lanes(list, lanes_.data(), n, piece_values_, &level);
    piece_proof_.resize(n);
    for (std::size_t k = 0; k < n; ++k) piece_proof_[k] = proof(piece_values_[k]);

    // A ray's decision at its first piece k not proven free, as scan() makes it: proven inside
    // (solid): Hit [p, p]; else the points' test — solid: g(q) < 0, zero: g defined and
    // continuous on the piece with g(p), g(q) of strict opposite signs: Hit [p, q]; else
    // undecided (the mean value form and the quarters come next). `point`: the lane of the
    // piece's first point value (q for the solid; p, then q, for the zero set), or none.
    const auto proven_neg = [](const UpInterval& v) { return v.defined && v.upper() < 0; };
    const auto proven_pos = [](const UpInterval& v) { return v.defined && v.lower() > 0; };
    const auto points_for = [&](const UpInterval& e) -> int {  // e: the piece's enclosure
        if (proof(e) == Proof::Inside) return 0;
        return solid_ ? 1 : e.defined ? 2 : 0;
    };
    const auto points_of = [&](std::size_t k) { return points_for(piece_values_[k]); };
    // The decision on a piece [p, q] of enclosure e (not proven free), up to `tmax`.
    const auto decide_piece = [&](RayResult& res, const UpInterval& e, double p, double q,
                                  double tmax, const UpInterval* point) {
        res.status = Status::Unknown;
        res.t_lo = p;
        res.t_hi = tmax;
        if (proof(e) == Proof::Inside) return hit_of(res, p, p);
        const int m = points_for(e);
        res.evals.interval += static_cast<unsigned>(m);
        if (m == 1 && proven_neg(point[0])) return hit_of(res, p, q);
        if (m == 2 && ((proven_neg(point[0]) && proven_pos(point[1])) ||
                       (proven_pos(point[0]) && proven_neg(point[1])))) {
            return hit_of(res, p, q);
        }
    };
    const auto decide = [&](Level::Scanned& z, std::size_t k, const UpInterval* point) {
        const Piece& c = pieces_[k];
        decide_piece(z.res, piece_values_[k], c.p, c.q, z.s.tmax, point);
    };
    const auto add_points_of = [&](std::vector<LaneBox>& boxes, const Ray& ray, const UpInterval& e,
                                   double p, double q) {
        const int m = points_for(e);
        if (m == 2) boxes.push_back(lane_box(ray, p, p));
        if (m >= 1) boxes.push_back(lane_box(ray, q, q));
    };
    const auto add_points = [&](std::vector<LaneBox>& boxes, std::size_t k) {
        const Piece& c = pieces_[k];
        add_points_of(boxes, px(c.i, c.j).ray, piece_values_[k], c.p, c.q);
    };

    // Each ray's first piece not proven free by its enclosure, decided by its points (a second
    // batched evaluation).
    std::vector<std::size_t>& first = first_piece_;  // per ray: the piece it stands at, or n
    std::vector<std::size_t>& at = point_lane_;      // per ray: its first point lane
    const std::size_t rays = level.scanned.size();
    first.assign(rays, n);
    at.assign(rays, 0);
    points_.clear();
    for (std::size_t ray = 0; ray < rays; ++ray) {
        Level::Scanned& z = level.scanned[ray];
        for (std::size_t k = z.begin; k < z.end; ++k) {
            ++z.res.evals.interval;
            if (piece_proof_[k] != Proof::Excluded) {
                first[ray] = k;
                break;
            }
        }
        if (first[ray] == n) continue;  // every piece proven free: Miss
        at[ray] = points_.size();
        add_points(points_, first[ray]);
    }
    if (!points_.empty()) eval_lanes(list, points_.data(), points_.size(), lane_values_, &level);
    std::size_t open = 0;  // rays still undecided
    for (std::size_t ray = 0; ray < rays; ++ray) {
        if (first[ray] == n) continue;
        decide(level.scanned[ray], first[ray], lane_values_.data() + at[ray]);
        open += level.scanned[ray].res.status == Status::Unknown;
    }

    // The undecided rays, where the list has a tangent list (expr/tangent.h): the mean value form
    // g(c) + G′·(P − c) on their piece P = [p, q] and on every later piece that its enclosure
    // does not prove free — G′ ⊇ g′ over the piece and g at its middle c = o + tc·d — with the
    // later pieces' points, all lanes of one walk of the tangent list (its values are the list's,
    // bit for bit). Then each ray goes on from its piece as scan() does: a piece the form proves
    // free is passed, the next one decided by its points or its form. It is what decides a
    // polynomial's pieces near its surface; without it, after_points() tries the form one ray and
    // one piece at a time.
    // A list with kinks: its forms are looser at the kinks' ties, so they are tried while they
    // pay in the root tile (otherwise each ray's form is one Dual walk, piece_mean_value()).
    const expr::TangentKind kind = open > 0 && options_.lane_mean_value
                                       ? lane_tangent_kind(list, depth, level)
                                       : expr::TangentKind::None;
    const bool kinked = kind == expr::TangentKind::Kinked;
    const expr::TangentList* tl =
        kind == expr::TangentKind::Smooth || (kinked && kink_forms_.attempt())
            ? lane_tangent(list, depth, level)
            : nullptr;
    std::size_t forms_tried = 0, forms_proven = 0;
    if (tl != nullptr) {
        form_boxes_.clear();
        dirs_.clear();
        form_of_.assign(n, n);
        // Per piece: its lane (the piece; its centre next; then its points), none if not asked.
        for (std::size_t ray = 0; ray < rays; ++ray) {
            const Level::Scanned& z = level.scanned[ray];
            if (z.res.status != Status::Unknown) continue;
            const Ray& full = px(z.i, z.j).ray;
            for (std::size_t k = first[ray]; k < z.end; ++k) {
                if (piece_proof_[k] != Proof::None) continue;
                const Piece& c = pieces_[k];
                form_of_[k] = form_boxes_.size();
                form_boxes_.push_back(lanes_[k]);
                const double tc = midpoint(UpInterval(c.p, c.q));
                form_boxes_.push_back(lane_box(full, tc, tc));  // holds the point o + tc·d
                if (k != first[ray]) add_points(form_boxes_, k);
            }
            dirs_.resize(form_boxes_.size(), full.d);
        }
        eval_tangent_lanes(*tl, form_boxes_.data(), dirs_.data(), form_boxes_.size(), lane_values_,
                           lane_slopes_, &level);
    }
    // The mean value form on a piece [p, q] of enclosure e from its lanes: G′ (the derivative
    // over the piece) and the value at its middle.
    const auto lane_form = [&](const UpInterval& e, const UpInterval& g1, const UpInterval& m,
                               double p, double q, RayResult& res) {
        const Proof pr = segment_form(e, g1, m, p, q, res);
        if (pr == Proof::Unusable) return Proof::None;
        stats.lane_forms += pr != Proof::None;
        ++forms_tried;
        forms_proven += pr != Proof::None;
        return pr;
    };
    const auto form = [&](std::size_t k, RayResult& res) {
        const std::size_t l = form_of_[k];
        return lane_form(piece_values_[k], lane_slopes_[l], lane_values_[l + 1], pieces_[k].p,
                         pieces_[k].q, res);
    };
    // Each undecided ray from its piece on, as scan() and after_points() go on: the piece's mean
    // value form (from the lanes, or one Dual walk without a tangent list) decides it, or the
    // piece is scanned again in quarters, where a Hit or an Unknown is the answer. A piece proven
    // free passes the ray to its next piece that the lanes' enclosures do not prove free, decided
    // by its points (the lanes', or two point walks), else as this one (a scan afresh from there
    // would evaluate the later pieces again).
    UpInterval points[2];
    if (tl == nullptr && scan_.size() < list.size()) scan_.resize(list.size());
    const auto point = [&](const Ray& ray, double t) {
        expr::detail::run<UpInterval>(list, ray_box(ray, t, t), scan_.data());
        return scan_[list.back().out];
    };
    // Ray z's piece k is free: its next piece not proven free, decided by its points; false when
    // that decides the ray (a Miss past its last piece, or a Hit).
    const auto next = [&](Level::Scanned& z, std::size_t& k) {
        do {
            ++k;
            if (k < z.end) ++z.res.evals.interval;
        } while (k < z.end && piece_proof_[k] == Proof::Excluded);
        if (k == z.end) {
            z.res.status = Status::Miss;
            return false;
        }
        if (tl != nullptr) {
            decide(z, k, lane_values_.data() + form_of_[k] + 2);
        } else {
            const Piece& e = pieces_[k];
            const Ray& full = px(e.i, e.j).ray;
            const int m = points_of(k);
            if (m == 2) points[0] = point(full, e.p);
            if (m >= 1) points[m - 1] = point(full, e.q);
            decide(z, k, points);
        }
        return z.res.status == Status::Unknown;
    };
    // Ray z undecided at its piece k: its forms there and on; true when it waits for the
    // quarters of piece k (its form does not decide it), false when it is decided.
    const auto go_on = [&](Level::Scanned& z, std::size_t& k) {
        for (;;) {
            const Piece& c = pieces_[k];
            const Proof pr =
                tl != nullptr ? form(k, z.res) : piece_mean_value(list, z.s, c.p, c.q, z.res);
            if (pr == Proof::Inside) {
                hit_of(z.res, c.p, c.p);
                return false;
            }
            if (pr == Proof::None) return true;
            if (!next(z, k)) return false;
        }
    };
    waiting_.clear();
    for (std::size_t ray = 0; ray < rays; ++ray) {
        Level::Scanned& z = level.scanned[ray];
        if (z.res.status == Status::Unknown && go_on(z, first[ray])) waiting_.push_back({ray});
    }
    // The quarters of the waiting rays' pieces, in rounds: each quarter one lane of a batched
    // evaluation, then the points of each ray's first quarter not proven free another; each
    // ray's quarters decided as scan() decides them (the same enclosures, bit for bit), with
    // after_points() on a quarter that they leave undecided.
    while (!waiting_.empty()) {
        stats.quarter_pieces += waiting_.size();
        quarter_boxes_.clear();
        quarter_t_.clear();
        for (Waiting& v : waiting_) {
            const Level::Scanned& z = level.scanned[v.ray];
            const Piece& c = pieces_[first[v.ray]];
            const Ray& full = px(z.i, z.j).ray;
            v.seg = z.s;
            v.seg.tmin = c.p;
            v.seg.tmax = c.q;
            const double w = 0.25 * (c.q - c.p);
            const int m = pieces_of(v.seg, w);
            v.box = quarter_boxes_.size();
            for (int j = 0; j < m; ++j) {
                const auto [lo, hi] = piece(v.seg, w, j, m);
                if (!(lo < hi)) continue;
                quarter_boxes_.push_back(lane_box(full, lo, hi));
                quarter_t_.push_back({lo, hi});
            }
            v.count = quarter_boxes_.size() - v.box;
        }
        eval_lanes(list, quarter_boxes_.data(), quarter_boxes_.size(), quarter_values_, &level);
        points_.clear();
        quarter_dirs_.clear();
        for (Waiting& v : waiting_) {
            const Level::Scanned& z = level.scanned[v.ray];
            const Ray& full = px(z.i, z.j).ray;
            v.res = RayResult{};
            v.res.status = Status::Miss;
            v.first = v.count;
            for (std::size_t j = 0; j < v.count; ++j) {
                ++v.res.evals.interval;
                if (proof(quarter_values_[v.box + j]) != Proof::Excluded) {
                    v.first = j;
                    break;
                }
            }
            if (v.first == v.count) continue;
            const UpInterval& e = quarter_values_[v.box + v.first];
            const auto [lo, hi] = quarter_t_[v.box + v.first];
            v.points = points_.size();
            v.m = points_for(e);
            add_points_of(points_, full, e, lo, hi);
            if (tl != nullptr && v.m >= 1) {  // the quarter's form: its box, then its centre
                points_.push_back(quarter_boxes_[v.box + v.first]);
                const double tc = midpoint(UpInterval(lo, hi));
                points_.push_back(lane_box(full, tc, tc));
            }
            quarter_dirs_.resize(points_.size(), full.d);
        }
        if (!points_.empty() && tl != nullptr) {
            eval_tangent_lanes(*tl, points_.data(), quarter_dirs_.data(), points_.size(),
                               quarter_points_, quarter_slopes_, &level);
        } else if (!points_.empty()) {
            eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
        }
        still_.clear();
        for (Waiting& v : waiting_) {
            Level::Scanned& z = level.scanned[v.ray];
            std::size_t& k = first[v.ray];
            if (v.count == 0) continue;  // no quarter to look at: Unknown from the piece on
            if (v.first < v.count) {
                const UpInterval& e = quarter_values_[v.box + v.first];
                const auto [lo, hi] = quarter_t_[v.box + v.first];
                RayResult& res = v.res;
                decide_piece(res, e, lo, hi, v.seg.tmax, quarter_points_.data() + v.points);
                if (res.status == Status::Unknown && tl != nullptr && v.m >= 1) {
                    // The quarter's form lanes follow its points (taken where it has points).
                    const std::size_t l = v.points + static_cast<std::size_t>(v.m);
                    const Proof pr =
                        lane_form(e, quarter_slopes_[l], quarter_points_[l + 1], lo, hi, res);
                    res = after_points(list, v.seg, lo, hi, res, 1, &pr);
                } else if (res.status == Status::Unknown) {
                    res = after_points(list, v.seg, lo, hi, res, 1);
                }
                res.evals += z.res.evals;
                if (res.status != Status::Miss) {
                    if (res.status == Status::Unknown) res.t_hi = z.s.tmax;
                    z.res = res;
                    continue;
                }
                z.res.evals = res.evals;
            } else {
                z.res.evals += v.res.evals;
            }
            // Piece k proven free in quarters: on to the next one.
            if (next(z, k) && go_on(z, k)) still_.push_back(v);
        }
        waiting_.swap(still_);
    }
    if (kinked && tl != nullptr) kink_forms_.wins += 2 * forms_proven >= forms_tried;
    // Settled in pixel order; a split recurses into deeper levels, which do not touch this one.
    for (std::size_t ray = 0; ray < level.scanned.size(); ++ray) {
        const Level::Scanned& z = level.scanned[ray];  // settle() recurses into deeper levels only
        stats.together += z.res.status != Status::Unknown;
        settle(z.i, z.j, z.s, z.res, true, list, tape, level, depth);
    }
    return taken;
}

void Walker::take_segment_forms(const Ssa& list, unsigned depth, Level& level) {
    // Each open ray's whole segment S gets the mean value form in t, g(c) + G′·(S − c): G′ ⊇ g′
    // along the ray over S (a lane of one walk of the tangent list, which also gives g's plain
    // enclosure over S) and g at its middle c (a lane of one walk of the list). A segment it
    // proves free needs no pieces: rays that run beside the surface (grazing it, or between close
    // sheets) are proven so, where their pieces' plain enclosures are as wide as the box a piece
    // spans. Short lists keep their pieces: there a walk's cost is mostly its own, not its lanes'.
    // At a kink G′ encloses Clarke's derivative: the form holds (Lebourg's mean value theorem),
    // and a G′ of one strict sign still makes g strictly monotone. Lists with kinks get the forms
    // only where folded: the bear's folded lists pay (−9%), the molecule's unfolded ones of
    // thousands of instructions (+11%) and the colonnade's short ones (+4%) do not.
    if (!options_.segment_forms || list.size() < kSegmentFormList) return;
    const expr::TangentKind kind = lane_tangent_kind(list, depth, level);
    if (kind == expr::TangentKind::None ||
        (kind == expr::TangentKind::Kinked && level.folded.list.empty())) {
        return;
    }
    const expr::TangentList& tl = *lane_tangent(list, depth, level);
    form_boxes_.clear();
    points_.clear();
    dirs_.clear();
    form_of_.clear();
    monotone_.clear();
    second_rays_.clear();
    for (std::size_t ray = 0; ray < level.scanned.size(); ++ray) {
        const Level::Scanned& z = level.scanned[ray];
        // A form costs two lanes (one of the tangent list, one of the list) in walks that run
        // anyway; a segment of one piece keeps its piece.
        if (z.res.status != Status::Miss || !(z.s.tmin < z.s.tmax) ||
            fewer_pieces(z.s, piece_width(z.s), kSegmentFormPieces)) {
            continue;
        }
        const Ray& full = px(z.i, z.j).ray;
        const double tc = midpoint(UpInterval(z.s.tmin, z.s.tmax));
        form_of_.push_back(ray);
        form_boxes_.push_back(lane_box(full, z.s.tmin, z.s.tmax));
        points_.push_back(lane_box(full, tc, tc));
        dirs_.push_back(full.d);
    }
    // On a folded list, where the segments' plain enclosures prove enough of them free (3 in 10
    // in the root tile so far, from the forms' own value lanes until then), those enclosures
    // come first, one walk of the list, and only the segments they leave walk the tangent list
    // (whose value lanes are the same enclosures, bit for bit) and the list at their middles:
    // the same decisions, fewer lanes. A walk of the tangent list and one of the list cost about
    // three of the list. The bear's heightmap: 54% of its segments so, the form itself 0.5%.
    // Short unfolded lists (the particles' 80 instructions) took up to 19% longer: a walk's
    // own cost is then most of it.
    const std::size_t tried = form_of_.size();
    const bool plain_first = options_.segment_enclosures_first && !level.folded.list.empty() &&
                             plain_tried_ > 0 && 10 * plain_free_ >= 3 * plain_tried_;
    plain_tried_ += tried;
    if (tried > 0 && plain_first) {
        eval_lanes(list, form_boxes_.data(), tried, lane_values_, &level);
        std::size_t rest = 0;
        for (std::size_t l = 0; l < tried; ++l) {
            Level::Scanned& z = level.scanned[form_of_[l]];
            ++z.res.evals.interval;
            if (proof(lane_values_[l]) == Proof::Excluded) {
                ++plain_free_;
                prove_free(z);
                continue;
            }
            form_of_[rest] = form_of_[l];
            form_boxes_[rest] = form_boxes_[l];
            points_[rest] = points_[l];
            dirs_[rest] = dirs_[l];
            ++rest;
        }
        form_of_.resize(rest);
        form_boxes_.resize(rest);
        points_.resize(rest);
        dirs_.resize(rest);
    }
    if (!form_of_.empty()) {
        // The middles' values: lanes of the tangent list's walk where they fit in its vector
        // (its value lanes are the list's, bit for bit: a walk of the list spared), else a walk
        // of the list.
        const std::size_t n = form_of_.size();
        if (options_.middles_in_forms && 2 * n <= kWalkLanes) {
            form_boxes_.insert(form_boxes_.end(), points_.begin(), points_.end());
            dirs_.resize(2 * n);
            std::copy_n(dirs_.begin(), n, dirs_.begin() + static_cast<std::ptrdiff_t>(n));
            eval_tangent_lanes(tl, form_boxes_.data(), dirs_.data(), 2 * n, lane_values_,
                               lane_slopes_, &level);
            if (quarter_points_.size() < n) quarter_points_.resize(n);
            std::copy_n(lane_values_.begin() + static_cast<std::ptrdiff_t>(n), n,
                        quarter_points_.begin());
        } else {
            eval_tangent_lanes(tl, form_boxes_.data(), dirs_.data(), n, lane_values_, lane_slopes_,
                               &level);
            eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
        }
        for (std::size_t l = 0; l < form_of_.size(); ++l) {
            Level::Scanned& z = level.scanned[form_of_[l]];
            const UpInterval& e = lane_values_[l];
            const UpInterval& g1 = lane_slopes_[l];
            ++z.res.evals.interval;
            const bool plain = proof(e) == Proof::Excluded;  // only without plain_first
            plain_free_ += plain;
            if (plain || segment_form(e, g1, quarter_points_[l], z.s.tmin, z.s.tmax, z.res) ==
                             Proof::Excluded) {
                prove_free(z);
            } else if (options_.monotone_segments && e.defined && finite(g1) &&
                       (g1.lower() > 0 || g1.upper() < 0)) {
                // g′ (Clarke's at kinks) keeps one strict sign: g is strictly monotone (on a
                // folded list h(·, s) is, for each value s of the fixed inputs, which is what
                // decide_monotone() needs: docs/theory/coherent.md).
                monotone_.push_back({form_of_[l], z.s.tmin, z.s.tmax, 0, g1.upper() < 0,
                                     midpoint(UpInterval(z.s.tmin, z.s.tmax)), quarter_points_[l],
                                     false, g1});
            } else if (options_.clip_forms && e.defined && finite(g1) &&
                       !quarter_points_[l].is_empty() && quarter_points_[l].defined) {
                // The form as a line in t narrows the segment its pieces cover.
                const LinearForm lin{quarter_points_[l], g1,
                                     midpoint(UpInterval(z.s.tmin, z.s.tmax)), true};
                double lo = z.s.tmin, hi = z.s.tmax;
                clip_to_line(lin, lo, hi);
                stats.clipped += lo != z.s.tmin || hi != z.s.tmax;
                if (!(lo <= hi)) {
                    prove_free(z);
                } else {
                    z.s.tmin = lo;
                    z.s.tmax = hi;
                    // The second-order form can prove the segment free only where g at its
                    // middle is proven away from 0 on the free side.
                    const UpInterval& gc = quarter_points_[l];
                    if (solid_ ? gc.lower() > 0 : strict_sign(gc) != 0) {
                        second_rays_.push_back(form_of_[l]);
                    }
                }
            }
        }
        try_second_order(list, level);
        decide_monotone(list, level);
    }
}

void Walker::try_second_order(const Ssa& list, Level& level) {
    // Segments whose form neither proved them free nor found g monotone (G′ holds 0: the ray
    // runs beside the surface, or through it) get the second-order form of g(t) = f(o + t·d)
    // about the middle c of S = [a, b]: g(t) ∈ g(c) + g′(c)·(t − c) + ½·G″·(t − c)² (Taylor's
    // theorem with Lagrange's remainder; g is C² where the smooth list is defined, G″ ⊇ g″ over
    // S finite). Its error is quadratic in the width and g′(c) is a point's, so where G′ over S
    // is wide (the dependency of a polynomial's interval evaluation) but g stays away from 0 — a
    // ray that passes near the surface without meeting it — it proves S free where the
    // first-order form needed pieces. Where G″ keeps one strict sign, the model's extreme over
    // all t and every curvature k in G″ is g(c) − g′(c)²/(2·k) at the bound of G″ nearest 0, on
    // the side G″ points away from: the form is that tight wherever the ray's closest approach
    // lies in S. One walk of the second-order list, two lanes a segment (its box: G″; its
    // middle: g(c) and g′(c)).
    if (second_rays_.empty() || !tape_second_ || &list != &tape_.ssa() ||
        !level.folded.list.empty() || !second_trial_.attempt()) {
        return;
    }
    const std::size_t n = second_rays_.size();
    second_boxes_.clear();
    second_dirs_.clear();
    for (const std::size_t ray : second_rays_) {
        const Level::Scanned& z = level.scanned[ray];
        const Ray& full = px(z.i, z.j).ray;
        const double tc = midpoint(UpInterval(z.s.tmin, z.s.tmax));
        second_boxes_.push_back(lane_box(full, z.s.tmin, z.s.tmax));
        second_boxes_.push_back(lane_box(full, tc, tc));
        second_dirs_.push_back(full.d);
        second_dirs_.push_back(full.d);
    }
    eval_tangent_lanes(*tape_tangent_, second_boxes_.data(), second_dirs_.data(), 2 * n, second_g_,
                       second_g1_, nullptr, &*tape_second_, &second_g2_);
    std::size_t proven = 0;
    for (std::size_t k = 0; k < n; ++k) {
        Level::Scanned& z = level.scanned[second_rays_[k]];
        z.res.evals.gradient += 1;
        const UpInterval &e = second_g_[2 * k], &g1 = second_g1_[2 * k], &g2 = second_g2_[2 * k];
        if (!e.defined || !g1.defined || !g2.defined || !finite(g1) || !finite(g2)) continue;
        const UpInterval &v = second_g_[2 * k + 1], &d = second_g1_[2 * k + 1];
        if (!v.defined || !finite(v) || !finite(d)) continue;
        const double c = midpoint(UpInterval(z.s.tmin, z.s.tmax));
        const UpInterval s = UpInterval(z.s.tmin, z.s.tmax) - UpInterval(c);
        const UpInterval form = v + d * s + UpInterval(0.5) * g2 * square(s);
        double lo = form.lower(), hi = form.upper();
        if (g2.lower() > 0) {
            lo = std::max(lo, (v - square(d) / (UpInterval(2.0) * UpInterval(g2.lower()))).lower());
        } else if (g2.upper() < 0) {
            hi = std::min(hi, (v - square(d) / (UpInterval(2.0) * UpInterval(g2.upper()))).upper());
        }
        if (!(lo <= hi)) continue;
        if (proof(UpInterval(lo, hi)) == Proof::Excluded) {
            ++proven;
            ++stats.second_order;
            prove_free(z);
        }
    }
    second_trial_.wins += proven == n;
}

void Walker::decide_monotone(const Ssa& list, Level& level) {
    // g at the middle tc (the form's lane) and, where that does not decide, at one end (one
    // batched walk; below). Points of one strict sign (the solid: both ≥ 0) prove the part
    // between them free; points of strict opposite signs (the zero set) hold a zero (exactly one
    // unless the list is folded), bracketed by halving [lo, hi] at points (a walk per round)
    // until it is as deep as a piece: Hit [lo, hi], with none before lo. The solid's g
    // decreasing from g(lo) ≥ 0 to g(hi) < 0 enters once, bracketed alike. A midpoint whose side
    // is not proven ends the halving: the ray is scanned in pieces from lo.
    // With newton_brackets, g's value at a point c also gives the interval Newton step
    // c − g(c)/G′, which holds every zero of g on the segment (G′ ⊇ g′ there, of one strict
    // sign; docs/theory/coherent.md): the bracket is narrowed to it, and where the step from tc
    // ends inside the segment, g has crossed 0 by its far end, so it brackets the zero without
    // the end's point. Near a simple zero the step is a few ulps wide where g(c) is small.
    if (monotone_.empty()) return;
    // The side of a value: the solid's ≥ 0 (1) or < 0 (−1), the zero set's strict sign; 0: not
    // proven.
    const auto side = [&](const UpInterval& v) {
        if (!solid_) return strict_sign(v);
        return !v.defined ? 0 : v.lower() >= 0 ? 1 : v.upper() < 0 ? -1 : 0;
    };
    const bool newton = options_.newton_brackets;
    // The Newton step from c, empty where g(c) is not proven defined and bounded.
    const auto step = [&](const Monotone& mo, double c, const UpInterval& gc) {
        if (!newton || !gc.defined || !finite(gc)) return UpInterval::empty();
        return UpInterval(c) - gc / mo.slope;
    };
    // [lo, hi] narrowed to the step n: every zero lies in n. The solid's g ≤ 0 at n's upper end
    // (past every zero), so g < 0 just after it (g strictly decreasing): hi is the next double.
    const auto narrow = [&](Monotone& mo, const UpInterval& n) {
        if (n.is_empty()) return;
        mo.lo = std::max(mo.lo, n.lower());
        const double up = solid_ ? std::nextafter(n.upper(), kInf) : n.upper();
        mo.hi = std::min(mo.hi, up);
    };
    // g at the middle tc is known. Where its side is proven, g moves away from g(tc) towards one
    // end (the zero set: decreasing from > 0 or increasing from < 0 moves towards 0 after tc; the
    // solid decreasing from ≥ 0 likewise), so the other half has g(tc)'s side, and the end on
    // the zero's side either has that side too (free) or the other one (a bracket half as deep).
    // The solid increasing: g(a) is its least value. Where g(tc)'s side is not proven (none of
    // the gallery's segments), the zero lies near tc: the ray is scanned in pieces.
    // The step from tc narrows that half to where a zero may be; a step that misses it proves
    // the half free of zeros (free where g(tc)'s side is: the solid's g < 0 there is left to
    // its pieces). A step whose far end lies inside the segment brackets the zero by itself:
    // g there has crossed 0 (the mean value theorem with G′'s bound nearest 0), no end point.
    std::size_t open = 0;
    ready_.clear();
    points_.clear();
    for (Monotone& mo : monotone_) {
        const int sc = side(mo.centre);
        if (sc == 0) continue;
        Level::Scanned& z = level.scanned[mo.ray];
        mo.sign = sc;
        mo.high = mo.decreasing ? sc == 1 : !solid_ && sc == -1;
        mo.bracket = !solid_ || mo.decreasing;
        mo.step_lo = mo.high ? mo.tc : mo.lo;
        mo.step_hi = mo.high ? mo.hi : mo.tc;
        if (mo.bracket) {
            const UpInterval n = step(mo, mo.tc, mo.centre);
            Monotone half = mo;
            half.lo = mo.step_lo;
            half.hi = mo.step_hi;
            narrow(half, n);
            if (!(half.lo <= half.hi)) {
                if (!solid_ || sc == 1) prove_free(z);
                continue;  // the solid's g < 0 on [a, tc]: its pieces
            }
            mo.step_lo = half.lo;
            mo.step_hi = half.hi;
            if (!n.is_empty() && (mo.high ? n.upper() < mo.hi : n.lower() > mo.lo)) {
                half.sign = mo.high ? sc : -sc;
                ready_.push_back(half);
                continue;
            }
        }
        const double end = mo.high ? mo.hi : mo.lo;
        points_.push_back(lane_box(px(z.i, z.j).ray, end, end));
        monotone_[open++] = mo;
    }
    monotone_.resize(open);
    if (open > 0) eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
    open = 0;
    for (std::size_t k = 0; k < monotone_.size(); ++k) {
        Monotone& mo = monotone_[k];
        Level::Scanned& z = level.scanned[mo.ray];
        const int sc = mo.sign, s_end = side(quarter_points_[k]);
        ++z.res.evals.interval;
        bool free = false, bracket = false;
        if (!mo.bracket) {
            free = s_end == 1;  // the solid increasing: g(a) ≥ 0, its least value
        } else if (s_end == sc) {
            free = !solid_ || sc == 1;  // the solid's g < 0 at both: it entered at a
        } else if (s_end == -sc) {
            bracket = true;
            // The half after the middle (g(tc) keeps its side on [a, tc]), else the one before
            // it, as far as the step leaves it.
            mo.lo = mo.step_lo;
            mo.hi = mo.step_hi;
            if (!mo.high) mo.sign = s_end;
        } else if (mo.high) {
            z.s.tmin = mo.step_lo;  // free before the step's part: its pieces from there
        }
        if (free) {
            prove_free(z);
            continue;
        }
        if (!bracket) continue;
        monotone_[open++] = mo;
    }
    monotone_.resize(open);
    monotone_.insert(monotone_.end(), ready_.begin(), ready_.end());
    stats.monotone_segments += monotone_.size();
    stats.newton_brackets += ready_.size();
    while (!monotone_.empty()) {
        // Halving: the brackets deeper than a piece get their midpoints.
        points_.clear();
        open = 0;
        for (const Monotone& mo : monotone_) {
            Level::Scanned& z = level.scanned[mo.ray];
            const double mid = 0.5 * mo.lo + 0.5 * mo.hi;
            if (mo.hi - mo.lo <= piece_width(z.s) || !(mo.lo < mid && mid < mo.hi)) {
                hit_of(z.res, mo.lo, mo.hi);  // one zero in [lo, hi], none before
                continue;
            }
            points_.push_back(lane_box(px(z.i, z.j).ray, mid, mid));
            monotone_[open++] = mo;
        }
        monotone_.resize(open);
        if (open == 0) break;
        eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
        open = 0;
        for (std::size_t k = 0; k < monotone_.size(); ++k) {
            Monotone& mo = monotone_[k];
            Level::Scanned& z = level.scanned[mo.ray];
            const double mid = 0.5 * mo.lo + 0.5 * mo.hi;
            ++z.res.evals.interval;
            // The solid keeps g(lo) ≥ 0 (so g ≥ 0 on [a, lo]) and g < 0 at hi.
            const int sm = side(quarter_points_[k]);
            if (sm == mo.sign) {
                mo.lo = mid;
            } else if (sm == -mo.sign) {
                mo.hi = mid;
            }
            const double width = mo.hi - mo.lo, lo = mo.lo;
            narrow(mo, step(mo, mid, quarter_points_[k]));
            // A side not proven and a step that leaves more than half: its pieces from lo
            // (free before it). (A step that misses the bracket cannot be, as the bracket holds a
            // zero; were it to, the pieces from lo would answer.)
            if (!(mo.lo <= mo.hi)) {
                z.s.tmin = lo;
                continue;
            }
            if (sm == 0 && !(mo.hi - mo.lo <= 0.5 * width)) {
                z.s.tmin = mo.lo;
                continue;
            }
            monotone_[open++] = mo;
        }
        monotone_.resize(open);
    }
}

void Walker::inside(const Rect& r, double a, double b, const Ssa& list) {
    const DeferNormals defer(*this, list);  // the box's hits, a walk of lanes per 16
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
            Px& p = px(i, j);
            if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
            // The point at t lies in the box, where f < 0 is proven; g ≥ 0 on [tmin, t) by the
            // walk's invariant.
            const double t = std::max(a, p.ray.tmin);
            RayResult res;
            res.status = Status::Hit;
            res.t_lo = res.t_hi = res.t = t;
            answer(i, j, p, res, list, a, b);
        }
    }
}

void Walker::spend(unsigned i, unsigned j, const EvalCounts& e) {
    evals += e;
    mine_.evals[slot(i, j)] += e.total();
    if (results_ != nullptr) (*results_)[std::size_t{j} * ans_.width + i].evals += e;
}

void Walker::answer(unsigned i, unsigned j, Px& p, const RayResult& res, const Ssa& list, double a,
                    double b) {
    assert(p.open);  // answered once
    p.open = false;
    Block& block = block_of(i, j);
    block.stale = true;
    --block.open;
    ++answered_;
    evals += res.evals;
    const Ray& ray = p.ray;
    const std::size_t k = slot(i, j);
    mine_.status[k] = res.status;
    mine_.evals[k] += res.evals.total();
    mine_.t[k] = res.t;
    if (results_ != nullptr) {
        RayResult& out = (*results_)[std::size_t{j} * ans_.width + i];
        const EvalCounts before = out.evals;  // of the segments this ray was proven free on
        out = res;
        out.evals += before;
    }
    if (res.status != Status::Hit) return;
    const bool on_list = a <= res.t && res.t <= b;
    if (on_list && &list == defer_list_) {
        if (pending_ > 0 && pending_list_ != &list) flush_normals();
        pending_list_ = &list;
        pending_px_[pending_] = k;
        pending_t_[pending_] = res.t;
        pending_ray_[pending_] = &ray;  // the root tile's pixel
        if (++pending_ == expr::kDualLanes) flush_normals();
        return;
    }
    NearestInUpward env;  // as render_3d computes the normal (the walk holds its upward scope)
    const Vec3 q = point_at(ray, res.t);
    Dual<double, 3> g;
    if (on_list && list.size() < tape_.size()) {
        // The pruned list, much shorter than the tape (a tenth on Fidget's colonnade).
        g = list_gradient(list, q);
    } else {
        g = expr::gradient(tape_, q);
    }
    set_normal(k, {g.v[0], g.v[1], g.v[2]}, ray.d);
}

Dual<double, 3> Walker::list_gradient(const Ssa& list, const Vec3& q) {
    using D = Dual<double, 3>;
    if (grad_.size() < list.size()) grad_.resize(list.size());
    expr::detail::run<D>(list, {D::variable(q[0], 0), D::variable(q[1], 1), D::variable(q[2], 2)},
                         grad_.data());
    return grad_[list.back().out];
}

void Walker::set_normal(std::size_t k, const Vec3& g, const Vec3& d) {  // in round-to-nearest
    Vec3 n = normalize(g);
    if (dot(n, d) > 0) n = {-n[0], -n[1], -n[2]};
    mine_.normal[k] = {static_cast<float>(n[0]), static_cast<float>(n[1]),
                       static_cast<float>(n[2])};
}

void Walker::flush_normals() {
    if (pending_ == 0) return;
    const Ssa& list = *pending_list_;
    NearestInUpward env;  // as answer() computes a normal, its normalisation included
    for (int k = 0; k < pending_; ++k) {
        pending_q_[k] = point_at(*pending_ray_[k], pending_t_[k]);
    }
    if (pending_ < kFewNormals) {
        for (int k = 0; k < pending_; ++k) {
            const Dual<double, 3> g = list_gradient(list, pending_q_[k]);
            set_normal(pending_px_[k], {g.v[0], g.v[1], g.v[2]}, pending_ray_[k]->d);
        }
    } else {
        if (dual_regs_.size() < list.size()) dual_regs_.resize(list.size());
        expr::run_dual_batch(list.data(), list.data() + list.size(), pending_q_, pending_,
                             dual_regs_.data());
        const expr::DualLanes& f = dual_regs_[list.back().out];
        for (int k = 0; k < pending_; ++k) {
            set_normal(pending_px_[k], {f.g[0][k], f.g[1][k], f.g[2][k]}, pending_ray_[k]->d);
        }
    }
    pending_ = 0;
}

}  // namespace

PixelRays::PixelRays(const CoherentOptions& options)
    : projection_(options.projection), bounds_(options.render.bounds) {
    const RenderOptions& r = options.render;
    if (r.width == 0 || r.height == 0) throw std::invalid_argument("render: empty image size");
    NearestScope env;
    if (projection_ == Projection::List) {
        throw std::invalid_argument("render: a ray list needs its rays (bundle_rays)");
    }
    if (projection_ == Projection::Pinhole) {
        angular_ = true;
        frame_.emplace(r.camera, r.width, r.height);
        pitch_ = std::tan(r.camera.fov_degrees * (M_PI / 360.0)) / (0.5 * r.height);
        return;
    }
    for (int c = 0; c < 3; ++c) {
        if (!(std::isfinite(bounds_[c][0]) && std::isfinite(bounds_[c][1]) &&
              bounds_[c][0] < bounds_[c][1])) {
            throw std::invalid_argument("ortho camera: the bounds must be finite with lo < hi");
        }
    }
    dx_ = (bounds_[0][1] - bounds_[0][0]) / r.width;
    dy_ = (bounds_[1][1] - bounds_[1][0]) / r.height;
    // One ulp up covers the rounding of the difference: o + tmax·d reaches z0.
    tmax_ = std::nextafter(bounds_[2][1] - bounds_[2][0], kInf);
    pitch_ = std::max(dx_, dy_);
}

PixelRays::PixelRays(std::span<const Ray> rays, unsigned width, unsigned height,
                     std::vector<std::uint32_t> cells, double pitch, bool angular)
    : projection_(Projection::List),
      angular_(angular),
      list_(rays),
      cells_(std::move(cells)),
      width_(width),
      pitch_(pitch) {
    if (width == 0 || height == 0 || cells_.size() != std::size_t{width} * height) {
        throw std::invalid_argument("ray bundle: the grid does not match its size");
    }
}

bool PixelRays::ray(unsigned i, unsigned j, Ray& ray) const {
    if (projection_ == Projection::List) return ray_in_scope(i, j, ray);
    NearestScope env;
    return ray_in_scope(i, j, ray);
}

bool PixelRays::ray_in_scope(unsigned i, unsigned j, Ray& ray) const {
    if (projection_ == Projection::List) {
        const std::uint32_t k = cells_[std::size_t{j} * width_ + i];
        if (k == kNoRay) return false;
        ray = list_[k];
        return true;
    }
    if (projection_ == Projection::Pinhole) {
        ray = frame_->ray(i + 0.5, j + 0.5);
        return clip_ray(ray, bounds_);
    }
    ray.o = {bounds_[0][0] + (i + 0.5) * dx_, bounds_[1][1] - (j + 0.5) * dy_, bounds_[2][1]};
    ray.d = {0, 0, -1};
    ray.tmin = 0;
    ray.tmax = tmax_;
    return true;
}

void PixelRays::row_in_scope(unsigned i0, unsigned j, unsigned n, Ray* rays, bool* in) const {
    if (projection_ == Projection::Pinhole) {
        frame_->clipped_row(i0, j, n, bounds_, rays, in);
        return;
    }
    for (unsigned k = 0; k < n; ++k) in[k] = ray_in_scope(i0 + k, j, rays[k]);
}

RenderResult render_3d_coherent(const expr::Tape& tape, const CoherentOptions& options,
                                CoherentStats* stats, std::vector<RayResult>* results) {
    return render_3d_coherent(tape, options, PixelRays(options), stats, results);
}

RenderResult render_3d_coherent(const expr::Tape& tape, const CoherentOptions& options,
                                const PixelRays& rays, CoherentStats* stats,
                                std::vector<RayResult>* results) {
    if (options.render.width == 0 || options.render.height == 0) {
        throw std::invalid_argument("render: empty image size");
    }
    if (options.root_tile == 0) throw std::invalid_argument("render: root tile side must be >= 1");
    const auto start = std::chrono::steady_clock::now();
    RenderResult result;
    PixelAnswers& ans = result.answers;
    ans.width = options.render.width;
    ans.height = options.render.height;
    const std::size_t pixels = std::size_t{ans.width} * ans.height;
    const Aov aov = options.render.aov;
    const bool colour_tiles = aov_is_local(aov);
    // Unwritten here: each root tile's worker writes its pixels' defaults (Walker::tile), so the
    // pages are first touched in the workers (a 512² image's 7.6 MB: 2.5 ms on one thread). Not
    // at all where the caller wants the image alone and each tile is coloured from its own.
    const bool keep = options.render.answers || !colour_tiles;
    if (keep) {
        ans.status.resize(pixels, boost::container::default_init);
        ans.t.resize(pixels, boost::container::default_init);
        ans.evals.resize(pixels, boost::container::default_init);
        ans.normal.resize(pixels, boost::container::default_init);
    }
    if (results != nullptr) {
        RayResult miss;
        miss.status = Status::Miss;
        results->assign(pixels, miss);
    }

    const unsigned side = options.root_tile;
    const unsigned tiles_x = (ans.width + side - 1) / side;
    const unsigned tiles_y = (ans.height + side - 1) / side;
    const std::size_t tiles = std::size_t{tiles_x} * tiles_y;
    const unsigned workers = static_cast<unsigned>(std::clamp<std::size_t>(
        options.render.threads > 0 ? options.render.threads : std::thread::hardware_concurrency(),
        1, std::max<std::size_t>(tiles, 1)));
    std::atomic<std::size_t> next{0};
    std::vector<CoherentStats> walk_stats(workers);
    std::vector<EvalCounts> sums(workers);
    std::vector<RenderStats> counts(workers);
    // A pixel's colour in a local AOV is its own answer's: each worker colours its tiles as it
    // answers them (while they are in its cache) instead of a pass over the image afterwards.
    // (For a local AOV the scale is the light alone: the answers, not written yet, are not read.)
    const AovScale scale = colour_tiles ? aov_scale(ans, aov, options.render.light) : AovScale{};
    if (colour_tiles)
        result.image = RgbImage(ans.width, ans.height, boost::container::default_init);
    // The tile's pixels counted (by the walker: `counted`) and coloured once the walk has
    // answered them, from the image's answers or the tile's own (`mine`). A tile answered without
    // its rays (every pixel a Miss with no evaluation, so each row's colour is its first pixel's):
    // its rows filled with that colour.
    const auto finish = [&](const Rect& r, RenderStats& c, bool empty, const RenderStats& counted,
                            const PixelAnswers& mine) {
        c.count_pixels(counted);
        if (!colour_tiles) return;
        const auto span = [&](unsigned j, unsigned i0, unsigned i1) {
            if (keep) {
                colorize_span(ans, aov, scale, j, i0, i1, result.image);
            } else {
                colorize_span(mine, aov, scale, j - r.j0, i0 - r.i0, i1 - r.i0, result.image, r.i0,
                              r.j0);
            }
        };
        if (empty) {
            for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
                span(j, r.i0, r.i0 + 1);
                const std::uint8_t* first = result.image.at(r.i0, j);
                for (unsigned i = r.i0 + 1; i < r.i0 + r.w; ++i) {
                    result.image.set(i, j, first[0], first[1], first[2]);
                }
            }
            return;
        }
        for (unsigned j = r.j0; j < r.j0 + r.h; ++j) span(j, r.i0, r.i0 + r.w);
    };
    WorkProgress* progress = options.render.progress;
    if (progress) progress->total.store(tiles, std::memory_order_relaxed);

    // One worker per thread (the library's one way of threads, tracers/parallel.h), each with its
    // walker; root tiles are taken in order.
    run_workers(workers, [&](unsigned w) {
        try {
            Walker walker(tape, options, rays, ans, results);
            for (;;) {
                const std::size_t t = next.fetch_add(1, std::memory_order_relaxed);
                if (t >= tiles) break;
                const unsigned i0 = static_cast<unsigned>(t % tiles_x) * side;
                const unsigned j0 = static_cast<unsigned>(t / tiles_x) * side;
                const Rect r{i0, j0, std::min(side, ans.width - i0),
                             std::min(side, ans.height - j0)};
                const bool empty = walker.tile(r);
                finish(r, counts[w], empty, walker.tile_counts, walker.tile_answers());
                if (progress) progress->done.fetch_add(1, std::memory_order_relaxed);
            }
            walk_stats[w] = walker.stats;
            sums[w] = walker.evals;
        } catch (...) {
            next.store(tiles);  // the others stop at their next tile
            throw;
        }
    });

    RenderStats& st = result.stats;
    CoherentStats total;
    total.tape_length = tape.size();
    for (unsigned w = 0; w < workers; ++w) {
        st.evals += sums[w];
        st.count_pixels(counts[w]);
        const CoherentStats& s = walk_stats[w];
        total.box_evals += s.box_evals;
        total.box_instructions += s.box_instructions;
        total.boxes_excluded += s.boxes_excluded;
        total.boxes_inside += s.boxes_inside;
        total.leaf_solves += s.leaf_solves;
        total.scans += s.scans;
        total.together += s.together;
        total.fallbacks += s.fallbacks;
        total.splits += s.splits;
        total.prunes += s.prunes;
        total.lane_forms += s.lane_forms;
        total.tile_pieces += s.tile_pieces;
        total.tile_decided += s.tile_decided;
        total.quarter_pieces += s.quarter_pieces;
        total.wide_forms += s.wide_forms;
        total.segment_forms += s.segment_forms;
        total.monotone_segments += s.monotone_segments;
        total.newton_brackets += s.newton_brackets;
        total.merged_scans += s.merged_scans;
        total.second_order += s.second_order;
        total.folds += s.folds;
        total.folded_instructions += s.folded_instructions;
        total.folded_scans += s.folded_scans;
        total.clipped += s.clipped;
        total.empty_tiles += s.empty_tiles;
    }
    if (stats != nullptr) *stats = total;
    if (!colour_tiles) {
        result.image = colorize(ans, aov, options.render.light, options.render.threads);
    }
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::optional<PixelRays> bundle_rays(std::span<const Ray> rays, std::size_t min_rays) {
    const std::size_t n = rays.size();
    if (n == 0 || n < min_rays || n >= PixelRays::kNoRay) return std::nullopt;
    NearestScope env;
    auto same = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
        return std::bit_cast<std::array<std::uint64_t, 3>>(a) ==
               std::bit_cast<std::array<std::uint64_t, 3>>(b);
    };
    bool one_origin = true, one_direction = true;
    for (const Ray& r : rays) {
        one_origin = one_origin && same(r.o, rays[0].o);
        one_direction = one_direction && same(r.d, rays[0].d);
        if (r.d[0] == 0 && r.d[1] == 0 && r.d[2] == 0) return std::nullopt;
    }
    if (!one_origin && !one_direction) return std::nullopt;
    // The bundle's axis e0 (the mean unit direction, or the one direction) and two axes across.
    Vec3 e0{0, 0, 0};
    for (const Ray& r : rays) {
        const Vec3 w = normalize({r.d[0], r.d[1], r.d[2]});
        for (int c = 0; c < 3; ++c) e0[c] += w[c];
        if (one_direction) break;
    }
    e0 = normalize(e0);
    if (!(std::isfinite(e0[0]) && std::isfinite(e0[1]) && std::isfinite(e0[2]))) {
        return std::nullopt;
    }
    const Vec3 helper = std::fabs(e0[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 e1 = normalize(cross(e0, helper));
    const Vec3 e2 = cross(e0, e1);
    // Each ray's place across the bundle: its direction's projection onto the plane at unit
    // distance along e0 (one origin, within a cone around e0), or its origin's (one direction).
    std::vector<std::array<double, 2>> uv(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Ray& r = rays[k];
        if (one_origin) {
            const Vec3 w = normalize({r.d[0], r.d[1], r.d[2]});
            const double along = dot(w, e0);
            if (!(along > 0.2)) return std::nullopt;  // wider than a camera: one by one
            uv[k] = {dot(w, e1) / along, dot(w, e2) / along};
        } else {
            const Vec3 o{r.o[0], r.o[1], r.o[2]};
            uv[k] = {dot(o, e1), dot(o, e2)};
        }
    }
    const auto width = static_cast<unsigned>(std::ceil(std::sqrt(static_cast<double>(n))));
    const auto height = static_cast<unsigned>((n + width - 1) / width);
    std::vector<std::uint32_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = static_cast<std::uint32_t>(k);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return uv[a][1] < uv[b][1]; });
    std::vector<std::uint32_t> cells(std::size_t{width} * height, PixelRays::kNoRay);
    for (std::size_t row = 0; row * width < n; ++row) {
        const auto first = order.begin() + static_cast<std::ptrdiff_t>(row * width);
        const auto last =
            order.begin() + static_cast<std::ptrdiff_t>(std::min(n, (row + 1) * width));
        std::sort(first, last,
                  [&](std::uint32_t a, std::uint32_t b) { return uv[a][0] < uv[b][0]; });
        std::copy(first, last, cells.begin() + static_cast<std::ptrdiff_t>(row * width));
    }
    double u0 = kInf, u1 = -kInf, v0 = kInf, v1 = -kInf;
    for (const auto& p : uv) {
        u0 = std::min(u0, p[0]);
        u1 = std::max(u1, p[0]);
        v0 = std::min(v0, p[1]);
        v1 = std::max(v1, p[1]);
    }
    const double pitch = std::max((u1 - u0) / width, (v1 - v0) / height);
    return PixelRays(rays, width, height, std::move(cells), pitch, one_origin);
}

std::optional<std::vector<RayResult>> query_coherent(const expr::Tape& tape,
                                                     std::span<const Ray> rays,
                                                     const CoherentOptions& options,
                                                     CoherentStats* stats) {
    std::optional<PixelRays> grid = bundle_rays(rays);
    if (!grid) return std::nullopt;
    CoherentOptions o = options;
    o.render.width = grid->grid_width();
    o.render.height = grid->grid_height();
    std::vector<RayResult> cells;
    render_3d_coherent(tape, o, *grid, stats, &cells);
    std::vector<RayResult> out(rays.size());
    for (unsigned j = 0; j < o.render.height; ++j) {
        for (unsigned i = 0; i < o.render.width; ++i) {
            const std::uint32_t k = grid->index(i, j);
            if (k != PixelRays::kNoRay) out[k] = cells[std::size_t{j} * o.render.width + i];
        }
    }
    return out;
}

}  // namespace certray::tracers
