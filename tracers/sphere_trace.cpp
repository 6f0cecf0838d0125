// tracers/sphere_trace.cpp — plain and over-relaxed sphere tracing, one loop (see the header).
//
// Invariant: at the top of the loop, g has no root on [tmin, t); `t_prev`, `r_prev` describe the
// last point whose free radius has been verified, and a pending over-relaxed step is checked
// (r_prev + r ≥ t − t_prev) before anything is concluded at t.
#include "tracers/sphere_trace.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "expr/derived.h"
#include "expr/eval.h"
#include "tracers/region_tapes.h"

namespace certray::tracers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The signed distance bound |g|/λ at t from the tape and a global λ (space units), improved by a
/// local λ over the point's box inflated by ρ: min(|g|/λ_local, ρ) is a distance bound too (a
/// surface point within ρ is reached inside that box; a farther one is farther than ρ), and the
/// larger bound is kept. ρ = max(16·epsilon, 2 × the previous bound): where the global λ is loose
/// (a cell of Fidget's bear: 10¹⁸; a chain of smooth unions: 10¹⁷⁰) the free radius then doubles
/// from step to step instead of crawling at |g|/λ. Tried where the global bound is below ρ/2;
/// once a local bound has not beaten the global one by 2× on a ray (λ is tight there), only where
/// the global bound falls below epsilon — where the tracer would stop — so that a merely loose λ
/// never stops the tracer far from any surface. Each local bound is one gradient evaluation.
/// With `regions`, every evaluation runs on the tape of its box's region (the same function).
/// The local boxes are cut to the ray's segment box `within` (the bound holds along the
/// segment, where the tracer steps).
Interval tape_distance(const expr::Tape& tape, const RegionTapes* regions, const Ray& ray,
                       const std::array<Interval, 3>& within, double lambda, double t,
                       double epsilon, detail::LocalBounds& local, EvalCounts& evals) {
    const std::array<Interval, 3> p = detail::point_box(ray, t);
    thread_local expr::Evaluator<Interval> eval;
    const Interval v = eval(regions ? regions->at(p) : tape, p);
    if (!detail::usable(v)) return v;
    Interval d = detail::distance_bound(v, lambda);
    const double global = detail::mignitude(d);
    const bool retry = !local.useful && global < local.retry_below;
    const double rho = local.useful ? std::max(16 * epsilon, 2 * local.previous)
                                    : std::max(16 * epsilon, retry ? 16 * global : 0.0);
    if (lambda > 0 && !contains(v, 0.0) &&
        (local.useful ? global < rho / 2 : global < epsilon || retry)) {
        if (local.useful && !local.probed) {
            ++evals.gradient;
            // A local λ over a box holding p is at least ‖∇f(p)‖: where that is ≥ λ/2 no local
            // bound can beat the global one by 2×, and a gradient at the point costs a fraction
            // of a bound over a box (a tenth on the molecule's region tapes). Decided once a ray.
            local.probed = true;
            if (2 * detail::gradient_norm(regions ? regions->at(p) : tape, detail::midpoint(p)) >=
                lambda) {
                local.useful = false;
                local.retry_below = global / 16;
                local.previous = detail::mignitude(d);
                return d;
            }
        }
        bool evaluated = false;
        const Interval near =
            detail::local_distance_bound(tape, p, v, rho, regions, within, local.box, evaluated);
        evals.gradient += evaluated;
        const double m = detail::usable(near) ? detail::mignitude(near) : 0.0;
        if (m > global) d = near;
        const bool beats = m >= 2 * global;
        if (local.useful && !beats) local.useful = false;
        if (!local.useful && beats && global >= epsilon) local.useful = true;  // λ loose here
        if (!local.useful) local.retry_below = global / 16;
    }
    // ρ next: twice this bound, but at least half this ρ (where the local λ grows fast with the
    // box, as under exponential blends, a bound far below ρ would restart the doubling low).
    local.previous = std::max(detail::mignitude(d), local.useful ? rho / 4 : 0.0);
    return d;
}

}  // namespace

