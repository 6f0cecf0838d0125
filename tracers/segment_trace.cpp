// tracers/segment_trace.cpp — segment tracing with interval directional derivatives.
//
// Invariant: at the top of the loop g has no root on [tmin, t).
#include "tracers/segment_trace.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "expr/derived.h"
#include "expr/eval.h"
#include "interval/dual.h"

namespace certray::tracers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using D1 = Dual<Interval, 1>;

/// G(T) and G′(T) for T = [lo, hi] (hi may be +inf).
D1 g_segment(const expr::Tape& tape, const Ray& ray, double lo, double hi) {
    thread_local expr::Evaluator<D1> eval;
    const Interval tt(lo, hi);
    std::array<D1, 3> p;
    for (int i = 0; i < 3; ++i) {
        p[i] = D1(Interval(ray.o[i]) + tt * Interval(ray.d[i]), {Interval(ray.d[i])});
    }
    return eval(tape, p);
}

}  // namespace

RayResult segment_trace(const expr::Tape& tape, const Ray& ray, const TraceOptions& opt) {
    RayResult r;
    auto unknown = [&](double lo) {
        r.status = Status::Unknown;
        r.t_lo = r.t = lo;
        r.t_hi = ray.tmax;
        return r;
    };
    const double dn = detail::norm_up(ray.d);
    if (dn == 0 || ray.tmin == ray.tmax) return detail::degenerate(tape, ray);
    double t = ray.tmin;
    double s = kInf;  // the first segment is the whole ray
    double m = -1;    // |g(t)| lower bound, -1 when not yet evaluated at this t
    while (true) {
        if (r.evals.total() >= opt.budget) return unknown(t);
        if (m < 0) {
            const Interval v = detail::g_at(tape, ray, t);
            ++r.evals.interval;
            if (v.is_empty() || !v.defined) return unknown(t);
            m = detail::mignitude(v);
            if (m == 0) {
                r.status = Status::Hit;
                r.t_lo = r.t_hi = r.t = t;
                return r;
            }
            if (t >= ray.tmax) break;  // g(tmax) ≠ 0 and [tmin, tmax) is free
            if (r.evals.total() >= opt.budget) return unknown(t);
        }
        const double end = std::min(detail::add_up(t, s), ray.tmax);
        const D1 d = g_segment(tape, ray, t, end);
        ++r.evals.gradient;
        if (!d.a.is_empty() && d.a.defined && !possibly_zero(d.a)) {
            // g is continuous and nonzero on all of [t, end].
            if (end >= ray.tmax) break;
            t = end;
            s = 2 * s;
            m = -1;
            continue;
        }
        const Interval& dg = d.v[0];
        double lam = kInf;
        if (d.a.defined && !dg.is_empty() && dg.defined) {
            lam = std::max(std::fabs(dg.lower()), std::fabs(dg.upper()));
        }
        const double seg_lo = (Interval(end) - Interval(t)).lower();
        const double seg_hi = (Interval(end) - Interval(t)).upper();
        if (!(lam < kInf)) {
            // No bound on this segment (unbounded, or g′ undefined somewhere): shrink and retry.
            const double shorter = s == kInf ? std::max(1.0, std::fabs(t)) / dn : seg_lo / 8;
            if (!(shorter > 0) || !(detail::add_up(t, shorter) > t)) return unknown(t);
            s = shorter;
            continue;
        }
        // δ: |g(t + τ)| ≥ m − λτ > 0 for τ < δ = m/λ (t units).
        const double delta = detail::div_down(m, lam);
        // Hit: |f|/λ_space < epsilon with λ_space = λ/‖d‖ ⇒ δ·‖d‖ < epsilon (up to rounding).
        if (delta * dn < opt.epsilon) {
            r.status = Status::Hit;
            r.t_lo = r.t_hi = r.t = t;
            return r;
        }
        if (delta >= seg_hi) {
            if (end >= ray.tmax) break;  // [t, tmax] free
            t = end;
            s = 2 * seg_lo;
            m = -1;
            continue;
        }
        const double next = detail::add_down(t, delta);
        if (!(next > t)) return unknown(t);  // the step vanished below the spacing of doubles
        t = next;
        m = -1;
        s = std::max(2 * delta, seg_lo / 2);
    }
    r.status = Status::Miss;
    return r;
}

}  // namespace certray::tracers
