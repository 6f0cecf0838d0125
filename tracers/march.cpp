// tracers/march.cpp — fixed-step ray marching with bisection, and the shared rigorous helpers.
#include "tracers/march.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "expr/derived.h"
#include "expr/eval.h"
#include "interval/batch.h"
#include "tracers/region_tapes.h"

namespace certray::tracers {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

namespace detail {

std::array<Interval, 3> point_box(const Ray& ray, double t) {
    // o + t·d with one rounding (fma), then one double outward on each side — unless the sum is
    // exact (the product's error by fma, the sum's by TwoSum, both zero): then the point itself.
    std::array<Interval, 3> p;
    for (int i = 0; i < 3; ++i) {
        const double x = std::fma(t, ray.d[i], ray.o[i]);
        const double prod = t * ray.d[i];
        bool exact = std::isfinite(x) && std::fma(t, ray.d[i], -prod) == 0;
        if (exact) {
            const double s = prod + ray.o[i];
            const double bb = s - prod;
            exact = s == x && (prod - (s - bb)) + (ray.o[i] - bb) == 0;
        }
        p[i] = exact ? Interval(x) : Interval(std::nextafter(x, -kInf), std::nextafter(x, kInf));
    }
    return p;
}

Interval distance_bound(const Interval& v, double lambda) {
    if (lambda == 0) {
        if (v.lower() > 0) return Interval(kInf);
        if (v.upper() < 0) return Interval(-kInf);
        return v;
    }
    // Quotients in round-to-nearest are within half an ulp: one double outward encloses them.
    return Interval(std::nextafter(v.lower() / lambda, -kInf),
                    std::nextafter(v.upper() / lambda, kInf));
}

namespace {

/// min(|v|/λ, ρ) with v's sign (v certainly non-zero); empty unless λ is finite and positive.
Interval capped(const Interval& v, double lam, double rho) {
    if (!(lam > 0 && lam < kInf)) return Interval::empty();
    const Interval q = distance_bound(v, lam);
    if (q.lower() > 0) return Interval(std::min(q.lower(), rho), std::min(q.upper(), rho));
    return Interval(std::max(q.lower(), -rho), std::max(q.upper(), -rho));
}

}  // namespace

Interval local_distance_bound(const expr::Tape& tape, const std::array<Interval, 3>& p,
                              const Interval& v, double rho, const RegionTapes* regions,
                              const std::array<Interval, 3>& within, LocalBox& cache,
                              bool& evaluated) {
    evaluated = false;
    if (cache.valid) {
        // The largest ρ′ with (p ⊕ ρ′) ∩ within inside the cached box: a face of the cached box
        // that is a face of `within` bounds nothing.
        // Not a box far larger than this ρ asks for: its λ may be far looser than a fresh one's
        // (a tracer converging on a surface, or deciding a hit, wants the tight one).
        double fit = kInf, half = 0;
        for (int i = 0; i < 3; ++i) {
            const Interval& c = cache.box[i];
            half = std::max(half, 0.5 * (c.upper() - c.lower()));
            if (c.lower() > within[i].lower()) {
                fit = std::min(fit, add_down(p[i].lower(), -c.lower()));
            }
            if (c.upper() < within[i].upper()) {
                fit = std::min(fit, add_down(c.upper(), -p[i].upper()));
            }
        }
        if (fit >= rho / 2 && half <= 16 * rho) {
            return capped(v, cache.lambda, std::min(fit, rho));
        }
    }
    evaluated = true;
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) {
        const double lo = std::max(std::nextafter(p[i].lower() - rho, -kInf), within[i].lower());
        const double hi = std::min(std::nextafter(p[i].upper() + rho, kInf), within[i].upper());
        if (!(lo <= hi)) return Interval::empty();
        box[i] = Interval(lo, hi);
    }
    cache.valid = true;
    cache.box = box;
    cache.lambda = expr::lipschitz_bound(regions ? regions->at(box) : tape, box);
    return capped(v, cache.lambda, rho);
}

Interval local_distance_bound(const expr::Tape& tape, const std::array<Interval, 3>& p,
                              const Interval& v, double rho, const RegionTapes* regions,
                              const std::array<Interval, 3>* within) {
    static const std::array<Interval, 3> kEverywhere{Interval(-kInf, kInf), Interval(-kInf, kInf),
                                                     Interval(-kInf, kInf)};
    LocalBox fresh;
    bool evaluated = false;
    return local_distance_bound(tape, p, v, rho, regions, within ? *within : kEverywhere, fresh,
                                evaluated);
}

double gradient_norm(const expr::Tape& tape, const std::array<double, 3>& p) {
    const Dual<double, 3> g = expr::gradient(tape, p);
    return std::sqrt(g.v[0] * g.v[0] + g.v[1] * g.v[1] + g.v[2] * g.v[2]);
}

std::array<double, 3> midpoint(const std::array<Interval, 3>& p) {
    return {certray::midpoint(p[0]), certray::midpoint(p[1]), certray::midpoint(p[2])};
}

std::array<Interval, 3> segment_box(const Ray& ray) {
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) {
        box[i] = Interval(ray.o[i]) + Interval(ray.tmin, ray.tmax) * Interval(ray.d[i]);
    }
    return box;
}

