// expr/derived.cpp — Lipschitz bounds from the interval gradient.
#include "expr/derived.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace certray::expr {

// One evaluator per thread, so that the per-region queries of tracers allocate nothing.
Dual<double, 3> gradient(const Tape& tape, const std::array<double, 3>& p) {
    using D = Dual<double, 3>;
    thread_local Evaluator<D> e;
    return e(tape, {D::variable(p[0], 0), D::variable(p[1], 1), D::variable(p[2], 2)});
}

Dual<Interval, 3> interval_gradient(const Tape& tape, const std::array<Interval, 3>& box) {
    using D = Dual<Interval, 3>;
    thread_local Evaluator<D> e;
    return e(tape, {D::variable(box[0], 0), D::variable(box[1], 1), D::variable(box[2], 2)});
}

double norm_bound(const std::array<Interval, 3>& grad) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    Interval sum(0.0);
    for (const Interval& g : grad) {
        if (g.is_empty() || !g.defined) return kInf;
        const double mag = std::max(std::fabs(g.lower()), std::fabs(g.upper()));
        if (!std::isfinite(mag)) return kInf;
        sum = sum + square(Interval(mag));
    }
    return sqrt(sum).upper();
}

double lipschitz_bound(const Tape& tape, const std::array<Interval, 3>& box) {
    const Dual<Interval, 3> d = interval_gradient(tape, box);
    if (!d.a.defined) return std::numeric_limits<double>::infinity();
    return norm_bound(d.v);
}

double lipschitz_bound_segment(const Tape& tape, const std::array<double, 3>& p,
                               const std::array<double, 3>& q) {
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) box[i] = Interval(std::min(p[i], q[i]), std::max(p[i], q[i]));
    return lipschitz_bound(tape, box);
}

}  // namespace certray::expr
