// tracers/segment_trace.h — segment tracing (Galin, Guérin, Paris, Peytavie 2020) with local
// bounds derived from the DAG, never stepping past the first root.
//
// Contract: each step evaluates the tape once in a second-order ray jet (segment_model): at the
// current t it encloses g(t) and g′(t), and over the segment T = [t, t + s] it encloses G(T),
// G′(T) and G″(T), the last usable only where g′ is proven absolutely continuous on T (kinks of
// min/max/abs are tracked; one whose derivative jump is multiplied by an exact 0, as in
// max(k, 0)³, is smooth). Every bound is an outward-rounded enclosure computed from the DAG
// itself; nobody derives a per-primitive bound. With σ the sign of g(t) and h = σ·g, the safe
// step δ is the first zero of the larger of the lower bounds
//     h(t) + τ·inf σG′(T)                                  (first order: Lipschitz on T),
//     h(t) + τ·inf σg′(t) + τ²/2·inf σG″(T)                (second order, where smooth),
// rounded down, so g has no zero on [t, t + δ): |g|/λ with λ the bound on T is a true distance
// bound along the segment. T is skipped whole when 0 ∉ G(T), g defined on all of T or not (a
// zero needs g defined: a pole or a gap of f's domain that the enclosure bounds away from 0 is
// passed, as by the certified solver), or when δ exceeds |T|. Where g is not proven defined at
// t, or not continuous on T, the segment shrinks. The smallest τ* ≤ |T| where the matching
// UPPER bound is proven ≤ 0 proves a zero in (t, t + τ*] (g continuous, h(t) > 0 ≥ h(t + τ*)).
// Switch cuts: during the pass, a min/max/abs whose branches overlap on T is replaced by the
// branch taken at t where the safe step of (a − b) proves that branch stays taken — on all of T,
// or on T cut to [t, t + τ] when τ ≥ switch_floor·|T| (the model then describes the cut T).
// Pruning: each pass runs on the tape pruned (expr/prune.h) to the smallest earlier segment
// holding T; a tape longer than 256 instructions, or a pruned list longer than 64, is first swept
// (interval evaluation over T, counted in evals.interval): if that proves 0 ∉ G(T) the step ends
// there, else the jet pass runs on the list pruned by the sweep.
// Answers: Hit [t + δ, t + τ*] (t = t_lo) when τ* − δ ≤ epsilon/‖d‖: a zero is proven in it and
// none lies before it (certified); Hit at t (t_lo = t_hi) when |g(t)| cannot be told from 0, or,
// when no zero can be proven (tangency), when δ‖d‖ < epsilon on a segment no longer than
// 4·epsilon/‖d‖ (approximate, as for sphere tracing); Miss when the skipped segments cover
// [tmin, tmax] (proven); Unknown when the budget or the time is spent, or the step (or a
// segment shrunk where g has no bound) vanishes. Every hit is at or before the first root.
// Counts: one evals.gradient per jet pass (it computes the field value g(t), the authors' count,
// and the segment bounds together) and one evals.interval per sweep.
// Step rule (Galin's Algorithm 1 plus interval exclusion): the first segment is [tmin, tmax];
// after a skipped segment the next is `growth` times longer (next_factor × the distance to the
// next switch seen, after a cut one; the rest of the ray when within 1/tail of it); after a
// partial step δ it is max(growth_partial·δ, |T|·shrink), or the proven bracket [t + δ, t + τ*].
// Reference: Galin et al., "Segment Tracing Using Local Lipschitz Bounds", Eurographics 2020;
// docs/theory/segment_tracing.md.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"
#include "tracers/march.h"

