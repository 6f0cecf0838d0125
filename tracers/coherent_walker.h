// tracers/coherent_walker.h — internal to the coherent walk: the Walker, one thread's descent
// over its root tiles, declared here and defined in tracers/coherent_walk.cpp (tiles, hulls, nodes,
// leaves, answers), coherent_lanes.cpp (walks in lanes, mean value forms, folds),
// coherent_scan.cpp (scans of rays in lanes) and coherent_segments.cpp (segment forms, monotone
// segments, second-order forms).
//
// Contract of node(r, a, b): every open ray of r (its pixel not yet answered) is proven free of
// zeros on [tmin, max(tmin, a)), and the list it is given equals f at every point of every open
// ray of r for t in [a, b]. node() leaves every open ray of r proven free of zeros up to b (or
// answered). What each pixel's answer means: tracers/coherent.h. Reference:
// docs/theory/coherent.md.
#pragma once

#include <array>
#include <boost/container/vector.hpp>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <vector>

#include "expr/eval_dual_batch.h"
#include "interval/dual.h"
#include "solvers/certified.h"
#include "solvers/solid.h"
#include "tracers/coherent.h"
#include "tracers/coherent_parts.h"

namespace certray::tracers::detail::coherent {

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
    /// Whether nodes of `list` at `depth` that would be scanned together are scanned coarsely
    /// (CoherentOptions::coarse_scans): where the segment forms run on the list itself, while
    /// they pay in the root tile (the first kCoarseFirst long segments, then while at most one
    /// in kCoarseShare is left to the halves).
    bool coarse_scans(const Ssa& list, unsigned depth) {
        return options_.coarse_scans && options_.coarse_pieces > kMaxPieces &&
               options_.segment_forms &&
               (coarse_long_ < kCoarseFirst || kCoarseShare * coarse_left_ <= coarse_long_) &&
               list.size() >= kSegmentFormList && depth + 1 < kMaxDepth &&
               tangent_kind(list, depth) == expr::TangentKind::Smooth;
    }
    /// Nodes of at most this many rays take CoherentOptions::scan_aspect where they scan
    /// coarsely.
    static constexpr unsigned kCoarseRays = 64;
    static constexpr std::size_t kCoarseFirst = 64, kCoarseShare = 8;  ///< coarse_scans()'s trial
    /// Opens or closes pixel (i, j)'s ray (answer(); descend_deferred() closes rays for a while):
    /// its block's count of open rays follows, and the hulls taken before are stale.
    void set_open(unsigned i, unsigned j, bool open) {
        px(i, j).open = open;
        Block& block = block_of(i, j);
        block.open += open ? 1 : -1;
        block.stale = true;
        ++answered_;
    }
    /// The rays of a coarse scan's group that it left to the node's halves (Scanned::deferred)
    /// walk them; the group's other rays, answered or proven free on [a, b], are left out of
    /// them (closed while they run, then open again).
    void descend_deferred(const Rect& r, double a, double b, const Ssa& list,
                          const expr::Tape* tape, Level& level, std::size_t begin, std::size_t end,
                          unsigned depth);
    /// One of descend_deferred()'s halves: its open rays scanned at once where the list neither
    /// folds nor prunes (the scan's segment forms, a ray each, decide what the node's box and
    /// form over all of them would); otherwise, or where the scan does not take them, node().
    void deferred_half(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                       unsigned depth);
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
    /// eval_lanes() in `file`, or in the registers of the list's LaneList where it has one:
    /// returns the file walked (every slot of the list holds its lanes there).
    template <class L>
    const LaneFile<L>& eval_lanes_in(LaneFile<L>& file, const Ssa& list, const LaneBox* boxes,
                                     std::size_t n, std::vector<UpInterval>& out,
                                     const Level* fold);
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
    /// interval ray_box gives (empty where a bound is NaN or lo > hi). With `ll` (whose file is
    /// `file`), into the slots of its variables instead.
    template <class L>
    void load_lanes(LaneFile<L>& file, const LaneBox* boxes, int m,
                    const LaneList<L>* ll = nullptr);
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
    /// Writes the normal of the pixel in slot k: the unit vector n (or 0), turned where its dot
    /// product with the ray's direction, `facing`, is positive (set_normal's last step, which
    /// flush_normals() takes after its vectors' arithmetic).
    void store_normal(std::size_t k, Vec3 n, double facing);
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
    /// Whether a scan of `list` takes tile pieces, and so whether their trial holds back merged
    /// scans: not where the segments' forms run on a smooth list (its tangent kind as the forms
    /// read it: folded to `scanned`'s box where that level folded it, else the list's own), which
    /// decide per ray what the tile pieces would decide per node (the trial's tries and the merged
    /// scans it held back: the sphere, the torus, Barth, the tanglecube and Chmutov's heightmap
    /// 0.97–0.99 of the time without them; docs/benchmarks.md, session 26). Kinked lists keep them
    /// (the colonnade's heightmap 1.25× without). The kind is asked for only where it decides.
    bool tile_pieces_for(const Ssa& list, unsigned depth, Level* scanned) {
        if (!options_.tile_pieces) return false;
        if (!options_.segment_forms || list.size() < kSegmentFormList) return true;
        const expr::TangentKind kind = scanned != nullptr ? lane_tangent_kind(list, depth, *scanned)
                                                          : tangent_kind(list, depth);
        return kind != expr::TangentKind::Smooth;
    }
    /// This root tile's mean value forms in lanes on lists with kinks (scan_together; a win: they
    /// proved at least half the pieces they were taken on): the first 4, then one in 16 (the
    /// molecule's forms prove 16% of such pieces, the bear's 67%).
    PayingTrial<4, 16> kink_forms_;
    /// The root tile's segment forms so far: segments tried, and those their plain enclosure
    /// proved free (take_segment_forms() walks those enclosures first while that is 3 in 10).
    std::size_t plain_tried_ = 0, plain_free_ = 0;
    /// This root tile's coarse scans: the rays whose segment was longer than kMaxPieces pieces,
    /// and those of them left to the halves (coarse_scans()).
    std::size_t coarse_long_ = 0, coarse_left_ = 0;
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
    std::uint64_t answered_ = 0;  ///< rays opened or closed so far (hulls taken before are stale)
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
        bool long_segment;  ///< Level::Scanned::long_segment
    };
    std::vector<Segment> segments_;
    std::vector<std::pair<unsigned, unsigned>> hidden_;  ///< descend_deferred()'s closed rays
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
    /// The LaneLists (make_lane_list) of the tape's list, its tangent list and its second-order
    /// list, made at their first walk in lanes of each kind (the tape's in double lanes too:
    /// split_screen), where they have at most kLanesList instructions: a longer list's registers
    /// outgrow the caches (particles.txt's 16,009: 25 MiB a walker), and its constants and
    /// variables are few beside the rest.
    template <class L>
    struct LaneLists {
        std::optional<LaneList<L>> tape, tangent, second;
        bool made[3] = {false, false, false};
    };
    LaneLists<expr::IntervalLanesF> f32_lists_;
    LaneLists<expr::IntervalLanes> d64_lists_;
    /// The LaneList of `list` in lanes L, or null where it has none (a pruned or folded list, or
    /// one longer than kLanesList).
    template <class L>
    LaneList<L>* lane_list(const Ssa& list) {
        LaneLists<L>* lists = nullptr;
        if constexpr (std::is_same_v<L, expr::IntervalLanes>) {
            lists = &d64_lists_;
        } else {
            lists = &f32_lists_;
        }
        std::optional<LaneList<L>>* found = nullptr;
        std::uint32_t slots = 0;
        int which = 0;
        if (&list == &tape_.ssa()) {
            found = &lists->tape;
            slots = static_cast<std::uint32_t>(list.size());
        } else if (tape_tangent_ && &list == &tape_tangent_->list) {
            found = &lists->tangent;
            slots = tape_tangent_->slots;
            which = 1;
        } else if (tape_second_ && &list == &tape_second_->list) {
            found = &lists->second;
            slots = tape_second_->slots;
            which = 2;
        } else {
            return nullptr;
        }
        if (!lists->made[which]) {
            lists->made[which] = true;
            if (list.size() <= kLanesList) *found = make_lane_list<L>(list, slots);
        }
        return found->has_value() ? &**found : nullptr;
    }
    /// Where a walk of `list` runs: the registers of its LaneList and the rest of the list, or
    /// `shared` and the whole list (`ll` null). A folded list has none (its fixed inputs are
    /// loaded into the registers of the walk), nor does any list but the three above.
    template <class L>
    struct LaneWalk {
        LaneFile<L>& file;
        const Ssa& walked;
        const LaneList<L>* ll;
    };
    template <class L>
    LaneWalk<L> lane_walk(LaneFile<L>& shared, const Ssa& list) {
        if (LaneList<L>* ll = lane_list<L>(list)) return {ll->file, ll->core, ll};
        return {shared, list, nullptr};
    }
};

}  // namespace certray::tracers::detail::coherent
