// tracers/bounding.h — bounding volumes: a signed distance bound that skips far primitives.
//
// Contract: BoundedScene mirrors the CSG structure at the top of f — maximal clusters of min
// (union) and max (intersection) and negations (complement) — down to leaves (any other
// subexpression, e.g. a primitive). Every node gets a box enclosing its solid {node ≤ 0} inside
// the bounds (leaves: by interval slab contraction; unions: the hull; intersections: the
// intersection; complements: the bounds), each leaf a Lipschitz bound λ over its box inflated by
// the margin (expr::lipschitz_bound, with root forms so that Euclidean distances get λ = 1), and
// each union cluster a balanced tree of boxes (a BVH). distance(p) is then Hart's CSG distance
// bound (1996): leaves f/λ, unions min, intersections max, complements negation — except that a
// node whose box is farther than the margin from p is replaced by the distance to its box, as the
// seed's "piecewise lower distance bound" says, and a union's subtrees whose boxes are farther
// than the best distance so far are not visited. The result has f's sign and a magnitude at most
// the distance from p to the surface inside the bounds: sufficient for sphere tracing (never
// steps past the first root inside the bounds), not for modelling (it is not f).
// Build cost: O(leaves · cells) interval evaluations of leaf tapes; memory O(leaves).
// Reference: docs/theory/bounding.md; Hart 1996 §3 (CSG distance bounds), §4 (bounding volumes).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "expr/graph.h"
#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"
#include "tracers/march.h"
#include "tracers/region_tapes.h"

namespace certray::tracers {

/// How bounding volumes are built.
struct BoundingOptions {
    /// A node closer than margin·diagonal(bounds) to the query point is evaluated, not bounded.
    double margin = 1.0 / 64;
    /// Rounds of slab contraction that find each leaf's box (each round cuts all six sides).
    int slab_rounds = 3;
    /// Bisection steps per side and round (the cut is within 2⁻ˢᵗᵉᵖˢ of the side's length).
    int slab_steps = 12;
    /// Deeper CSG nesting (alternating unions, intersections, complements) becomes one leaf.
    int max_nesting = 48;
};

/// A scene prepared for sphere tracing with bounding volumes (see the file contract).
class BoundedScene {
  public:
    using Box = std::array<Interval, 3>;

    /// Builds the volumes of the tape's function inside `bounds` (finite, non-empty; else
    /// std::invalid_argument).
    BoundedScene(const expr::Tape& tape, const Box& bounds, const BoundingOptions& options = {});
    /// Not copied or moved: the region tapes refer to the scene's own tapes.
    BoundedScene(const BoundedScene&) = delete;
    BoundedScene& operator=(const BoundedScene&) = delete;

    /// How distance() used local bounds: with `refine` false a leaf tries one only where its
    /// box's λ gives no bound at all; `tried` counts the local bounds computed and `won` those
    /// at least twice the box's bound (bounded_sphere_trace stops refining on a ray where they
    /// do not win, as sphere tracing does).
    struct LocalTries {
        bool refine = true;
        std::uint64_t tried = 0, won = 0;
        /// The last local bounds' boxes of up to four leaves, reused while the point's box fits
        /// (detail::LocalBox), and whether each leaf's λ has been checked against the gradient at
        /// a point (leaf_distance); slots taken round robin.
        std::array<std::uint32_t, 4> leaf{~0u, ~0u, ~0u, ~0u};
        std::array<detail::LocalBox, 4> boxes{};
        std::array<bool, 4> probed{};  ///< the gradient at a point compared with the leaf's λ
        std::array<bool, 4> tight{};   ///< and found ≥ λ/4: no local bound on that leaf
        unsigned next = 0;
    };

    /// An enclosure of the signed distance bound at every point of the box p (a tiny box around
    /// one point); `leaf_evals` counts the leaf tapes evaluated (values and local bounds).
    /// With rho > 0, a leaf whose bound from its box's λ is below rho/2 also tries the local λ
    /// over p ⊕ rho (cut to the bounds: only surface points inside them count): min(|f|/λ_local,
    /// rho) is a distance bound too (the nearest surface point within rho is reached inside that
    /// box; a farther one is farther than rho), and the larger of the two is kept — so a loose λ
    /// neither stalls the tracer nor stops it far from the surface. Undefined (decoration false)
    /// where a leaf is undefined or has no finite λ. Thread-safe.
    Interval distance(const Box& p, std::uint64_t& leaf_evals, double rho = 0,
                      LocalTries* tries = nullptr) const;

