// solvers/analytic.h — first roots of piecewise-polynomial g(t) = f(o + t·d) along a ray: closed
// forms (degree ≤ 4) and certified Bernstein isolation, piece by piece (Wyvill 1990).
//
// The tape is evaluated over Poly<Interval> (interval/poly.h) on a parameter interval T: the
// result encloses the coefficients of one polynomial equal to g on all of T, or is invalid when a
// min/max/abs branch is undecided on T (then T is split, as blobs split at their kernels' support
// boundaries) or when g is not polynomial. On each piece, in order from tmin:
//   - `Mode::ClosedForm`: degree ≤ 4 by the robust closed forms of solvers/closed_form.h on the
//     midpoints of the coefficient enclosures (approximate: a Hit is a point t, not a proof);
//     higher degrees by the Bernstein route.
//   - `Mode::Bernstein`: solvers/bernstein.h on the coefficient enclosures — certified: a Hit
//     encloses a zero of g with none before it, a Miss proves none (solvers/ray.h semantics).
// Reference: docs/theory/closed_form.md, docs/theory/bernstein.md.
#pragma once

#include <cstdint>
#include <string>

#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::solvers {

struct AnalyticOptions {
    enum class Mode : std::uint8_t { ClosedForm, Bernstein };
    Mode mode = Mode::ClosedForm;
    /// The most Poly evaluations (pieces tried) per ray; then Unknown.
    std::uint64_t budget = 20000;
};

/// Empty when g is piecewise polynomial along every ray (every sqrt, exp, log, sin, cos and every
/// divisor is constant: independent of x, y, z), else a sentence naming the first instruction
/// that is not, e.g. "sqrt of a non-constant (instruction 7 of 11)".
std::string why_not_polynomial(const expr::Tape& tape);

/// The first root of g on [ray.tmin, ray.tmax] by the chosen mode. Each Poly evaluation counts as
/// one interval evaluation. A tape that is not polynomial gives Unknown on [tmin, tmax]; so does
/// an infinite tmax where a min/max/abs branch is undecided. Thread-safe.
RayResult analytic_first_root(const expr::Tape& tape, const Ray& ray,
                              const AnalyticOptions& options = {});

}  // namespace certray::solvers
