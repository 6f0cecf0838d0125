// solvers/solid.h — the certified first entry into the solid {f < 0} along a ray: leftmost-first
// interval bisection, with mean-value (Newton-like) reaches from the left end of each interval.
//
// Contract (the "solid" surface, docs/design.md and docs/theory/solid.md). For g(t) = f(o + t·d)
// on [tmin, tmax]:
//   Hit [t_lo, t_hi]: g(t_hi) < 0 is proven by a point evaluation at t_hi (an enclosure of g at
//       that point that is defined and < 0; tmin ≤ t_lo ≤ t_hi ≤ tmax), and g ≥ 0 is proven on
//       [tmin, t_lo) by enclosures that are defined (f defined and continuous there) with lower
//       bound ≥ 0. So the first entry inf{t : g(t) < 0} lies in [t_lo, t_hi].
//   Miss: g ≥ 0 is proven on all of [tmin, tmax] in the same way (regions where f ≡ 0 pass).
//   Unknown [t_lo, t_hi]: g ≥ 0 is proven on [tmin, t_lo); in [t_lo, t_hi] nothing is decided
//       (a tangency, points where f is undefined or discontinuous, a spent budget); when the
//       search ended without spending the budget, g ≥ 0 is also proven on (t_hi, tmax].
// Where f is undefined nothing is proven: a ray through such a region is never a Miss.
// Reference: docs/theory/solid.md.
#pragma once

#include <cstdint>

#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::solvers {

struct SolidOptions {
    /// The most whole-tape evaluations (of any kind) spent on one ray; then the answer is Unknown
    /// (or a Hit with the enclosure proven so far, when a point inside is already proven).
    std::uint64_t budget = 20000;
    /// Also enclose g over each parameter interval T by the affine form of g in T's one noise
    /// symbol, and use the intersection with the interval enclosure (two evaluations, counted).
    bool affine = false;
    /// 0: a hit is narrowed as far as the search goes (a few ulps at a simple crossing). > 0: it
    /// stops once t_hi − t_lo ≤ hit_width · max(|t_lo|, |t_hi|) (an image needs no few-ulp depths);
    /// the answer keeps its meaning.
    double hit_width = 0;
    /// As hit_width, an absolute width: a hit may also stop once t_hi − t_lo ≤ hit_width_absolute
    /// (when > 0).
    double hit_width_absolute = 0;
};

/// The first entry of the ray o + t·d, t ∈ [ray.tmin, ray.tmax], into {f < 0}, certified (see the
/// contract above). t_hi is always the proven-inside point of a Hit; t is the midpoint of
/// [t_lo, t_hi]. A ray starting inside gives Hit [tmin, tmin]. At a simple crossing from + to −
/// the enclosure is a few ulps wide. tmax may be +inf. Thread-safe: each thread uses its own
/// scratch space, allocated once; no allocation per ray after that.
RayResult solid_first_entry(const expr::Tape& tape, const Ray& ray,
                            const SolidOptions& options = {});

/// The same search with every evaluation of g and g′ in MpfrInterval at 256 bits, rounded outward
/// to doubles: signs are decided where double intervals cannot, so a simple crossing's enclosure
/// is usually two adjacent doubles. The reference of the tests; about two orders of magnitude
/// slower.
RayResult solid_first_entry_reference(const expr::Tape& tape, const Ray& ray,
                                      const SolidOptions& options = {});

}  // namespace certray::solvers
