// tracers/sphere_trace.h — sphere tracing (Hart 1996) and enhanced sphere tracing (Keinert et al.
// 2014) with a Lipschitz bound λ, made rigorous: neither ever steps past the first root.
//
// Contract: λ must bound the Lipschitz constant of f (‖∇f‖₂) on a region containing the traced
// segment [o + tmin·d, o + tmax·d] (the caller clips the ray to the region where λ holds, e.g.
// the scene bounds given to global_lipschitz). At each point, g(t) is enclosed by interval
// arithmetic at the exact real t, and the step |g|/(λ‖d‖) is rounded down, as is t + step: so
// every t visited is ≤ the first root of g on [tmin, tmax]. Where λ is loose the step is the
// larger min(|g|/λ_ρ, ρ), λ_ρ a local bound over the point's box inflated by ρ (a distance bound
// too; ρ doubles from step to step while it helps; docs/theory/sphere_tracing.md).
// Answers: Hit at t (t_lo = t_hi = t) when |f|/λ < epsilon there (an approximate hit, no root
// proven: the surface is within about epsilon only where λ is close to |∇f|; a loose λ can stop
// the tracer farther away, never beyond the first root); Miss when a step passes tmax (proven: no
// root on [tmin, tmax] given λ); Unknown when the budget is spent (notably for tmax = +inf with
// no surface ahead: the tracer never proves a miss to infinity), when g is undefined at a point,
// or when λ is NaN, negative or infinite; with options.hand_over_crawls, also where the bound falls
// below epsilon while the first-order estimate puts the surface farther than 4·epsilon (a loose
// bound: the caller goes on by segment tracing from there). Each step costs one interval evaluation
// (evals.interval), and one interval-gradient evaluation (evals.gradient) where a local bound is
// tried. Enhanced: steps of (1 + kappa)·|g|/λ; when the unbounding spheres of the old and the new
// point do not overlap (r_old + r_new < step length) it goes back and takes the plain step, and
// stays plain for the rest of the ray (Keinert's rule), so the guarantee is kept. Reference:
// docs/theory/sphere_tracing.md.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"
#include "tracers/march.h"

namespace certray::tracers {

/// A sound bound on the Lipschitz constant of f over `bounds` (expr::lipschitz_bound): +inf when
/// f is not proven defined and continuous on the box.
double global_lipschitz(const expr::Tape& tape, const std::array<Interval, 3>& bounds);

/// Sphere tracing with the Lipschitz bound `lambda` (see the file contract).
RayResult sphere_trace(const expr::Tape& tape, const Ray& ray, double lambda,
                       const TraceOptions& options);

/// Enhanced (over-relaxed) sphere tracing with `lambda` and options.kappa (see the contract).
RayResult enhanced_trace(const expr::Tape& tape, const Ray& ray, double lambda,
                         const TraceOptions& options);

/// sphere_trace and enhanced_trace on f's region-pruned tapes (tracers/region_tapes.h): each
/// value, local bound and estimate is evaluated on the tape of its point's or box's region, the
/// same function there (λ, over the region traced, is the caller's as above). The same contract
/// and the same steps up to the roundings of the shorter tapes.
RayResult sphere_trace(const RegionTapes& regions, const Ray& ray, double lambda,
                       const TraceOptions& options);
RayResult enhanced_trace(const RegionTapes& regions, const Ray& ray, double lambda,
                         const TraceOptions& options);

/// The evaluations after which the tracers that combine sphere tracing with segment tracing hand
/// the rest of a piece still undecided to segment tracing: sphere tracing's free radius shrinks
/// along a ray that grazes the surface or where λ is loose, segment tracing bounds g along the ray
/// itself; both never step past the first root. Per part of a ray inside the bounds (bvh; bear,
/// 256²: 64 steps 7.9 s, 32 steps 6.3 s), and per octree cell (a cell is small: sphere tracing
/// crosses or converges in a few steps where its λ serves; bear, 128²: 64 per cell 1.84 s, 16 per
/// cell 0.84 s).
inline constexpr std::uint64_t kSphereSteps = 32;
inline constexpr std::uint64_t kSphereStepsPerCell = 16;

namespace detail {

/// What sphere tracing's local bounds carry from one point to the next: the last distance bound
/// (ρ is twice it) and whether a local λ still beats the global one on this ray.
struct LocalBounds {
    double previous = 0;
    bool useful = true;
    /// While not useful: a local bound is tried again once the global bound falls below this.
    double retry_below = 0;
    /// Whether the gradient at a point has been compared with λ on this ray (tape_distance: where
    /// ‖∇f(p)‖ ≥ λ/2, λ is tight and no local bound is tried until the bound falls below epsilon).
    bool probed = false;
    /// The box of the last local bound computed on this ray and λ over it (tape_distance reuses
    /// it while the point's box inflated by ρ/2 or more fits inside: detail::LocalBox).
    LocalBox box;
};

/// sphere_trace continuing from `local` and leaving it as it ends: a caller tracing consecutive
/// pieces of one ray (the octree's cells) hands it from piece to piece, so that the local
/// bounds' ρ need not grow again from 16·epsilon in every piece.
RayResult sphere_trace(const expr::Tape& tape, const Ray& ray, double lambda,
                       const TraceOptions& options, LocalBounds& local);

/// A signed distance bound at the exact point o + t·d: an enclosure of a value whose sign is f's
/// and whose magnitude is at most the distance to the surface (within the region where it holds).
/// Empty or undefined: unknown. Evaluations beyond the one the loop counts go to `evals`.
using DistanceAt = std::function<Interval(double t, EvalCounts& evals)>;

/// A first-order estimate of the distance to the surface at o + t·d (|f| / ‖∇f‖ in double): not a
/// bound, a sanity check of a hit.
using EstimateAt = std::function<double(double t, EvalCounts& evals)>;

/// The first-order estimate |f(p)| / ‖∇f(p)‖ of `tape` at p = o + t·d (0 where f(p) = 0; +inf
/// where ∇f(p) = 0 or f is undefined); one gradient evaluation.
double first_order_distance(const expr::Tape& tape, const Ray& ray, double t);

/// The loop of sphere_trace / enhanced_trace over any distance bound (bounding volumes use it);
/// `tape` answers degenerate rays (‖d‖ = 0 or tmin = tmax). Same contract as sphere_trace. Where
/// the bound falls below epsilon, a hit is answered only if `estimate` (when given) is at most
/// 4·epsilon too: a bound that is merely loose then makes the tracer crawl until its budget ends
/// (unknown) instead of answering a hit far from any surface.
RayResult trace_distance(const DistanceAt& distance, const EstimateAt& estimate,
                         const expr::Tape& tape, const Ray& ray, const TraceOptions& options,
                         double kappa);

}  // namespace detail

}  // namespace certray::tracers
