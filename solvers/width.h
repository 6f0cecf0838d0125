// solvers/width.h — how wide a parameter interval along a ray is, for the certified solvers.
//
// splittable: [a, b] still has a double strictly inside (its midpoint); narrow: [a, b] is at most
// 4 ulps wide at its magnitude (4·ulp(max(|a|, |b|))), or cannot be split: the target width of a
// certified hit enclosure (solvers/certified.cpp, solvers/analytic.cpp, solvers/exact.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "interval/interval.h"

namespace certray::solvers {

/// Whether [a, b] can still be split: its midpoint lies strictly inside.
inline bool splittable(double a, double b) {
    const double m = midpoint(Interval(a, b));
    return a < m && m < b;
}

/// Few ulps wide: at most 4 ulps at the magnitude of the larger bound, or not splittable.
inline bool narrow(double a, double b) {
    const double scale = std::max(std::fabs(a), std::fabs(b));
    const double lim = detail::step_up(scale, 4);
    return !splittable(a, b) || (std::isfinite(b - a) && b - a <= lim - scale);
}

/// Narrow, or at most `relative` times the larger magnitude wide (relative > 0), or at most
/// `absolute` wide (absolute > 0): how wide a hit enclosure may stay (an image needs no few-ulp
/// depths).
inline bool narrow_enough(double a, double b, double relative, double absolute = 0) {
    if (narrow(a, b)) return true;
    const double scale = std::max(std::fabs(a), std::fabs(b));
    if (!std::isfinite(scale)) return false;
    return (relative > 0 && b - a <= relative * scale) || (absolute > 0 && b - a <= absolute);
}

}  // namespace certray::solvers