namespace detail {

double first_order_distance(const expr::Tape& tape, const Ray& ray, double t) {
    std::array<double, 3> p;
    for (int i = 0; i < 3; ++i) p[i] = std::fma(t, ray.d[i], ray.o[i]);
    const Dual<double, 3> g = expr::gradient(tape, p);
    if (g.a == 0) return 0;
    const double n = std::sqrt(g.v[0] * g.v[0] + g.v[1] * g.v[1] + g.v[2] * g.v[2]);
    const double e = std::fabs(g.a) / n;
    return std::isnan(e) ? kInf : e;
}

RayResult trace_distance(const DistanceAt& distance, const EstimateAt& estimate,
                         const expr::Tape& tape, const Ray& ray, const TraceOptions& opt,
                         double kappa) {
    RayResult r;
    auto unknown = [&](double lo) {
        r.status = Status::Unknown;
        r.t_lo = r.t = lo;
        r.t_hi = ray.tmax;
        return r;
    };
    const double dn = detail::norm_up(ray.d);
    if (dn == 0 || ray.tmin == ray.tmax) return detail::degenerate(tape, ray);
    const double omega = 1.0 + std::max(0.0, kappa);
    bool relaxed = omega > 1.0;

    double t = ray.tmin;
    double t_prev = t, r_prev = 0;
    bool positive_prev = true;  // the sign of g at t_prev
    bool pending = false;       // the step into t was over-relaxed and is not yet verified
    const Deadline deadline(opt.seconds);
    std::uint64_t step = 0;
    while (true) {
        if (r.evals.total() >= opt.budget || deadline.passed_at(step++)) {
            return unknown(pending ? t_prev : t);
        }
        const Interval v = distance(t, r.evals);  // space units, sign of g
        ++r.evals.interval;
        if (v.is_empty() || !v.defined) {
            if (!pending) return unknown(t);
            t = detail::add_down(t_prev, r_prev);  // retreat: take the plain step instead
            relaxed = pending = false;
            continue;
        }
        const double m = detail::mignitude(v);  // a free radius around the point, rounded down
        const double rad = m == kInf ? kInf : detail::div_down(m, dn);
        if (pending) {
            pending = false;
            const double gap = detail::add_up(t, -t_prev);
            // The free radii are open balls (a root may sit at exactly |g|/λ), so they must
            // overlap strictly — and g must keep its sign, or a root lies between.
            const bool positive = v.lower() > 0;
            if (!(detail::add_down(r_prev, rad) > gap) || positive != positive_prev ||
                (!positive && !(v.upper() < 0))) {
                // Keinert: the spheres do not overlap; go back and step plainly from here on.
                t = detail::add_down(t_prev, r_prev);
                relaxed = false;
                continue;
            }
        }
        // No root on [tmin, t); |g(t)|/λ is a free radius around t.
        if (m < opt.epsilon) {
            if (!estimate || estimate(t, r.evals) <= 4 * opt.epsilon) {
                r.status = Status::Hit;
                r.t_lo = r.t_hi = r.t = t;
                return r;
            }
            // The bound is loose here (the surface is farther than 4·epsilon by the estimate).
            if (opt.hand_over_crawls) return unknown(t);
        }
        if (t >= ray.tmax) break;  // g(tmax) ≠ 0 and [tmin, tmax) is free
        const double plain = detail::add_down(t, rad);
        if (plain > ray.tmax) break;
        double next = plain;
        if (relaxed) {
            const double far = detail::add_down(t, detail::mul_down(omega, rad));
            if (far > plain) {
                next = std::min(far, ray.tmax);
                pending = next > plain;
            }
        }
        if (!(next > t)) {
            // The step vanished below the spacing of doubles: cannot make progress.
            return unknown(t);
        }
        t_prev = t;
        r_prev = rad;
        positive_prev = v.lower() > 0;
        t = next;
    }
    r.status = Status::Miss;
    return r;
}

}  // namespace detail

double global_lipschitz(const expr::Tape& tape, const std::array<Interval, 3>& bounds) {
    return expr::lipschitz_bound(tape, bounds);
}

namespace {

RayResult trace(const expr::Tape& tape, const RegionTapes* regions, const Ray& ray, double lambda,
                const TraceOptions& opt, double kappa, detail::LocalBounds& local) {
    if (std::isnan(lambda) || lambda < 0 || lambda == kInf) {
        RayResult r;
        r.status = Status::Unknown;
        r.t_lo = r.t = ray.tmin;
        r.t_hi = ray.tmax;
        return r;
    }
    const std::array<Interval, 3> within = detail::segment_box(ray);
    return detail::trace_distance(
        [&](double t, EvalCounts& evals) {
            return tape_distance(tape, regions, ray, within, lambda, t, opt.epsilon, local, evals);
        },
        [&](double t, EvalCounts& evals) {
            ++evals.gradient;
            if (!regions) return detail::first_order_distance(tape, ray, t);
            return detail::first_order_distance(regions->at(detail::point_box(ray, t)), ray, t);
        },
        tape, ray, opt, kappa);
}

}  // namespace

RayResult sphere_trace(const expr::Tape& tape, const Ray& ray, double lambda,
                       const TraceOptions& options) {
    detail::LocalBounds local;
    return trace(tape, nullptr, ray, lambda, options, 0.0, local);
}

RayResult enhanced_trace(const expr::Tape& tape, const Ray& ray, double lambda,
                         const TraceOptions& options) {
    detail::LocalBounds local;
    return trace(tape, nullptr, ray, lambda, options, options.kappa, local);
}

RayResult sphere_trace(const RegionTapes& regions, const Ray& ray, double lambda,
                       const TraceOptions& options) {
    detail::LocalBounds local;
    return trace(regions.tape(), &regions, ray, lambda, options, 0.0, local);
}

RayResult enhanced_trace(const RegionTapes& regions, const Ray& ray, double lambda,
                         const TraceOptions& options) {
    detail::LocalBounds local;
    return trace(regions.tape(), &regions, ray, lambda, options, options.kappa, local);
}

namespace detail {

RayResult sphere_trace(const expr::Tape& tape, const Ray& ray, double lambda,
                       const TraceOptions& options, LocalBounds& local) {
    return trace(tape, nullptr, ray, lambda, options, 0.0, local);
}

}  // namespace detail

}  // namespace certray::tracers
