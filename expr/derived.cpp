// expr/derived.cpp — Lipschitz bounds from the interval gradient and root forms.
#include "expr/derived.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "interval/grad_bound.h"

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
    std::array<double, 3> mag{};
    double m = 0;
    for (int i = 0; i < 3; ++i) {
        const Interval& g = grad[i];
        if (g.is_empty() || !g.defined) return kInf;
        mag[i] = std::max(std::fabs(g.lower()), std::fabs(g.upper()));
        if (!std::isfinite(mag[i])) return kInf;
        m = std::max(m, mag[i]);
    }
    if (m == 0) return 0;
    if (m > 0x1p-400 && m < 0x1p400) {
        // No square can overflow, and any that underflows is below 2⁻⁸⁰⁰·m²: rounding everything
        // upward in one scope bounds the norm directly (the common case, no rescaling).
        RoundingScope scope;
        const double sum = mag[0] * mag[0] + mag[1] * mag[1] + mag[2] * mag[2];
        return std::sqrt(sum);
    }
    // ‖g‖ = 2^e ‖g / 2^e‖ with 2^e near the largest component, so that the squares neither
    // underflow (a gradient of 1e-300 would otherwise give a bound of 1e-162) nor overflow.
    const int e = std::ilogb(m);
    Interval sum(0.0);
    for (double g : mag) {
        Interval x(g);
        // 2^-e in at most two exact factors (2^1074 alone would overflow).
        for (int k = -e; k != 0;) {
            const int step = std::clamp(k, -1000, 1000);
            x = x * Interval(std::ldexp(1.0, step));
            k -= step;
        }
        sum = sum + square(x);
    }
    return (sqrt(sum) * Interval(std::ldexp(1.0, e))).upper();
}

double lipschitz_bound(const Tape& tape, const std::array<Interval, 3>& box) {
    thread_local std::vector<GradBound> regs;
    if (regs.size() < tape.registers()) regs.resize(tape.registers());
    std::array<Interval, 3> parts;
    double lip = 0;
    {
        RoundingScope scope;
        const std::array<GradBound, 3> p{GradBound::variable(UpInterval(box[0]), 0),
                                         GradBound::variable(UpInterval(box[1]), 1),
                                         GradBound::variable(UpInterval(box[2]), 2)};
        detail::run<GradBound>(tape.instrs(), p, regs.data());
        const GradBound& out = regs[tape.output()];
        if (!out.d.a.defined) return std::numeric_limits<double>::infinity();
        lip = out.lip;
        for (int i = 0; i < 3; ++i) parts[i] = Interval(out.d.v[i]);
    }
    // The components' norm scaled against underflow (GradBound's own is only rounded up).
    return std::min(lip, norm_bound(parts));
}

double lipschitz_bound_segment(const Tape& tape, const std::array<double, 3>& p,
                               const std::array<double, 3>& q) {
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) box[i] = Interval(std::min(p[i], q[i]), std::max(p[i], q[i]));
    return lipschitz_bound(tape, box);
}

}  // namespace certray::expr
