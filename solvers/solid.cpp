// solvers/solid.cpp — leftmost-first interval bisection for the first entry into {f < 0}.
//
// Invariant: every part of [tmin, tmax] left of the interval being examined is proven g ≥ 0
// (a defined enclosure with lower bound ≥ 0), or lies in a recorded unresolved candidate; `neg_`,
// when set, is a point where g < 0 is proven by a point evaluation, and nothing right of it is
// examined. Proof rules and narrowing: docs/theory/solid.md.
#include "solvers/solid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "expr/derived.h"  // Fast<Dual<Interval, N>>: one definition of Evaluator<Dual<…>>
#include "expr/eval.h"
#include "interval/affine.h"
#include "interval/dual.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "solvers/ray_field.h"

namespace certray::solvers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using detail::D1;
using detail::Field;
using detail::Scratch;

/// g ≥ 0 proven on the whole box: the enclosure is defined and its lower bound is ≥ 0.
bool proven_nonneg(const Interval& v) { return !v.is_empty() && v.defined && v.lower() >= 0; }
/// No point of the box is in the solid {f < 0} = {p : f(p) defined and < 0}: the enclosure (of
/// f at the points of the box where it is defined) is empty or has lower bound ≥ 0. Points where f
/// is undefined — a pole, a square root of a negative — are not interior, as they are not zeros
/// for the zero surface (docs/theory/solid.md).
bool outside(const Interval& v) { return v.is_empty() || v.lower() >= 0; }
/// g < 0 proven on the whole box.
bool proven_neg(const Interval& v) { return !v.is_empty() && v.defined && v.upper() < 0; }
/// g defined on the box, with both signs in the enclosure: undecided by rounding, not by f.
bool blurred(const Interval& v) {
    return !v.is_empty() && v.defined && v.lower() < 0 && v.upper() >= 0;
}

template <class E>
class Solver {
  public:
    Solver(const expr::Tape& tape, const Ray& ray, const SolidOptions& options, Scratch<E>& s)
        : tape_(tape), ray_(ray), options_(options), s_(s) {}

    RayResult solve();

  private:
    bool out_of_budget() const { return result_.evals.total() >= options_.budget; }
    /// [lo, hi] is as narrow as the options ask a hit enclosure to be (false when they ask for
    /// no width: then a hit is narrowed as far as the search goes).
    bool wide_enough(double lo, double hi) const {
        return (options_.hit_width > 0 || options_.hit_width_absolute > 0) &&
               narrow_enough(lo, hi, options_.hit_width, options_.hit_width_absolute);
    }

    /// G(T), refined by the affine form when the options ask for it and G(T) is undecided.
    Interval g(const Interval& t) {
        ++result_.evals.interval;
        Interval v = s_.field.g(tape_, ray_, t);
        if (options_.affine && !proven_nonneg(v) && !proven_neg(v) && t.lower() < t.upper() &&
            std::isfinite(t.lower()) && std::isfinite(t.upper())) {
            ++result_.evals.interval;
            v = s_.field.refine_affine(tape_, ray_, t, v);
        }
        if (!outside(v) && !proven_neg(v) && !v.defined && s_.field.has_poles(tape_)) {
            // A pole inside T makes the ordinary enclosure the whole line; the two-piece one sees
            // past it (interval/interval_pair.h).
            ++result_.evals.interval;
            const IntervalPair w = s_.field.g_pair(tape_, ray_, t);
            if (w.is_empty() || (outside(w.p[0]) && outside(w.p[1]))) return w.hull();
        }
        return v;
    }
    /// The enclosure of g at the point t (the box around o + t·d holds the exact point).
    Interval g_at(double t) {
        ++result_.evals.interval;
        return s_.field.g(tape_, ray_, Interval(t));
    }
    D1 g_dual(const Interval& t) {
        ++result_.evals.gradient;
        return s_.field.g_dual(tape_, ray_, t);
    }

    /// The mean-value reaches from a over T = [a, b] (b finite), given ga ⊇ g(a) and G(T), G′(T)
    /// with g defined and continuous on T and G′(T) bounded. Returns the new T: its left end moved
    /// to the last point q up to which g ≥ 0 is proven (when g(a) ≥ 0), and its right end to a
    /// point r where g(r) < 0 is proven by a point evaluation (sets neg_), when these exist.
    Interval reach(const Interval& t, const Interval& ga, const Interval& dg);
    /// Records T as unresolved.
    void unresolved(const Interval& t) {
        if (std::isnan(cand_lo_)) cand_lo_ = t.lower();
        cand_hi_ = std::isnan(cand_hi_) ? t.upper() : std::max(cand_hi_, t.upper());
    }
    void set_neg(double p) {
        if (std::isnan(neg_) || p < neg_) neg_ = p;
    }
    RayResult finish(Status status, double lo, double hi);