namespace certray::tracers {

/// What one pass of the ray jet proves about g(t + τ) = f(o + (t + τ)·d) for τ ∈ [0, end − t].
struct SegmentModel {
    /// ⊇ {g(t)}; `.defined` iff f is proven defined at o + t·d.
    Interval g0;
    /// ⊇ the right derivative g′(t⁺) (at a kink of g: the hull of both one-sided derivatives).
    Interval g1;
    /// ⊇ {g(t + τ)}; `.defined` iff g is proven defined and continuous on the whole segment.
    Interval g;
    /// ⊇ {g′(t + τ)} wherever g′ exists (Clarke's generalised derivative at kinks).
    Interval dg;
    /// ⊇ {g″(t + τ)} wherever g″ exists.
    Interval ddg;
    /// g′ is proven absolutely continuous on the segment (no kink with a derivative jump), so
    /// g(t + τ) ∈ g0 + τ·g1 + τ²/2·ddg for every τ in [0, end − t] (when g.defined).
    bool smooth = false;
};

/// One pass of the second-order ray jet over the whole tape (no switch cut, no pruning; one
/// gradient evaluation): the enclosures of SegmentModel for t ≤ end (end may be +inf).
SegmentModel segment_model(const expr::Tape& tape, const Ray& ray, double t, double end);

/// The variant knobs of segment tracing (defaults: the production method). None of them weakens
/// the guarantee except `step_scale` > 1, which exists only so that tests can check that an
/// overstepping tracer is caught.
struct SegmentOptions {
    /// A name for benchmarks.
    const char* name = "default";
    /// Growth of the segment after a step that covered it (Galin's c; his code uses 1.5).
    double growth = 3.0;
    /// After a step over a segment cut at a switch: the next segment is next_factor × the
    /// distance to the next switch seen in that evaluation (0: growth as usual).
    double next_factor = 3.0;
    /// When the next segment would exceed tail × the rest of the ray, it is the rest of the ray.
    double tail = 0.25;
    /// After a partial step δ on T, the next segment is max(growth_partial·δ, |T|·shrink).
    double growth_partial = 2.0;
    double shrink = 0.5;
    /// Use the second-order bound where g′ is proven smooth (else first order only).
    bool second_order = true;
    /// Prove zeros with the upper bounds and stop on a bracket narrower than epsilon.
    bool certify = true;
    /// Switch-aware segments: a min/max/abs whose branches overlap on the segment is replaced by
    /// the branch taken at t when that branch provably stays taken on the segment, or on a cut
    /// segment no shorter than switch_floor × the proposed one (0: off).
    double switch_floor = 0.1;
    /// Run each pass on the tape pruned to the smallest earlier segment holding it, sweeping the
    /// whole tape first (see the file contract). Off: no sweep, every pass on the whole tape.
    bool prune = true;
    /// Also sweep (interval-evaluate and prune, one counted interval evaluation) pruned lists
    /// longer than this before their jet pass; the whole tape is always swept when longer than
    /// 256 instructions. A sweep proves many segments free without a jet pass and prunes the
    /// jet's list to the segment itself: fewer µs, more evaluations (particles, peers camera:
    /// 305 → 181 µs and 9.4 → 12.2 evaluations per ray; Fidget's bear about 2× faster).
    std::size_t sweep_pruned_above = 64;
    /// TEST ONLY: multiplies every safe step (2 ≙ λ/2). Must be 1 for a sound tracer.
    double step_scale = 1.0;
    /// When set (with `prune`), a pass over a segment whose box lies in a cell of these region
    /// tapes of f (tracers/region_tapes.h) starts from that cell's tape when it is shorter than the
    /// list the stack of pruned windows gives: the same function on the box, so the same bounds
    /// up to the roundings of the shorter list. Molecule, particles: the first passes of a ray
    /// otherwise sweep the whole tape (16,009 and 21,014 instructions).
    const RegionTapes* regions = nullptr;
    /// The first segment's length in space units; 0: the whole ray (Galin's rule). The registry
    /// sets it to a region cell's size where it gives `regions` (the first pass then fits a cell
    /// and its tape; the image's cone march has brought the ray near its surface): Lipschitz-
    /// Pruning's molecule at 256² 13.7 → 6.5 s, from the camera 98.6 → 74.3 s.
    double first_length = 0;
};

/// Segment tracing with the default variant (see the file contract).
RayResult segment_trace(const expr::Tape& tape, const Ray& ray, const TraceOptions& options);

/// Segment tracing with explicit variant knobs.
RayResult segment_trace(const expr::Tape& tape, const Ray& ray, const TraceOptions& options,
                        const SegmentOptions& variant);

/// The named variants measured by bench/segment_bench.cpp (the first is the default).
std::vector<SegmentOptions> segment_presets();

}  // namespace certray::tracers
