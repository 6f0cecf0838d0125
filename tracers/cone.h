// tracers/cone.h — cone marching: the free balls of sphere tracing shared by the rays of a screen
// tile, so that the Lipschitz tracers (sphere, enhanced, segment, bvh, octree) start each ray near
// its surface instead of at the camera.
//
// Contract: march(tile) raises each active ray's tmin to a parameter before which the ray is
// proven free of zeros of f given the Lipschitz bounds (the same proofs the tracers make), and
// marks Free the rays proven free on their whole segment [tmin, tmax] (misses); it never raises a
// ray past its first root. The rays must be clipped to the bounds (clip_ray) and all of a tile's
// active rays' points on their segments lie in the bounds. At a centre point p in the bounds (an
// exact double), an enclosure v of f(p) that excludes 0 and a Lipschitz bound λ of f over a convex
// box C ∋ p give the free radius D = |v|/λ (rounded down): f has no zero at any point q of C with
// ‖q − p‖ < D, since |f(q) − f(p)| ≤ λ‖q − p‖ < |f(p)| on the segment [p, q] ⊂ C. C is the
// bounds (λ: expr::lipschitz_bound over them, computed once) or the box of half-side ρ around p
// cut to the bounds (a local λ; then D ≤ ρ, as tracers/march.h's local_distance_bound), tried
// where the global D is below ρ/2 and ‖∇f(p)‖ (in double) below λ/4 — else no local λ could beat
// the global one by 4×, too little for its cost. The box of
// every active ray's points over [t, t + δ] (o + [t, t + δ]·d over the rays' o and d, outward
// rounded) lies inside that ball when its farthest corner from p is nearer than D (rounded up):
// then every active ray is free on [t, t + δ]. Steps are taken front to back from the least tmin
// of the tile's rays, so each step extends a proof that starts before every ray's segment. A tile
// whose cone is wider than half its free radius, or whose centre value may be 0 or is undefined,
// is split into four (its rays keep the parameter reached); a single ray, or a tile after
// `max_steps` steps, stops there. The bounds are inflated by 2⁻³⁰ of their size (clip_ray's
// segments may reach a few ulps beyond the box) before λ is taken. Each value is one interval
// evaluation and each local λ one gradient evaluation, on the tape of its region
// (tracers/region_tapes.h: the same function there). The march works in round-to-nearest with
// directed operations where a bound needs them (the library's environment).
// Reference: Amanatides 1984 (cones), Hart 1996 (free balls); docs/theory/cone.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"
#include "tracers/camera.h"
#include "tracers/region_tapes.h"

namespace certray::tracers {

/// The rays of one screen tile, row-major, and what the march made of them.
struct ConeTile {
    enum State : std::uint8_t {
        Outside,  ///< the ray misses the bounds (not marched)
        Active,   ///< to be traced from ray.tmin (raised by the march)
        Free,     ///< proven free of zeros on its whole segment: a miss
    };
    unsigned width = 0, height = 0;
    std::vector<Ray> rays;
    std::vector<State> state;
    /// The march's evaluations attributed to each ray: each step's shared among the rays active
    /// in its tile (the steps AOV); the totals are march()'s return value.
    std::vector<double> share;
};

/// The knobs of the march.
struct ConeOptions {
    /// Most steps of one tile before its rays stop there (a bound on the work of one tile).
    unsigned max_steps = 128;
    /// The least distance bound tried by a local λ (ρ ≥ 16·epsilon, as sphere tracing's).
    double epsilon = 1e-6;
    /// Off: the global λ alone (no gradient evaluation at all).
    bool local_bounds = true;
};

/// The march over one scene (see the file contract). Thread-safe after construction.
class ConeMarch {
  public:
    /// `tape` must outlive this object; `bounds` finite and non-empty.
    ConeMarch(const expr::Tape& tape, const Box3& bounds, const ConeOptions& options = {});

    /// Marches the tile's Active rays (see the file contract); returns its evaluations.
    EvalCounts march(ConeTile& tile) const;

    /// λ over the inflated bounds (+inf when f is not proven Lipschitz there).
    double lambda() const noexcept { return lambda_; }
    /// The region-pruned tapes the march evaluates on (over the inflated bounds).
    const RegionTapes& regions() const noexcept { return regions_; }

  private:
    struct Walk;
    void node(Walk& w, unsigned i0, unsigned j0, unsigned i1, unsigned j1, double t,
              double previous) const;

    const expr::Tape& tape_;
    std::array<Interval, 3> within_;
    ConeOptions options_;
    RegionTapes regions_;
    double lambda_;
};

}  // namespace certray::tracers