Interval g_at(const expr::Tape& tape, const Ray& ray, double t) {
    thread_local expr::Evaluator<Interval> eval;
    return eval(tape, point_box(ray, t));
}

double mignitude(const Interval& v) {
    if (v.is_empty()) return kNaN;
    if (v.lower() > 0) return v.lower();
    if (v.upper() < 0) return -v.upper();
    return 0.0;
}

double norm_up(const std::array<double, 3>& d) {
    // In round-to-nearest the sum of three squares and its root carry a relative error below
    // 3·2⁻⁵³ (no underflow or overflow: checked), so n·(1 + 2⁻⁵⁰), rounded, then one double up,
    // is above ‖d‖.
    const double sq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (sq > 0x1p-900 && sq < 0x1p900) {
        return std::nextafter(std::sqrt(sq) * (1 + 0x1p-50), kInf);
    }
    Interval s(0.0);
    for (double x : d) s = s + square(Interval(x));
    return sqrt(s).upper();
}

namespace {

/// Smallest magnitude at which a product's or quotient's error is exact by fma (far from the
/// subnormals: |q·b| and the remainder stay normal).
constexpr double kTiny = 0x1p-900;

/// s = fl(a + b) and the sign of (a + b) − s, exact in round-to-nearest (TwoSum, Knuth), for
/// finite a, b, s.
int sum_error_sign(double a, double b, double s) {
    const double bb = s - a;
    const double e = (a - (s - bb)) + (b - bb);
    return (e > 0) - (e < 0);
}

}  // namespace

double div_down(double a, double b) {
    if (b == 0) return a > 0 ? kInf : 0.0;
    const double q = a / b;
    if (!(std::isfinite(q) && std::fabs(q) > kTiny && std::fabs(a) > kTiny) || !std::isfinite(b)) {
        return (Interval(a) / Interval(b)).lower();
    }
    // a − q·b exactly (fma; q·b is within an ulp of a, so the remainder is representable).
    const double rem = std::fma(-q, b, a);
    const bool q_above = b > 0 ? rem < 0 : rem > 0;
    return q_above ? std::nextafter(q, -kInf) : q;
}

double mul_down(double a, double b) {
    const double p = a * b;
    if (!(std::isfinite(p) && (p == 0 ? a == 0 || b == 0 : std::fabs(p) > kTiny))) {
        return (Interval(a) * Interval(b)).lower();
    }
    return std::fma(a, b, -p) < 0 ? std::nextafter(p, -kInf) : p;
}

double add_down(double a, double b) {
    const double s = a + b;
    if (!std::isfinite(s) || !std::isfinite(a) || !std::isfinite(b)) {
        return (Interval(a) + Interval(b)).lower();
    }
    return sum_error_sign(a, b, s) < 0 ? std::nextafter(s, -kInf) : s;
}

double add_up(double a, double b) {
    const double s = a + b;
    if (!std::isfinite(s) || !std::isfinite(a) || !std::isfinite(b)) {
        return (Interval(a) + Interval(b)).upper();
    }
    return sum_error_sign(a, b, s) > 0 ? std::nextafter(s, kInf) : s;
}

RayResult degenerate(const expr::Tape& tape, const Ray& ray) {
    RayResult r;
    const Interval v = g_at(tape, ray, ray.tmin);
    r.evals.interval = 1;
    if (!v.is_empty() && v.defined && v.lower() == 0 && v.upper() == 0) {
        r.status = Status::Hit;
        r.t_lo = r.t_hi = r.t = ray.tmin;
    } else if (!v.is_empty() && v.defined && !possibly_zero(v)) {
        r.status = Status::Miss;
    } else {
        r.status = Status::Unknown;
        r.t_lo = ray.tmin;
        r.t_hi = ray.tmax;
        r.t = ray.tmin;
    }
    return r;
}

}  // namespace detail