    /// f restricted to one ray's segment [ray.tmin, ray.tmax] (inside the bounds): a leaf whose
    /// box the segment provably misses is positive all along it, so it is dropped from a union
    /// (min(f, g) has g's zeros and sign where f > 0) and makes an intersection positive (max(f, g)
    /// > 0). The result has the zeros and the sign of g(t) = f(o + t·d) on the segment — what a
    /// certified root finder needs — with only the leaves the segment meets. `sign` is +1 or −1
    /// when no leaf is left (f has that sign on the whole segment; `tape` is empty), else 0.
    struct Restricted {
        int sign = 0;
        expr::Tape tape;
        std::size_t leaves = 0;  ///< leaves kept
    };
    Restricted restrict_to(const Ray& ray) const;

    /// The bounds everything holds in.
    const Box& bounds() const { return bounds_; }
    /// The full tape of f (for degenerate rays and outside the bounds).
    const expr::Tape& tape() const { return tape_; }
    /// Number of leaves and of tree nodes.
    std::size_t leaves() const { return leaves_.size(); }
    std::size_t nodes() const { return nodes_.size(); }
    /// The region-pruned tapes of f (tracers/region_tapes.h) when f is long, else null.
    const RegionTapes* region_tapes() const { return regions_.get(); }
    /// Nodes closer than this to the query point are evaluated (scene units).
    double margin() const { return margin_; }
    /// Wall time of the build in seconds.
    double build_seconds() const { return build_seconds_; }

  private:
    enum class Kind : std::uint8_t { Leaf, Neg, Min, Max };
    struct Node {
        Kind kind = Kind::Leaf;
        std::array<double, 3> lo{}, hi{};  ///< the solid's box (lo > hi: empty)
        std::uint32_t a = 0, b = 0;        ///< children (Neg: a); Leaf: a = leaf index
        bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
    };
    struct Leaf {
        expr::Tape tape;
        double lambda = 0;
        /// The leaf's region-pruned tapes when its tape is long (kRegionTapesAbove), else null.
        std::shared_ptr<const RegionTapes> regions;
    };

    std::uint32_t build(const expr::Graph& g, expr::NodeId id, int nesting);
    std::uint32_t cluster(const expr::Graph& g, expr::NodeId id, int nesting);
    std::uint32_t balance(std::vector<std::uint32_t>& parts, std::size_t lo, std::size_t hi,
                          Kind kind);
    std::uint32_t leaf(const expr::Graph& g, expr::NodeId id);
    std::uint32_t add(Node n);
    double box_distance(const Node& n, const Box& p) const;
    Interval leaf_distance(const Leaf& l, const Box& p, double db, double rho,
                           std::uint64_t& leaf_evals, LocalTries* tries) const;

    Box bounds_;
    expr::Tape tape_;
    BoundingOptions options_;
    double margin_ = 0;
    std::vector<Node> nodes_;
    std::vector<Leaf> leaves_;
    std::uint32_t root_ = 0;
    std::shared_ptr<const RegionTapes> regions_;  // the only leaf's, when that leaf is f
    double build_seconds_ = 0;
};

/// A tracer of one segment of a ray with the budget left.
using SegmentTracer = std::function<RayResult(const Ray& segment, std::uint64_t budget)>;

/// Runs `inside` on the part of the ray inside `bounds` and `outside` on the parts before and
/// after them (each only when longer than a point: they share their ends with the inside part),
/// in order of t, and returns the first answer that is not a miss — an unknown one extended to
/// ray.tmax, nothing being known past it — with the evaluations of all parts and one budget.
RayResult trace_in_parts(const Ray& ray, const std::array<Interval, 3>& bounds,
                         std::uint64_t budget, const SegmentTracer& inside,
                         const SegmentTracer& outside);

/// The certified solver (solvers/certified.h) on the segment of the ray inside the bounds, with
/// the tape restricted to the leaves the segment meets (restrict_to); the parts of the ray before
/// and after the bounds on the full tape. Certified: the restricted tape has the same zeros and
/// sign along the segment.
RayResult bounded_certified(const BoundedScene& scene, const Ray& ray, std::uint64_t budget);

/// Sphere tracing with the scene's bounding volumes inside its bounds (Hart 1996): the ray is
/// clipped to the bounds; each step evaluates distance() once (evals.interval) with
/// rho = max(16·epsilon, 2·the previous distance), the margin at the first point (local bounds
/// where the box's λ is loose).
/// Same answers and guarantee as sphere_trace. The ray outside the bounds is the caller's.
RayResult bounded_sphere_trace(const BoundedScene& scene, const Ray& ray,
                               const TraceOptions& options);

}  // namespace certray::tracers
