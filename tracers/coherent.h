// tracers/coherent.h — certified 3D images by rays that share interval work: screen tiles ×
// parameter segments evaluated as interval boxes, front to back, with the tape pruned per box; the
// rays that are left run the certified solver from where their tile proved them free of zeros.
//
// Contract: every pixel's answer has the meaning of solvers::certified_first_root on the very ray
// pixel_ray() gives (solvers/ray.h): Hit [t_lo, t_hi] — a zero proven in [t_lo, t_hi] and none in
// [tmin, t_lo); Miss — none on [tmin, tmax]; otherwise Unknown. A box that encloses every point of
// every ray of a tile over a parameter range [a, b] (outward rounding), over which the interval
// enclosure of f excludes 0, proves every one of those rays free of zeros on [a, b]; segments are
// processed front to back, so when a ray reaches a leaf at parameter a, [tmin, a) is proven free
// and the certified solver's answer on [a, b] (with a tape pruned to the leaf's box, which equals f
// there) is an answer for the whole ray. A one-ray leaf answer of Unknown on [a, b] is first split
// in two again (each half its own box evaluation and pruned tape, up to 24 times a ray); what
// stays undecided is redone by the per-ray solver on [a, tmax] with the full tape, so that a proof
// further along the ray is still found. Reference:
// Knoll et al. 2009, Keeter 2020, Duff 1992; docs/theory/coherent.md.
//
// Under the solid surface (CoherentOptions::surface) every pixel has the meaning of
// solvers::solid_first_entry on its ray: Hit [t_lo, t_hi] — g(t_hi) < 0 proven and g ≥ 0 proven on
// [tmin, t_lo); Miss — g ≥ 0 proven on [tmin, tmax] (where g is defined); otherwise Unknown. A box
// over which the enclosure of f is empty or has lower bound ≥ 0 proves g ≥ 0 for its rays on
// [a, b] (wherever f is defined: other points are not in the solid); one over
// which it is defined with upper bound < 0 proves, for each of its rays, g < 0 at the first
// parameter of [a, b] on the ray — where g ≥ 0 is already proven before it, so that ray is a Hit
// [t, t] with no further work. Leaves run solid_first_entry on their segment.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/ray.h"
#include "tracers/camera.h"
#include "tracers/methods.h"
#include "tracers/render.h"