    const expr::Tape& tape_;
    const Ray& ray_;
    const SolidOptions& options_;
    Scratch<E>& s_;
    RayResult result_;
    double cand_lo_ = kNaN, cand_hi_ = kNaN;  // the unresolved parts: first start, last end
    double neg_ = kNaN;                       // the leftmost proven-inside point found
};

template <class E>
RayResult Solver<E>::finish(Status status, double lo, double hi) {
    return detail::finish(result_, status, lo, hi);
}

template <class E>
Interval Solver<E>::reach(const Interval& t, const Interval& ga, const Interval& dg) {
    double a = t.lower(), b = t.upper();
    // Mean value theorem (Clarke's generalised form at the kinks of abs/min/max, which Dual
    // encloses by the hull of the one-sided derivatives): g(s) ∈ g(a) + G′(T)·(s − a), s ∈ T.
    if (proven_nonneg(ga)) {
        // g(s) ≥ lo(ga) + lo(G′)·(s − a) ≥ 0 while s − a ≤ lo(ga) / −lo(G′): every bound below
        // is rounded toward a smaller q, so the real inequality holds on [a, q].
        double q = b;
        if (dg.lower() < 0) {
            const double step = (Interval(ga.lower()) / Interval(-dg.lower())).lower();
            q = std::min(b, (Interval(a) + Interval(step)).lower());
        }
        if (q >= b) return Interval::empty();  // g ≥ 0 on all of T
        a = std::max(a, q);
    }
    // g(s) ≤ hi(ga) + hi(G′)·(s − a) < 0 once s − a > hi(ga) / −hi(G′): a candidate for the
    // inside, rounded up, then proven (or not) by its own point evaluation.
    // Where rounding blurs g(r), the step is doubled, up to 2⁷ times.
    if (dg.upper() < 0 && ga.upper() >= 0) {
        const double step = (Interval(ga.upper()) / Interval(-dg.upper())).upper();
        const double r0 = std::nextafter((Interval(t.lower()) + Interval(step)).upper(), kInf);
        for (int k = 0; k < 8 && !out_of_budget(); ++k) {
            const double r = k == 0 ? r0 : t.lower() + std::ldexp(r0 - t.lower(), k);
            if (!(a < r && r < b)) break;
            if (proven_neg(g_at(r))) {
                set_neg(r);
                b = r;
                break;
            }
        }
    }
    return Interval(a, b);
}

