// tracers/segment_trace.h — segment tracing (Galin, Guérin, Paris, Peytavie 2020) with local
// Lipschitz bounds computed from the DAG, never stepping past the first root.
//
// Contract: from the current t, a candidate segment T = [t, t + s] is enclosed by one evaluation of
// g and g′ in Dual<Interval, 1> (g′ = ∇f·d, so λ_T = max |G′(T)| is the directional Lipschitz
// bound of g on T, in units of t, derived from the expression itself). If 0 ∉ G(T) (g proven
// defined, continuous and nonzero on T) the whole segment is skipped; otherwise the step is
// min(s, |g(t)|/λ_T), with |g(t)| the mignitude of an interval enclosure at the exact real t, and
// every rounding taken downward. After a full step s doubles; after a partial step δ the next
// segment is max(2δ, s/2) (Galin's growth factor 2, with a gentler shrink).
// The first segment is the whole [tmin, tmax] (for tmax = +inf, the tail [tmin, +inf)), so a ray
// that is cleanly away from the surface is a Miss after one evaluation.
// Answers: Hit at t when |g(t)|/λ < epsilon, λ = λ_T/‖d‖ the bound in scene units (approximate,
// as for sphere tracing); Miss when the segments cover [tmin, tmax] (proven); Unknown when the
// budget is spent, g is undefined at a point, or the step vanishes. Counts: one interval
// evaluation per point, one gradient evaluation per segment. Reference:
// docs/theory/segment_tracing.md.
#pragma once

#include "expr/tape.h"
#include "solvers/ray.h"
#include "tracers/march.h"

namespace certray::tracers {

/// Segment tracing with local bounds from the DAG's interval derivative (see the file contract).
RayResult segment_trace(const expr::Tape& tape, const Ray& ray, const TraceOptions& options);

}  // namespace certray::tracers
