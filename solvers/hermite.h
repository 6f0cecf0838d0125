// solvers/hermite.h — approximate first root along a ray by piecewise cubic Hermite interpolation
// of g(t) = f(o + t·d) from sampled values and derivatives.
//
// Contract: approximate, not certified. g and g′ are sampled at equally spaced points; the first
// cubic Hermite piece with a root gives the answer (error O(h⁴) for a simple root of a smooth g).
// A feature thinner than the sample spacing (a thin shell, a grazing touch) can be missed.
// Reference: A. Sherstyuk, "Fast ray tracing of implicit surfaces", Computer Graphics Forum 18(2),
// 1999; docs/theory/hermite.md.
#pragma once

#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::solvers {

struct HermiteOptions {
    /// Number of pieces: g and g′ are sampled at samples + 1 points of [tmin, tmax].
    unsigned samples = 64;
    /// One Newton step on the real g from the cubic's root (one more gradient evaluation), kept
    /// when it stays inside the piece.
    bool newton = true;
};

/// Approximate first root: sample g and g′ at samples+1 equally spaced points of [tmin, tmax]
/// (Dual<double,1> evaluations of the tape, each counted in evals.gradient, stopping at the first
/// piece with a root), fit a cubic Hermite piece on each interval, and return the first root of the
/// first piece that has one (status Hit, t_lo = t_hi = t), else Miss. Not certified: it can miss a
/// thin feature between samples. tmax = +inf or non-finite samples → Unknown. Degenerate rays
/// (zero direction, tmin = tmax): g(tmin) = 0 → Hit, finite nonzero → Miss, else Unknown.
/// Thread-safe; no allocation per ray once a thread has seen the tape size.
RayResult hermite_first_root(const expr::Tape& tape, const Ray& ray,
                             const HermiteOptions& options = {});

}  // namespace certray::solvers
