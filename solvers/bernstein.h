// solvers/bernstein.h — certified first root of a polynomial with interval coefficients by
// Bernstein subdivision and Bézier clipping.
//
// Contract (solvers/ray.h, docs/design.md "Certification semantics"), for every polynomial p whose
// power-basis coefficients lie in the given intervals: Hit [lo, hi] means p has a zero in [lo, hi]
// and none in [tmin, lo); Miss means none in [tmin, tmax]; Unknown [lo, hi] means none in
// [tmin, lo) and a possible zero in [lo, hi] that is neither proven nor excluded (multiple or
// tangent roots, too-wide coefficients, exhausted steps). Zeros are proven by a certain sign change
// of the interval Horner value between two points, or by an exact zero enclosure [0, 0].
// References: T. Nishita, T. W. Sederberg, M. Kakimoto, "Ray tracing trimmed rational surface
// patches", SIGGRAPH 1990 (Bézier clipping); T. Nishita, E. Nakamae, "A method for displaying
// metaballs by using Bézier clipping", Eurographics 1994; docs/theory/bernstein.md.
#pragma once

#include <span>

#include "interval/interval.h"
#include "solvers/ray.h"

namespace certray::solvers {

struct BernsteinOptions {
    /// Subdivision or clipping steps before the answer is Unknown.
    unsigned max_steps = 4000;
};

/// First root on [tmin, tmax] of every polynomial whose power-basis coefficients (c[k] for t^k,
/// degree = c.size() − 1) lie in the given intervals. Hit [lo, hi]: each such polynomial has a zero
/// in [lo, hi] and none in [tmin, lo); Miss: none in [tmin, tmax]; Unknown: candidate interval.
/// Infinite ends are made finite by the Cauchy root bound when the leading coefficient is certainly
/// nonzero (else Unknown). `evals` stays zero. Thread-safe; no allocation once warmed up.
RayResult first_root_bernstein(std::span<const Interval> c, double tmin, double tmax,
                               const BernsteinOptions& options = {});

}  // namespace certray::solvers