namespace certray::tracers {

/// How pixels become rays.
enum class Projection : std::uint8_t {
    /// The pinhole camera of RenderOptions::camera: pixel (i, j) is CameraFrame::ray(i + 0.5,
    /// j + 0.5) clipped to the bounds (clip_ray), exactly as render_3d traces it.
    Pinhole,
    /// A heightmap: one ray per pixel straight down (d = (0, 0, −1)) from z = z1 to z = z0 of the
    /// bounds, pixel centres spread over the bounds' x–y rectangle (x0 on the left, y1 on the top
    /// row): o = (x0 + (i + 0.5)·(x1 − x0)/width, y1 − (j + 0.5)·(y1 − y0)/height, z1),
    /// t ∈ [0, z1 − z0] (the upper end rounded up). The setting of libfive's and Fidget's 3D
    /// timings.
    Ortho,
    /// Given rays laid out on a grid (bundle_rays): pixel (i, j) is the ray in that cell, as it
    /// is (not clipped), or none.
    List,
};

/// The solver options for images: tighten off, hit_width 1e-6.
inline solvers::CertifiedOptions image_solver_options() {
    solvers::CertifiedOptions o;
    o.tighten = false;
    o.hit_width = 1e-6;
    return o;
}

/// Everything a coherent image needs besides the scene.
struct CoherentOptions {
    /// Size, pinhole camera, bounds, light, AOV, threads (0: one per hardware thread), progress
    /// (advanced root tile by root tile).
    RenderOptions render;
    Projection projection = Projection::Pinhole;
    /// Zero: the first t with f = 0 (certified_first_root); Solid: the first entry into {f < 0}
    /// (solid_first_entry).
    Surface surface = Surface::Zero;
    /// The per-ray solver's options, for every leaf ray (budget per solve). By default those an
    /// image needs: hits narrowed to 1e-6 relative width, not to 4 ulps by the exact oracle
    /// (docs/theory/coherent.md, "Options for images"); the answers keep their meaning. Set
    /// `certified = {}` for the per-ray defaults (slower: docs/benchmarks.md).
    solvers::CertifiedOptions certified = image_solver_options();
    /// Pixels per side of a root tile, the unit of work of a thread (≥ 1).
    unsigned root_tile = 16;
    /// A box is split in t while its depth (t extent) exceeds `aspect` times its lateral extent
    /// (the spread of its rays at the far end, plus one pixel), otherwise across the screen.
    double aspect = 0.5;
    /// Where the interval enclosure of f over a box of at most this many rays holds 0, try the
    /// mean value form (f at the box's centre plus the gradient enclosure times the box's radius;
    /// one gradient and one point evaluation), which is second-order tight on small boxes (and
    /// seldom pays on larger ones). 0: never. Unset: in each root tile the form is tried on boxes
    /// of at most 16 rays while it pays (the first 16 tries, then while one in four proves a
    /// box, else one try in eight): it is what makes polynomial scenes fast, and costs more than
    /// it saves on Fidget's exp-blended bear (docs/benchmarks.md, session 7); on larger boxes
    /// whose list is smooth (a tangent list without kinks: the form from five lanes) apart, while
    /// one in three proves a box (the first try, then one in 16): Chmutov's sextic, session 13.
    std::optional<unsigned> mean_value_rays;
    /// Images (Pinhole, Ortho) of any AOV but the depth: a pixel's hit enclosure may stop
    /// narrowing once it is at most this many pixel footprints deep (pinhole: relative to t, the
    /// pixel's angle times this; ortho: the pixel's side times this), besides
    /// certified.hit_width; the answer keeps its meaning. 0: only certified.hit_width. Not used
    /// for ray lists (query bundles) nor for the depth AOV (depths as data keep their digits).
    /// 0.5 is what an image needs (the CLI's render, the benchmarks).
    double depth_pixels = 0;
    /// With depth_pixels: a node of at most this many open rays whose segments are each at most
    /// 8 pieces of that depth long is not divided further; its rays are scanned together, every
    /// piece of every ray one lane of one batched interval evaluation (docs/theory/coherent.md,
    /// "Scanning rays together"); a leaf of one ray is scanned in lanes the same way. 0: each
    /// ray scanned alone, piece by piece, at the end of the descent (the reference the lanes are
    /// tested against). 8 had measured best of 4–64 on Barth's sextic, the tanglecube, Chmutov's
    /// sextic and Fidget's bear and colonnade (session 10); 16 since session 22, on a machine
    /// whose batch walks take 16 binary32 lanes a vector and with segment forms on folded lists:
    /// the colonnade's heightmaps 0.90–0.91 of the time, csg.expr 0.86–0.92, the bear 1.00
    /// (docs/benchmarks.md).
    unsigned together_rays = 16;
    /// together_rays where the node's list has a tangent list (expr/tangent.h) and
    /// lane_mean_value is on: the pieces' mean value forms in lanes make wider scans pay. 16
    /// measured best of 4–32 on Barth's sextic, the tanglecube and Chmutov's sextic (–10 to
    /// –21% against 8; docs/benchmarks.md, session 10); 32 since session 24, with the segment
    /// forms and Newton brackets (pairs at one thread against 16: Clebsch's heightmap 0.95,
    /// Chmutov's 256² heightmap 0.96, Barth's zero set 0.98, the others 0.98–1.01).
    unsigned smooth_together_rays = 32;
    /// together_rays where the node's list has at least 200 instructions: one walk of a long list
    /// costs more per call, so more rays share it. 16 measured −14% on Fidget's bear (lists of
    /// about 400 instructions) and −10% on the molecule against 8, the colonnade's short lists
    /// untouched (docs/benchmarks.md, session 11).
    unsigned long_together_rays = 16;
    /// Nodes of more rays than those, up to this many, whose list fold_lists folds to the node's
    /// box: their rays are scanned together on the folded list (a node whose list does not fold
    /// is divided further). The folded list's walks are shorter than the list's, and the node's
    /// one box evaluation, prune and fold serve all its rays. 64 (a root tile's quarter): Fidget's
    /// bear 512² heightmap 0.87 of the time with 16, pinhole 0.94, 256² heightmap 0.89; the
    /// molecule, the particles and test.json unchanged (they fold seldom at such nodes); 128 and
    /// 256 no better (docs/benchmarks.md, session 18). 0: never more than the others.
    unsigned folded_together_rays = 64;
    /// In those lanes, pieces that their enclosure leaves undecided get the mean value form in t
    /// at once, from a derivative computed in the same batched walk (expr/tangent.h), where the
    /// list has only ops with such a rule (no abs, min, max, …). Off: the form is tried on one
    /// ray's first undecided piece at a time, as a scan of one ray does.
    bool lane_mean_value = true;
    /// Scans of several rays first evaluate the node's segment in pieces of the narrowest ray's
    /// width as boxes over all its rays (one lane each): a piece proven free there is free on
    /// every ray, and a ray whose first piece not proven free is followed by one proven inside
    /// (solid), or lies between pieces of strict opposite signs (zero set), is answered without
    /// pieces of its own. Not on a smooth list where the segment forms run (they decide per ray
    /// what the tile pieces would: Barth 0.985 of the instructions; docs/theory/coherent.md).
    /// Off: each ray's own pieces only.
    bool tile_pieces = true;
    /// Scans of rays on a smooth list (a tangent list without kinks, expr/tangent.h, of at least
    /// 8 instructions), or on a list with kinks that fold_lists folded (Clarke's derivative at the
    /// kinks), first take the mean value form in t over each ray's whole segment (one
    /// lane of a walk of the tangent list over the segment, one of the list at its middle; for
    /// segments of at least 2 pieces): a segment it proves free needs no pieces. Taken on every
    /// such scan (since session 22; a trial had stopped them where they spared few lanes, which
    /// cost the smooth scenes up to 5%). The answers keep their meaning. Off: the pieces only.
    bool segment_forms = true;
    /// Coarse scans: where the segment forms run on a node's own list (a smooth list: a tangent
    /// list without kinks, of at least 8 instructions), a node of rays that would be scanned
    /// together is scanned while each segment is at most `coarse_pieces` pieces long (instead of
    /// 8), and a node of at most 64 rays is split in t while its depth exceeds `scan_aspect`
    /// (instead of `aspect`) times its lateral extent: fewer, deeper nodes above the scans. A
    /// ray whose segment of more than 8 pieces the forms leave undecided (neither free nor
    /// strictly monotone) is left to the node's two halves in t, which only such rays enter (the
    /// others are answered, or proven free on [a, b] and closed while the halves run). Tried in
    /// each root tile while they pay: the first 64 long segments, then while at most one in eight
    /// is left to the halves (Chmutov's sextic leaves many). The answers keep their meaning.
    /// Measured in docs/benchmarks.md (session 28). Off: segments of at most 8 pieces, `aspect`.
    bool coarse_scans = true;
    /// With coarse_scans: the longest segment scanned, in pieces (more than 8).
    unsigned coarse_pieces = 32;
    /// With coarse_scans: the aspect of nodes of at most 64 rays.
    double scan_aspect = 1.0;
    /// With the segment forms, a segment that they do not prove free but on which the derivative
    /// along the ray keeps one strict sign (g strictly monotone) is decided by points: ends of one
    /// strict sign prove it free (the solid: both ≥ 0), ends of strict opposite signs bracket a
    /// zero with none before it (the solid: g decreasing from ≥ 0 to < 0, an entry), halved at
    /// points until the bracket is a piece deep (Hit). The answers keep their meaning. Off: the
    /// pieces.
    bool monotone_segments = true;
    /// With the monotone segments, every value of g at a point c also narrows a bracket to the
    /// interval Newton step c − g(c)/G′ (which holds every zero of g on the segment), and a step
    /// from the segment's middle whose far end lies inside the segment brackets the zero without
    /// a point at the segment's end (g has crossed 0 by then). The answers keep their meaning;
    /// their brackets are narrower. Off: halving alone.
    bool newton_brackets = true;
    /// The segment forms' middles as lanes of the tangent list's walk (whose value lanes are the
    /// list's, bit for bit) where forms and middles fit in one vector, instead of a walk of the
    /// list of their own. The same answers, bit for bit. Off: two walks.
    bool middles_in_forms = true;
    /// The quarters of a node that would each be scanned at once (scan_together) are scanned
    /// together, each over its own [a, b], where their list has no choices and does not fold and
    /// the root tile's tile pieces do not pay: one walk per phase of the scan for all of them.
    /// The answers keep their meaning. Off: one scan per quarter.
    bool merged_scans = true;
    /// A scanned segment that its first-order form leaves undecided and not monotone, and at
    /// whose middle c g is proven away from 0 on the free side, gets the second-order form
    /// g(c) + g′(c)·(t − c) + ½·G″·(t − c)² (G″ ⊇ g″ over the segment, from a walk of the tangent
    /// list's own tangent list), where the tape is smooth and its own list is scanned, while it
    /// pays in the root tile: rays that pass near the surface are proven free without their
    /// pieces. The answers keep their meaning. Off: the pieces.
    bool second_order_forms = true;
    /// With the segment forms on a folded list (fold_lists), the segments' plain enclosures are
    /// walked first where they prove enough of the segments free (3 in 10 so far in the root
    /// tile), and only the other segments walk the tangent list and the list at their middles.
    /// The same decisions, bit for bit, in fewer lanes: Fidget's bear 0.86–0.93 of the time
    /// (docs/benchmarks.md, session 18). Off: every segment's form at once.
    bool segment_enclosures_first = true;
    /// Where a node is divided into its four quarters, the quarters' boxes are evaluated in lanes
    /// of one batched walk, and the mean value forms they need in lanes of one walk of the
    /// tangent list, instead of a walk per quarter: the same enclosures and forms, bit for bit.
    /// Where the descent prunes (min/max choices) or folds, each quarter's slot enclosures are
    /// kept from the lanes for it (since session 23; csg.expr 0.92 of the time, the gyroid 0.96,
    /// Fidget's colonnade heightmap 0.98). The forms of all four are tried before the first
    /// quarter descends, so the adaptive trials may decide otherwise than without. Lists of more
    /// than 256 instructions keep a walk per quarter (their registers of 64 lanes outgrow the
    /// caches: the molecule took 1.1× the time). Off: a walk per quarter.
    bool children_in_lanes = true;
    /// Where a node's mean value form does not prove its box, the form read as a line in t
    /// (f ∈ p + (t − tc)·q on every ray of the node) narrows the node's [a, b] to where that line
    /// may vanish (the solid: be negative); each part cut off is proven free by the line's
    /// enclosure over it. Off: the node keeps its [a, b].
    bool clip_forms = true;
    /// A node's hull over the blocks of 4 × 4 pixels that its rectangle covers whole comes from
    /// each block's hull of its open rays, kept until one of them is answered, where all of them
    /// meet the node's [a, b] (else from the block's pixels): the same hulls, bit for bit (but the
    /// sign of a bound of 0 reached as +0 and −0), with a pass over each block's pixels only when
    /// it changed. Off: every node passes over its pixels.
    bool block_hulls = true;
    /// The scans' walks in lanes (pieces, points, tiles, quarters, segment enclosures and forms)
    /// and the nodes' mean value forms run in binary32 bounds (expr/eval_interval_batch.h: eight
    /// lanes per AVX2 instruction instead of four), each bound rounded outward, so that every
    /// enclosure holds the real values over a box that holds the scan's. The answers keep their
    /// meaning; the node boxes, the solver and the normals stay in double, and so do lists in which
    /// the ops without a binary32 kernel (expr::binary32_kernel) are more than a sixth of the
    /// instructions. Fidget's bear 0.76–0.82 of the time, the molecule 0.76, the gyroid 0.81
    /// (docs/benchmarks.md, sessions 19 and 20).
    /// Off: the double walk.
    bool float_lanes = true;
    /// The scans in lanes of a node whose list has at least this many instructions walk it folded
    /// to the node's box (expr::fold_ssa): the subexpressions whose enclosures over the box are at
    /// most a thousandth of f's wide become inputs fixed at those enclosures, when that drops an
    /// eighth of the list or more and the folded list's enclosure at the box's centre stays within
    /// a thousandth of f's width (else the same with a 32nd of the width, twice). Tried in each
    /// root tile while it pays (the first 4 nodes, then while half of them fold, else one in 16).
    /// The scan's pieces, points and mean value forms are then enclosures of f that the fixed
    /// inputs widen a little (the forms hold with the inputs' derivatives taken as 0:
    /// expr/prune.h); the solver, the normals and deeper nodes' boxes keep the list itself. The
    /// answers keep their meaning. 128: Barth's, the colonnade's and the gyroid's lists of 10–40
    /// have nothing to fold, the particles' of about 80 drop a fifth and took 1–2% longer, Fidget's
    /// bear's of about 380 drop 40% and take 20% less time (docs/benchmarks.md, session 17).
    /// 0: never.
    unsigned fold_lists = 128;
    /// A hit's normal is the gradient at the hit of the pruned list that answered it. On: the hits
    /// of one scan in lanes get theirs together once the scan returns (16 at most per walk), from
    /// one walk of Dual<double, 3> lanes (expr/eval_dual_batch.h), each the same bits as a walk of
    /// its own. Off: a Dual<double, 3> walk per hit.
    bool batch_normals = true;
};

/// What the coherent walk did, summed over the image.
struct CoherentStats {
    std::uint64_t box_evals = 0;         ///< interval evaluations over tile × segment boxes
    std::uint64_t box_instructions = 0;  ///< instructions those evaluations ran (pruned lengths)
    std::uint64_t boxes_excluded = 0;    ///< boxes proven free of zeros (solid: f ≥ 0 on them)
    std::uint64_t boxes_inside = 0;      ///< solid: boxes proven inside (f < 0), rays answered
    std::uint64_t leaf_solves = 0;       ///< certified solves of one ray on one segment
    std::uint64_t scans = 0;      ///< leaf segments decided by scanning pieces (depth_pixels)
    std::uint64_t together = 0;   ///< of the scanned segments: scanned in lanes (scan_together)
    std::uint64_t fallbacks = 0;  ///< leaf Unknowns redone on the rest of the ray
    std::uint64_t splits = 0;     ///< undecided one-ray leaf segments split in two again
    std::uint64_t prunes = 0;     ///< boxes whose tape was shortened
    /// scanned pieces that the mean value form in lanes proved (CoherentOptions::lane_mean_value)
    std::uint64_t lane_forms = 0;
    std::uint64_t tile_pieces = 0;   ///< tile pieces evaluated (CoherentOptions::tile_pieces)
    std::uint64_t tile_decided = 0;  ///< rays answered by tile pieces
    /// scanned pieces that neither their points nor their form decided, scanned again in
    /// quarters in lanes (several rays' quarters in one batched evaluation)
    std::uint64_t quarter_pieces = 0;
    /// boxes of more than 16 rays that the mean value form proved (CoherentOptions::
    /// mean_value_rays unset, smooth lists)
    std::uint64_t wide_forms = 0;
    /// rays' leaf segments that their segment form proved free (CoherentOptions::segment_forms)
    std::uint64_t segment_forms = 0;
    /// rays whose segment a coarse scan left to the node's halves in t (coarse_scans)
    std::uint64_t coarse_deferred = 0;
    /// of those tried: strictly monotone segments whose ends bracket a zero (monotone_segments)
    std::uint64_t monotone_segments = 0;
    /// of those: brackets that the Newton step from the segment's middle gave without an end
    /// point (newton_brackets)
    std::uint64_t newton_brackets = 0;
    /// scans of the rays of two to four quarters of a node at once (merged_scans)
    std::uint64_t merged_scans = 0;
    /// segments proven free by their second-order form (second_order_forms)
    std::uint64_t second_order = 0;
    /// scans in lanes whose list was folded to the node's box (CoherentOptions::fold_lists), and
    /// the instructions that dropped from their lists in all
    std::uint64_t folds = 0;
    std::uint64_t folded_instructions = 0;
    /// scans of more rays than together_rays allows, on a folded list (folded_together_rays)
    std::uint64_t folded_scans = 0;
    /// node boxes and scanned segments whose parameter range the line of their mean value form
    /// narrowed (or proved free where the form's own enclosure did not; clip_forms)
    std::uint64_t clipped = 0;
    /// root tiles answered without building their rays: every pixel a Miss (a heightmap's tile
    /// proven free by one box, a pinhole tile whose rays all miss the bounds)
    std::uint64_t empty_tiles = 0;
    std::uint64_t tape_length = 0;  ///< instructions of the full tape
};

/// The rays of an image, pixel by pixel: what render_3d_coherent answers, and what a per-ray
/// method given the same options would trace.
class PixelRays {
  public:
    /// Throws std::invalid_argument for an empty size, a bad pinhole camera (CameraFrame), or
    /// (Ortho) bounds that are not finite with x0 < x1, y0 < y1, z0 < z1.
    explicit PixelRays(const CoherentOptions& options);
    /// The rays of a bundle (Projection::List): `cells` (width × height, row-major) holds an
    /// index into `rays` or kNoRay; `pitch` is the typical distance between neighbouring rays,
    /// as an angle when `angular` (rays from one origin), else as a length. `rays` must outlive
    /// this object.
    PixelRays(std::span<const Ray> rays, unsigned width, unsigned height,
              std::vector<std::uint32_t> cells, double pitch, bool angular);
    static constexpr std::uint32_t kNoRay = 0xffffffffu;
    /// The ray of pixel (i, j) (j = 0 the top row), clipped to the bounds; false when it misses
    /// them (the pixel is then a Miss with no evaluation). Runs in a NearestScope.
    bool ray(unsigned i, unsigned j, Ray& ray) const;
    /// ray() for a caller that holds a NearestScope (one for a whole tile of pixels).
    bool ray_in_scope(unsigned i, unsigned j, Ray& ray) const;
    /// ray_in_scope() for pixels (i0 + k, j), k < n: rays[k] and in[k] (the pinhole's eight
    /// at a time, CameraFrame::clipped_row: the same bits).
    void row_in_scope(unsigned i0, unsigned j, unsigned n, Ray* rays, bool* in) const;
    /// True only where no ray of pixels [i0, i0 + w) × [j0, j0 + h) meets the bounds (a pinhole's
    /// CameraFrame::misses; the other projections: false), so that they need not be built.
    bool misses(unsigned i0, unsigned j0, unsigned w, unsigned h) const {
        return projection_ == Projection::Pinhole && frame_->misses(i0, j0, w, h, bounds_);
    }
    /// The widest angle (pinhole) or distance (ortho) between neighbouring pixel rays.
    double pixel_pitch() const { return pitch_; }
    Projection projection() const { return projection_; }
    /// List: the grid's size.
    unsigned grid_width() const { return width_; }
    unsigned grid_height() const {
        return width_ == 0 ? 0 : static_cast<unsigned>(cells_.size() / width_);
    }
    /// List: the index of the ray in cell (i, j), or kNoRay.
    std::uint32_t index(unsigned i, unsigned j) const {
        return cells_[std::size_t{j} * width_ + i];
    }
    /// The pitch is an angle (pinhole, rays from one origin): the rays spread with the distance.
    bool angular() const { return angular_; }