template <class E>
RayResult Solver<E>::solve() {
    if (ray_.d[0] == 0 && ray_.d[1] == 0 && ray_.d[2] == 0) {
        // g is the constant f(o).
        const Interval v = g_at(0.0);
        if (proven_neg(v)) return finish(Status::Hit, ray_.tmin, ray_.tmin);
        if (outside(v)) return finish(Status::Miss, 0, 0);
        return finish(Status::Unknown, ray_.tmin, ray_.tmax);
    }
    std::vector<Interval>& stack = s_.stack;
    stack.clear();
    stack.push_back(Interval(ray_.tmin, ray_.tmax));
    // Everything left of stack.back() is proven g ≥ 0, or lies in [cand_lo_, cand_hi_].
    auto proven_to = [&] { return std::isnan(cand_lo_) ? stack.back().lower() : cand_lo_; };

    while (!stack.empty()) {
        if (!std::isnan(neg_)) {
            if (stack.back().lower() >= neg_) break;  // the stack is ordered: all the rest too
            if (stack.back().upper() > neg_) stack.back() = Interval(stack.back().lower(), neg_);
            // Everything left of the pending interval is proven outside: [that, neg] is a hit
            // enclosure, narrow enough for the options.
            if (std::isnan(cand_lo_) && wide_enough(stack.back().lower(), neg_)) {
                return finish(Status::Hit, stack.back().lower(), neg_);
            }
        }
        if (out_of_budget()) {
            const double lo = std::min(proven_to(), std::isnan(neg_) ? kInf : neg_);
            if (!std::isnan(neg_)) return finish(Status::Hit, lo, neg_);
            return finish(Status::Unknown, lo, ray_.tmax);
        }
        Interval t = stack.back();
        stack.pop_back();
        const Interval gt = g(t);
        if (outside(gt)) continue;  // f undefined on all of T (empty) included
        if (proven_neg(gt)) {       // g < 0 on all of T, at its left end in particular
            set_neg(t.lower());
            continue;
        }
        const double a = t.lower();
        const Interval ga = g_at(a);
        if (proven_neg(ga)) {
            set_neg(a);
            continue;
        }
        if (!outside(ga) && !std::isnan(neg_)) {
            // The answer's t_lo is final: every enclosure of g over a set holding a also holds
            // the point enclosure ga (inclusion monotonicity), so nothing starting at a is ever
            // proven ≥ 0. Only t_hi can still move left: bisect [a, neg_] with point evaluations
            // for a proven-inside point nearer to a.
            const double lo = std::isnan(cand_lo_) ? a : cand_lo_;
            double left = a;
            while (splittable(left, neg_) && !wide_enough(lo, neg_) && !out_of_budget()) {
                const double m = midpoint(Interval(left, neg_));
                if (proven_neg(g_at(m))) {
                    neg_ = m;
                } else {
                    left = m;
                }
            }
            return finish(Status::Hit, lo, neg_);
        }
        double b = t.upper();
        if (!splittable(a, b)) {  // a leaf: [a, b] adjacent doubles (or a point)
            if (a < b && std::isfinite(b) && (std::isnan(neg_) || b < neg_) && !out_of_budget() &&
                proven_neg(g_at(b))) {
                set_neg(b);
            }
            unresolved(t);
            continue;
        }
        if (std::isfinite(b) && !out_of_budget()) {
            const D1 gd = g_dual(t);
            const Interval& dg = gd.v[0];
            if (gd.a.defined && ga.defined && !ga.is_empty() && dg.defined && !dg.is_empty() &&
                std::isfinite(dg.lower()) && std::isfinite(dg.upper())) {
                const Interval n = reach(t, ga, dg);
                if (n.is_empty()) continue;  // g ≥ 0 on all of T
                if (n.lower() > a || n.upper() < b) {
                    // Contracted: examine what is left again (Newton-like steps) while they
                    // halve it at least; otherwise bisect what is left.
                    if (n.upper() - n.lower() <= 0.5 * (b - a)) {
                        stack.push_back(n);
                        continue;
                    }
                    t = n;
                }
            }
        }
        const double lo = t.lower();
        b = t.upper();
        // g defined with both signs within rounding at both ends and at the midpoint: T lies in a
        // zone (a tangency, a crossing blurred by cancellation) where no point evaluation decides
        // a sign, and bisecting it would only make ever more candidates. It is one candidate.
        if (lo == a && blurred(ga) && std::isfinite(b) && (std::isnan(neg_) || b < neg_) &&
            !out_of_budget()) {
            const Interval gb = g_at(b);
            if (proven_neg(gb)) {
                set_neg(b);
            } else if (blurred(gb) && !out_of_budget() &&
                       blurred(g_at(midpoint(Interval(lo, b))))) {
                unresolved(t);
                continue;
            }
        }
        if (!splittable(lo, b)) {
            unresolved(Interval(lo, b));
            continue;
        }
        const double m = midpoint(Interval(lo, b));
        stack.push_back(Interval(m, b));  // right half examined after the left one
        stack.push_back(Interval(lo, m));
    }
    if (!std::isnan(neg_)) return finish(Status::Hit, std::isnan(cand_lo_) ? neg_ : cand_lo_, neg_);
    if (!std::isnan(cand_lo_)) return finish(Status::Unknown, cand_lo_, cand_hi_);
    return finish(Status::Miss, 0, 0);
}

}  // namespace

RayResult solid_first_entry(const expr::Tape& tape, const Ray& ray, const SolidOptions& options) {
    NearestScope env;  // sound in any caller's floating-point environment (interval/interval.h)
    thread_local Scratch<Interval> scratch;
    return Solver<Interval>(tape, ray, options, scratch).solve();
}

RayResult solid_first_entry_reference(const expr::Tape& tape, const Ray& ray,
                                      const SolidOptions& options) {
    NearestScope env;
    thread_local Scratch<MpfrInterval> scratch;
    return Solver<MpfrInterval>(tape, ray, options, scratch).solve();
}

}  // namespace certray::solvers
