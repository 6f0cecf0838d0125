// tracers/octree.h — an octree over the scene bounds with per-cell pruned tapes and local
// Lipschitz constants (Hart 1996, §"Octree"; libfive's EMPTY / FILLED / AMBIGUOUS cells), built
// once per scene and shared by every ray.
//
// Contract: every leaf is classified by an interval evaluation over its box: `Empty` (f > 0 on the
// whole cell) and `Full` (f < 0) hold no zero of f; an `Ambiguous` leaf keeps a tape pruned to a
// slightly inflated copy of its box (expr::prune: equal to f at every point of that box) and λ, a
// sound bound on ‖∇f‖₂ over it (expr::lipschitz_bound; +inf where f is not proven defined and
// continuous). Rays walk the leaves in order of entry along the ray with conservative (outward
// rounded) slab intersections, so consecutive segments overlap by a few ulps and cover the ray's
// part inside the bounds without gaps. Two methods use it:
//   - certified(): the certified solver (solvers/certified.h) on each ambiguous leaf's segment
//     with its pruned tape, and on the parts of [tmin, tmax] outside the bounds with the full
//     tape — the certification semantics of solvers/ray.h hold for the whole ray;
//   - sphere(): tracers/sphere_trace.h on each ambiguous leaf's segment with the leaf's pruned
//     tape and local λ, inside the bounds (outside them the scene is taken as empty: an
//     approximate method that never steps past a root inside the bounds when the λ are sound).
//     Where a leaf has no finite λ (a pole, the edge of f's domain) or sphere tracing ends
//     unknown with budget and time left, segment tracing (tracers/segment_trace.h) goes on from
//     where it stopped, on the leaf's pruned tape (never past the first root either). The whole
//     ray shares one budget of evaluations and one of time (TraceOptions::seconds).
// Memory is bounded by `max_nodes`; a pruned tape equal to its parent's is shared, not copied.
// Reference: docs/theory/octree.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/certified.h"
#include "solvers/ray.h"

namespace certray::tracers {

struct TraceOptions;  // tracers/march.h

struct OctreeOptions {
    /// Subdivision depth of the deepest leaves (the root cell is depth 0).
    int max_depth = 5;
    /// The most nodes the tree may hold; subdivision stops when the next split would exceed it.
    std::size_t max_nodes = std::size_t{1} << 20;
};

/// Counts of what the tree holds.
struct OctreeStats {
    std::size_t nodes = 0, empty = 0, full = 0, ambiguous = 0;
    std::size_t distinct_tapes = 0;     ///< pruned tapes actually stored
    std::size_t tape_instructions = 0;  ///< summed over the distinct tapes
    std::size_t full_tape_instructions = 0;
    std::size_t bytes = 0;  ///< nodes + distinct tapes, approximately
    double build_seconds = 0;
};

class Octree {
  public:
    enum class State : std::uint8_t { Empty, Full, Ambiguous, Branch };

    /// Builds the tree of `tape` (which must outlive the Octree) over `bounds`.
    Octree(const expr::Tape& tape, const std::array<Interval, 3>& bounds,
           const OctreeOptions& options = {});

    /// The first root along the ray, certified (see the file contract).
    RayResult certified(const Ray& ray, const solvers::CertifiedOptions& options) const;
    /// Sphere tracing with local constants inside the bounds: Hit when |f|/λ < epsilon (see the
    /// file contract); options.budget and options.seconds bound the whole ray.
    RayResult sphere(const Ray& ray, const TraceOptions& options) const;

    /// An ambiguous leaf met by a ray, with the parameter segment [t0, t1] it covers.
    struct Segment {
        std::uint32_t node;
        double t0, t1;
    };
    /// The ambiguous leaves met by the ray on [t0, t1] (clip to the bounds first: ray_box), in
    /// order of entry; consecutive segments overlap by a few ulps (see the file contract).
    void walk(const Ray& ray, double t0, double t1, std::vector<Segment>& out) const;
    /// The box of node `node` (a leaf index from walk()).
    const std::array<Interval, 3>& box(std::uint32_t node) const { return nodes_[node].box; }
    /// The pruned tape of an ambiguous leaf, valid on inflate(box(node)).
    const expr::Tape& leaf_tape(std::uint32_t node) const { return *tapes_[nodes_[node].tape]; }
    /// The Lipschitz bound of an ambiguous leaf over inflate(box(node)).
    double leaf_lambda(std::uint32_t node) const { return nodes_[node].lambda; }
    /// The number of nodes (valid indices are 0 … node_count() − 1).
    std::size_t node_count() const noexcept { return nodes_.size(); }
    /// The state of a node.
    State state(std::uint32_t node) const { return nodes_[node].state; }
    /// The full tape the tree was built from.
    const expr::Tape& tape() const noexcept { return tape_; }

    const OctreeStats& stats() const noexcept { return stats_; }
    const std::array<Interval, 3>& bounds() const noexcept { return bounds_; }

  private:
    struct Node {
        std::array<Interval, 3> box;
        State state = State::Ambiguous;
        std::uint32_t first_child = 0;  ///< Branch: index of the 8 children
        std::uint32_t tape = 0;         ///< Ambiguous: index into tapes_
        double lambda = 0;              ///< Ambiguous: local Lipschitz bound
    };
    void build();

    const expr::Tape& tape_;
    std::array<Interval, 3> bounds_;
    OctreeOptions options_;
    std::vector<Node> nodes_;
    std::vector<std::shared_ptr<const expr::Tape>> tapes_;
    OctreeStats stats_;
};

/// The parameter interval where o + t·d lies in `box`, rounded outward; empty if it misses.
Interval ray_box(const Ray& ray, const std::array<Interval, 3>& box);

/// The box widened by 2⁻²⁰ of its size on every side (rounded outward): where a leaf's pruned
/// tape and λ are valid, so that points a few ulps outside the cell stay covered.
std::array<Interval, 3> inflate(const std::array<Interval, 3>& box);

/// True when every point o + t·d, t in [t0, t1], provably lies in `box`.
bool segment_inside(const Ray& ray, double t0, double t1, const std::array<Interval, 3>& box);

/// A certified solve of the piece [a, b] of a ray (a cell's segment, or part of one) that ended
/// Unknown, not for want of budget, with its candidate [r.t_lo, r.t_hi] touching an end of the
/// piece (within the candidate's width plus 16 ulps): the zero it could not decide may sit on the
/// face between two cells, where each cell's solve sees only half of the sign change (the points
/// with a decided sign lie in the neighbour). Returns true and the window [lo, hi] ⊇ the
/// candidate, reaching one piece length (at least four candidate widths) to each side within
/// [ray.tmin, ray.tmax], on which the caller re-decides the candidate with the full tape: since
/// every zero of the piece lies in the candidate and nothing before r.t_lo is possible, a Miss
/// there makes the piece and the window free of zeros, and a Hit [h, k] is the first zero of the
/// ray in [max(h, r.t_lo), k]. Returns false when the candidate touches no end.
bool face_window(const Ray& ray, double a, double b, const RayResult& r, double& lo, double& hi);

}  // namespace certray::tracers