namespace {

/// The march over f evaluated by `tape_at(p)` (the tape to use at the point p).
/// Samples evaluated together: one batch walk (expr/eval.h, detail::run_batch) over half a Batch
/// costs a few scalar evaluations on a short tape (tanglecube: 21 instructions).
constexpr int kChunk = kBatch / 2;

/// The march over f, evaluating at a box (the hull of the points) the tape `tape_for(box)` gives.
/// The samples t_i are evaluated kChunk at a time, lane by lane bit for bit the double
/// evaluation (interval/batch.h), and consumed one by one exactly as a sample-by-sample march
/// would: evaluations are counted as consumed, so the answers, the budget and the counts are
/// those of the scalar loop (the lanes past the first sign change are work not counted).
template <class TapeFor>
RayResult march_with(const TapeFor& tape_for, const expr::Tape& tape, const Ray& ray,
                     const TraceOptions& options) {
    thread_local expr::Evaluator<double> eval;
    thread_local std::vector<Batch> regs;
    thread_local std::array<Batch, 3> lanes;
    RayResult r;
    const double dn = detail::norm_up(ray.d);
    if (dn == 0 || ray.tmin == ray.tmax) return detail::degenerate(tape, ray);
    auto point = [&](double t) {
        return std::array<double, 3>{ray.o[0] + t * ray.d[0], ray.o[1] + t * ray.d[1],
                                     ray.o[2] + t * ray.d[2]};
    };
    auto g = [&](double t) {
        ++r.evals.value;
        const std::array<double, 3> p = point(t);
        return eval(
            tape_for(std::array<Interval, 3>{Interval(p[0]), Interval(p[1]), Interval(p[2])}), p);
    };
    auto unknown = [&](double lo) {
        r.status = Status::Unknown;
        r.t_lo = r.t = lo;
        r.t_hi = ray.tmax;
        return r;
    };
    const double h = options.step / dn;  // the step in t
    const double eps_t = options.epsilon / dn;
    if (!(h > 0)) return unknown(ray.tmin);
    // t_i from the start (no drift from repeated additions); t_0 = tmin.
    auto t_at = [&](std::uint64_t i) {
        return std::min(ray.tmin + static_cast<double>(i) * h, ray.tmax);
    };
    // g(t_i) for i in [first, first + kChunk), computed when first needed.
    double values[kChunk];
    std::uint64_t first = 0;
    bool filled = false;
    auto sample = [&](std::uint64_t i) {
        ++r.evals.value;
        if (!filled || i >= first + kChunk) {
            first = i;
            filled = true;
            std::array<double, 3> lo, hi;
            lo.fill(kInf);
            hi.fill(-kInf);
            for (int j = 0; j < kChunk; ++j) {
                const std::array<double, 3> p = point(t_at(i + j));
                for (int k = 0; k < 3; ++k) {
                    lanes[k].v[j] = p[k];
                    lo[k] = std::min(lo[k], p[k]);
                    hi[k] = std::max(hi[k], p[k]);
                }
            }
            std::array<Interval, 3> hull;
            for (int k = 0; k < 3; ++k) {
                // Not finite (or NaN): the full tape.
                hull[k] = lo[k] <= hi[k] ? Interval(lo[k], hi[k]) : Interval(-kInf, kInf);
            }
            const expr::Tape& tp = tape_for(hull);
            if (regs.size() < tp.registers()) regs.resize(tp.registers());
            expr::detail::run_batch(tp.instrs().data(), tp.instrs().data() + tp.size(),
                                    lanes.data(), regs.data(), kChunk);
            const Batch& out = regs[tp.output()];
            for (int j = 0; j < kChunk; ++j) values[j] = out.v[j];
        }
        return values[i - first];
    };
    double t0 = ray.tmin;
    double g0 = sample(0);
    std::uint64_t i = 0;
    const Deadline deadline(options.seconds);
    while (true) {
        if (std::isnan(g0)) return unknown(t0);
        if (g0 == 0) {
            r.status = Status::Hit;
            r.t_lo = r.t_hi = r.t = t0;
            return r;
        }
        if (t0 >= ray.tmax) break;
        if (r.evals.total() >= options.budget || deadline.passed_at(i)) return unknown(t0);
        ++i;
        const double t1 = t_at(i);
        const double g1 = sample(i);
        if (std::isnan(g1)) return unknown(t0);
        if (g1 != 0 && (g0 < 0) != (g1 < 0)) {
            // Bisect [t0, t1] until narrower than epsilon (or the budget ends: report the bracket).
            double lo = t0, hi = t1, glo = g0;
            while (hi - lo > eps_t && r.evals.total() < options.budget) {
                const double mid = lo + 0.5 * (hi - lo);
                if (mid <= lo || mid >= hi) break;
                const double gm = g(mid);
                if (std::isnan(gm)) return unknown(lo);
                if (gm == 0) {
                    lo = hi = mid;
                    break;
                }
                if ((gm < 0) == (glo < 0)) {
                    lo = mid;
                    glo = gm;
                } else {
                    hi = mid;
                }
            }
            r.status = Status::Hit;
            r.t_lo = lo;
            r.t_hi = hi;
            r.t = lo + 0.5 * (hi - lo);
            return r;
        }
        t0 = t1;
        g0 = g1;
    }
    r.status = Status::Miss;
    return r;
}

}  // namespace

RayResult march(const expr::Tape& tape, const Ray& ray, const TraceOptions& options) {
    return march_with([&tape](const std::array<Interval, 3>&) -> const expr::Tape& { return tape; },
                      tape, ray, options);
}

RayResult march(const RegionTapes& regions, const Ray& ray, const TraceOptions& options) {
    return march_with(
        [&regions](const std::array<Interval, 3>& b) -> const expr::Tape& { return regions.at(b); },
        regions.tape(), ray, options);
}

}  // namespace certray::tracers
