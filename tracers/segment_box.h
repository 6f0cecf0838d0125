// tracers/segment_box.h — boxes that hold ray segments, rounded outward (the coherent walk's).
//
// Contract: inside a RoundingScope (upward mode), segment_box(olo, ohi, dlo, dhi, a, b) holds
// o + t·d for every origin o in [olo, ohi], direction d in [dlo, dhi] and t in [a, b]; ray_box is
// the same box for one ray (a point origin and direction), bit for bit, computed with two products
// and two sums per axis instead of an interval product. Tests: tests/tracers/coherent_test.cpp.
#pragma once

#include <array>

#include "interval/interval.h"
#include "solvers/ray.h"

namespace certray::tracers {

/// The box [o] + [a, b]·[d] for origins in [olo, ohi] and directions in [dlo, dhi], rounded
/// outward (in the walk's upward mode): it holds o + t·d for every such ray and t in [a, b].
inline std::array<UpInterval, 3> segment_box(const double* olo, const double* ohi,
                                             const double* dlo, const double* dhi, double a,
                                             double b) {
    const UpInterval t(a, b);
    std::array<UpInterval, 3> box;
    for (int c = 0; c < 3; ++c)
        box[c] = UpInterval(olo[c], ohi[c]) + t * UpInterval(dlo[c], dhi[c]);
    return box;
}

/// The bounds of the box o + [p, q]·d of one ray (p ≤ q), rounded outward in the walk's upward
/// mode: per axis [o + (d ≥ 0 ? p : q)·d rounded down, o + (d ≥ 0 ? q : p)·d rounded up], the
/// bounds segment_box gives for a point origin and direction, with two products and two sums
/// instead of an interval product (a rounding down is the negation of a rounding up of the
/// negated operands).
[[gnu::always_inline]] inline void ray_bounds(const Ray& ray, double p, double q, double* lo,
                                              double* hi) {
    for (int c = 0; c < 3; ++c) {
        const double o = ray.o[c], d = ray.d[c];
        const double tl = d >= 0 ? p : q, th = d >= 0 ? q : p;
        lo[c] = -(detail::opaque(-o) + detail::opaque(-tl * d));  // ↓(o + ↓(tl·d))
        hi[c] = detail::opaque(o + detail::opaque(th * d));       // ↑(o + ↑(th·d))
    }
}

/// ray_bounds as intervals.
inline std::array<UpInterval, 3> ray_box(const Ray& ray, double p, double q) {
    double lo[3], hi[3];
    ray_bounds(ray, p, q, lo, hi);
    std::array<UpInterval, 3> box;
    for (int c = 0; c < 3; ++c) box[c] = UpInterval(lo[c], hi[c]);
    return box;
}

}  // namespace certray::tracers