  private:
    Projection projection_;
    bool angular_ = false;
    std::span<const Ray> list_;         ///< List only
    std::vector<std::uint32_t> cells_;  ///< List only
    unsigned width_ = 0;                ///< List only
    std::optional<CameraFrame> frame_;  ///< Pinhole only
    Box3 bounds_;
    double dx_ = 0, dy_ = 0, tmax_ = 0, pitch_ = 0;
};

/// Renders `tape` by coherent certified ray casting (see the file contract): the same RenderResult
/// as render_3d with the `certified` method on options.surface (answers, AOV image, statistics),
/// where answers.evals[k] counts the whole-tape evaluations of pixel k's own solves (leaf and
/// fallback) and stats.evals adds every box evaluation (as interval evaluations, whatever their
/// pruned length). When `stats` is given it receives the walk's counters; when `results` is given,
/// every pixel's whole answer (row-major, top row first; a ray that misses the bounds is a Miss
/// with no evaluation). Threads: a parallel loop over root tiles, the calling thread taking part;
/// sound in any caller's floating-point environment. Throws std::invalid_argument as PixelRays
/// does, or for root_tile = 0.
RenderResult render_3d_coherent(const expr::Tape& tape, const CoherentOptions& options,
                                CoherentStats* stats = nullptr,
                                std::vector<RayResult>* results = nullptr);

/// The same walk over the rays `rays` gives (options.render's width and height must be theirs;
/// its camera and bounds are not read).
RenderResult render_3d_coherent(const expr::Tape& tape, const CoherentOptions& options,
                                const PixelRays& rays, CoherentStats* stats = nullptr,
                                std::vector<RayResult>* results = nullptr);

/// Lays out a set of camera-like rays — all from one origin, or all along one direction, at least
/// `min_rays` of them, none degenerate — on a grid where neighbouring cells hold neighbouring
/// rays (rows by one coordinate across the bundle, each row sorted by the other), for the
/// coherent walk. Empty when the rays are not such a set.
std::optional<PixelRays> bundle_rays(std::span<const Ray> rays, std::size_t min_rays = 256);

/// Answers `rays` by the coherent walk when they form a bundle (bundle_rays), with the
/// certified meaning of options.surface; the results in input order (each ray's evaluations are
/// its own solves'; the shared box evaluations are in `stats`). Empty when they do not form a
/// bundle: answer them one by one.
std::optional<std::vector<RayResult>> query_coherent(const expr::Tape& tape,
                                                     std::span<const Ray> rays,
                                                     const CoherentOptions& options,
                                                     CoherentStats* stats = nullptr);

}  // namespace certray::tracers
