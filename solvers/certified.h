// solvers/certified.h — the certified first root along a ray: interval bisection (Snyder 1992)
// with interval Newton (Moore) for existence, uniqueness and quadratic convergence.
//
// Contract (solvers/ray.h, docs/design.md "Certification semantics"): a Hit [t_lo, t_hi] means g
// has a zero in [t_lo, t_hi] and none in [tmin, t_lo); a Miss means none in [tmin, tmax]; otherwise
// Unknown. Zeros are proven by a sign change between two points where g is proven defined and
// continuous on the whole segment between them (the interval decoration), by an exact zero, or by
// the interval Newton test N(T) ⊂ int T. Exclusion uses 0 ∉ G(T), or N(T) ∩ T = ∅. Reference:
// docs/theory/certified.md.
#pragma once

#include <cstdint>

#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::solvers {

struct CertifiedOptions {
    /// The most whole-tape evaluations (of any kind) spent on one ray; then the answer is Unknown.
    std::uint64_t budget = 20000;
    /// Also enclose g over each parameter interval T by the affine form of g in T's one noise
    /// symbol, and use the intersection with the interval enclosure (two evaluations, counted).
    bool affine = false;
    /// On a polynomial scene, also re-decide a Hit wider than 4 ulps with the exact oracle (about
    /// 100 µs per such ray on the Barth sextic); an Unknown is re-decided either way. Images need
    /// no 4-ulp depths (docs/benchmarks.md, "Coherent certified rendering").
    bool tighten = true;
    /// A Hit enclosure is narrowed until it is a few ulps wide or, when this is > 0, until
    /// t_hi − t_lo ≤ hit_width · max(|t_lo|, |t_hi|) (an image needs no 4-ulp depths). The answer
    /// keeps its meaning; only the enclosure may be wider. A Hit left wider than 4 ulps this way is
    /// not narrowed by the exact oracle either.
    double hit_width = 0;
    /// As hit_width, an absolute width: a Hit may also stop once t_hi − t_lo ≤ hit_width_absolute
    /// (when > 0; a heightmap's depth resolution).
    double hit_width_absolute = 0;
};

/// The first root of g(t) = f(o + t·d) on [ray.tmin, ray.tmax], certified (see the contract).
/// When the interval search ends Unknown, or with a Hit wider than 4 ulps (and options.tighten),
/// and the tape is a polynomial (solvers/exact.h, is_polynomial), the exact rational oracle
/// re-decides within what is left of the budget and its answer is returned, with its evaluations
/// added (a tangent root becomes a Hit of adjacent doubles). Thread-safe: each thread uses its own
/// scratch space, allocated once.
RayResult certified_first_root(const expr::Tape& tape, const Ray& ray,
                               const CertifiedOptions& options = {});

/// The same search with every evaluation of g and g′ in MpfrInterval at 256 bits, rounded outward
/// to doubles: signs are decided where double intervals cannot, so a simple root's enclosure is
/// at most a few ulps wide, usually adjacent doubles. The reference (ground truth) of the tests
/// and benchmarks; about two orders of magnitude slower.
RayResult certified_first_root_reference(const expr::Tape& tape, const Ray& ray,
                                         const CertifiedOptions& options = {});

}  // namespace certray::solvers
