// solvers/certified.cpp — leftmost-first interval bisection with interval Newton along a ray.
//
// Invariant: every part of [tmin, tmax] left of the interval being processed has been proven free
// of zeros (0 ∉ G, or Newton's N(T) ∩ T = ∅), or lies in the recorded unresolved candidate.
#include "solvers/certified.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "expr/derived.h"
#include "expr/eval.h"
#include "interval/affine.h"
#include "interval/dual.h"
#include "interval/interval.h"
#include "interval/interval_pair.h"
#include "interval/mpfr_interval.h"
#include "solvers/exact.h"
#include "solvers/ray_field.h"

namespace certray::solvers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using detail::D1;
using detail::Field;
using detail::Scratch;

template <class E>
class Solver {
  public:
    Solver(const expr::Tape& tape, const Ray& ray, const CertifiedOptions& options, Scratch<E>& s)
        : tape_(tape), ray_(ray), options_(options), s_(s) {}

    RayResult solve();

  private:
    bool out_of_budget() const { return result_.evals.total() >= options_.budget; }
    /// A hit enclosure needs no more narrowing: a few ulps, or options.hit_width relative to |t|.
    bool narrow_enough(const Interval& t) const {
        return solvers::narrow_enough(t.lower(), t.upper(), options_.hit_width,
                                      options_.hit_width_absolute);
    }

    /// G(T): g over the parameter interval T.
    Interval g(const Interval& t) {
        ++result_.evals.interval;
        return s_.field.g(tape_, ray_, t);
    }
    /// G(T), refined by the affine form when the options ask for it and G(T) holds 0.
    Interval g_excluding(const Interval& t) {
        Interval v = g(t);
        if (options_.affine && possibly_zero(v) && t.lower() < t.upper() &&
            std::isfinite(t.lower()) && std::isfinite(t.upper())) {
            ++result_.evals.interval;
            v = s_.field.refine_affine(tape_, ray_, t, v);
        }
        return v;
    }
    /// No zero of g in T, given v = G(T): 0 ∉ v; or, where v holds 0 but g is not proven defined
    /// on T and the tape has poles, 0 lies in neither piece of the two-piece enclosure of g over T
    /// (a pole inside T: a zero needs g defined, and g's values on either side of the pole are
    /// bounded away from 0). One more interval evaluation, counted, and only then.
    bool excluded(const Interval& t, const Interval& v) {
        if (!possibly_zero(v)) return true;
        if (v.defined || !s_.field.has_poles(tape_)) return false;
        ++result_.evals.interval;
        return !possibly_zero(s_.field.g_pair(tape_, ray_, t));
    }
    /// G(T) and G'(T) at once.
    D1 g_dual(const Interval& t) {
        ++result_.evals.gradient;
        return s_.field.g_dual(tape_, ray_, t);
    }

    /// Proven: g has a zero in T (everything left of T excluded) → narrow T and report.
    RayResult hit(Interval t);
    /// Interval Newton from T with the derivative enclosure of `gt`. Returns the contracted T
    /// (empty if T holds no zero) and sets `unique` when N(T) ⊂ int T proves a unique zero.
    Interval newton(const Interval& t, const D1& gt, bool& unique);
    /// Sign of g at the point t when certain: −1, +1, 0 for an exact zero, 2 when unknown.
    int sign_at(double t);
    /// The same for an enclosure of g at a point.
    static int sign_of(const Interval& v);
    /// g defined at the point and 0 in its enclosure there, which is not the exact zero [0, 0].
    static bool undecided_defined(const Interval& v) {
        return !v.is_empty() && v.defined && v.lower() <= 0 && v.upper() >= 0 &&
               !(v.lower() == 0 && v.upper() == 0);
    }
    RayResult finish(Status status, double lo, double hi);
    /// Only candidates remain, the first being [lo, hi]: a point p > hi such that a sign change
    /// around the candidate proves a zero in [lo, p], or NaN.
    double sign_change_around(double lo, double hi);

    const expr::Tape& tape_;
    const Ray& ray_;
    const CertifiedOptions& options_;
    Scratch<E>& s_;
    RayResult result_;
};

template <class E>
int Solver<E>::sign_at(double t) {
    if (!std::isfinite(t)) return 2;
    return sign_of(g(Interval(t)));
}

template <class E>
int Solver<E>::sign_of(const Interval& v) {
    if (v.is_empty() || !v.defined) return 2;
    if (v.lower() > 0) return 1;
    if (v.upper() < 0) return -1;
    if (v.lower() == 0 && v.upper() == 0) return 0;
    return 2;
}

template <class E>
Interval Solver<E>::newton(const Interval& t, const D1& gt, bool& unique) {
    unique = false;
    const Interval& dg = gt.v[0];
    // The mean value form needs g defined and continuous on T and a bounded derivative enclosure
    // that excludes 0 (Clarke's mean value theorem covers the kinks of abs/min/max).
    if (!gt.a.defined || !dg.defined || dg.is_empty() || possibly_zero(dg) ||
        !std::isfinite(dg.lower()) || !std::isfinite(dg.upper()) || !std::isfinite(t.lower()) ||
        !std::isfinite(t.upper())) {
        return t;
    }
    const double c = midpoint(t);
    const Interval gc = g(Interval(c));
    if (gc.is_empty() || !gc.defined) return t;
    const Interval n = Interval(c) - gc / dg;
    if (n.is_empty()) return t;
    unique = t.lower() < n.lower() && n.upper() < t.upper();
    return intersect(t, n);
}

template <class E>
RayResult Solver<E>::finish(Status status, double lo, double hi) {
    return detail::finish(result_, status, lo, hi);
}

// T holds a zero and nothing left of T does. Narrow T: by Newton while it contracts (a unique zero
// stays unique), else by bisection that keeps the first zero inside (exclude the left half, or
// keep a sign change in it).
template <class E>
RayResult Solver<E>::hit(Interval t) {
    // A point lp ≤ a = lower(T) with [lp, a) free of zeros and, when sl ≠ 2, the certain sign sl
    // of g at lp: a sign change between lp and a point p of T proves a zero in [a, p]. Keeping
    // lp when a moves right matters where g's sign at the new a is undecided (a contraction
    // stopping an ulp short of a simple root, say).
    double lp = t.lower();
    int sl = sign_at(lp);
    if (sl == 0) return finish(Status::Hit, lp, lp);
    // Undecided at a (a root within rounding of a): [tmin, a) is free of zeros, so a point a few
    // ulps left of a, where the sign is decided, serves as lp.
    for (int k = 0; sl == 2 && k < 8 && !out_of_budget(); ++k) {
        const double q =
            t.lower() -
            std::ldexp(std::nextafter(std::fabs(t.lower()), kInf) - std::fabs(t.lower()), 2 * k);
        if (!(q >= ray_.tmin) || !std::isfinite(q)) break;
        const int sq = sign_at(q);
        if (sq == 1 || sq == -1) {
            lp = q;
            sl = sq;
        }
    }
    auto moved_to = [&](double a) {  // [lp, a) has been proven free of zeros
        const int sa = sign_at(a);
        if (sa != 2 || sl == 2) {
            lp = a;
            sl = sa;
        }
        return sa;
    };
    // Newton's contraction keeps every zero of T (whether or not uniqueness was proven).
    for (int it = 0; it < 64 && !narrow_enough(t) && !out_of_budget(); ++it) {
        bool unique = false;
        const D1 gt = g_dual(t);
        const Interval next = newton(t, gt, unique);
        if (next.is_empty()) break;  // cannot happen for a proven zero; keep the proof we have
        if (next.lower() == t.lower() && next.upper() == t.upper()) break;
        t = next;
    }
    if (t.lower() != lp && moved_to(t.lower()) == 0) {
        return finish(Status::Hit, t.lower(), t.lower());
    }
    while (!narrow_enough(t) && !out_of_budget() && std::isfinite(t.upper())) {
        // Split at the midpoint; where g's sign there is undecided (the split hit the root
        // itself, say), at the quarter points instead.
        const double m = midpoint(t);
        const double splits[3] = {m, midpoint(Interval(t.lower(), m)),
                                  midpoint(Interval(m, t.upper()))};
        bool progress = false;
        for (double p : splits) {
            if (!(t.lower() < p && p < t.upper())) continue;
            const Interval left(t.lower(), p);
            const Interval gl = g_excluding(left);
            if (excluded(left, gl)) {  // no zero in [a, p]: the first zero is in [p, b]
                t = Interval(p, t.upper());
                if (moved_to(p) == 0) return finish(Status::Hit, p, p);
                progress = true;
                break;
            }
            const int sp = sign_at(p);
            // A zero at p, or a sign change on [lp, p] where g is defined and continuous: the
            // first zero is in [a, p] (not necessarily at p: [a, p) is not excluded).
            bool change = sl != 2 && sp != 2 && sl != sp;
            if (change && lp < t.lower()) change = g(Interval(lp, p)).defined;
            if (change && lp == t.lower()) change = gl.defined;
            if (sp == 0 || change) {
                t = left;
                progress = true;
                break;
            }
        }
        if (!progress) break;  // the first zero is in T; no cheaper proof narrows it further
    }
    return finish(Status::Hit, t.lower(), t.upper());
}

// Points ever further out on both sides of the first candidate [lo, hi] (4^k ulps, k < 9): to
// the left everything is excluded, so a point q there with a certain sign and a point p right of
// hi with the other sign (or an exact zero) prove a zero in [q, p] — in [lo, p] — once g is proven
// defined and continuous on [q, p]. Other candidates between hi and p do not matter.
template <class E>
double Solver<E>::sign_change_around(double lo, double hi) {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    if (!std::isfinite(lo) || !std::isfinite(hi)) return kNaN;
    auto ulp = [](double x) { return std::nextafter(std::fabs(x), kInf) - std::fabs(x); };
    double q = kNaN;
    int sq = 2;
    for (int k = 0; k < 9 && sq == 2 && !out_of_budget(); ++k) {
        q = lo - std::ldexp(ulp(lo), 2 * k);
        if (!(q >= ray_.tmin)) return kNaN;
        sq = sign_at(q);
        if (sq == 0) sq = 2;  // cannot happen left of the first candidate; never trusted
    }
    if (sq == 2) return kNaN;
    for (int k = 0; k < 9 && !out_of_budget(); ++k) {
        const double p = hi + std::ldexp(ulp(hi), 2 * k);
        if (!(p <= ray_.tmax)) return kNaN;
        const int sp = sign_at(p);
        if (sp == 2) continue;
        if (sp == sq) return kNaN;  // the same sign on both sides: a touching zero, or none
        return g(Interval(q, p)).defined ? p : kNaN;
    }
    return kNaN;
}

template <class E>
RayResult Solver<E>::solve() {
    if (ray_.d[0] == 0 && ray_.d[1] == 0 && ray_.d[2] == 0) {
        // g is the constant f(o): a zero everywhere (an exact zero), nowhere (0 excluded, or f
        // undefined at o), or undecided.
        const Interval v = g(Interval(0.0));
        if (v.defined && v.lower() == 0 && v.upper() == 0) {
            return finish(Status::Hit, ray_.tmin, ray_.tmin);
        }
        if (!possibly_zero(v)) return finish(Status::Miss, 0, 0);
        return finish(Status::Unknown, ray_.tmin, ray_.tmax);
    }
    const Interval all(ray_.tmin, ray_.tmax);
    std::vector<Interval>& stack = s_.stack;
    stack.clear();
    stack.push_back(all);
    // The first interval that could not be resolved, if any, and how far unresolved parts reach.
    double cand_lo = std::numeric_limits<double>::quiet_NaN();
    double cand_hi = cand_lo;
    double first_hi = cand_lo;  // the right end of the first candidate
    auto unresolved = [&](const Interval& t) {
        if (std::isnan(cand_lo)) {
            cand_lo = t.lower();
            first_hi = t.upper();
        }
        cand_hi = std::isnan(cand_hi) ? t.upper() : std::max(cand_hi, t.upper());
    };

    // The narrowest interval proven so far to hold a zero, with nothing but excluded parts and
    // candidates to its left. A wide proof does not end the search: bisection goes on to narrow it.
    double proof_lo = std::numeric_limits<double>::quiet_NaN();
    double proof_hi = proof_lo;
    auto prove = [&](double lo, double hi) {
        if (std::isnan(proof_hi) || hi <= proof_hi) {
            proof_lo = lo;
            proof_hi = hi;
        }
    };
    // A zero is proven in [lo, hi] and the search has resolved, left to right, everything before
    // it: the first zero lies in [first candidate or lo, hi]. hit() narrows that.
    auto answer = [&](double lo, double hi) {
        return hit(Interval(std::isnan(cand_lo) ? lo : cand_lo, hi));
    };

    while (!stack.empty()) {
        if (!std::isnan(proof_hi) && stack.back().lower() >= proof_hi) break;
        if (out_of_budget()) {
            if (!std::isnan(proof_hi)) return answer(proof_lo, proof_hi);
            // Everything left of the leftmost pending interval is resolved.
            const double lo = std::isnan(cand_lo) ? stack.back().lower() : cand_lo;
            return finish(Status::Unknown, lo, ray_.tmax);
        }
        Interval t = stack.back();
        stack.pop_back();
        if (!std::isnan(proof_hi) && t.upper() > proof_hi) t = Interval(t.lower(), proof_hi);
        const Interval gt = g_excluding(t);
        if (excluded(t, gt)) continue;  // excluded (also when g is undefined on all of T)

        // g ≡ 0 on T: its left end is the first zero.
        if (gt.lower() == 0 && gt.upper() == 0 && gt.defined) return answer(t.lower(), t.lower());

        const D1 gd = g_dual(t);
        bool unique = false;
        const Interval contracted = newton(t, gd, unique);
        if (contracted.is_empty()) continue;  // Newton: no zero in T
        if (unique) return answer(contracted.lower(), contracted.upper());
        const double a = contracted.lower(), b = contracted.upper();
        const bool leaf = !splittable(a, b) || narrow(a, b);
        // A sign change over T where g is defined and continuous (or an exact zero at an end)
        // proves a zero in T.
        bool zone = false;
        if (std::isfinite(a) && std::isfinite(b)) {
            const Interval va = g(Interval(a));
            const Interval vb = g(Interval(b));
            const int sa = sign_of(va);
            const int sb = sign_of(vb);
            if (sa == 0) return answer(a, a);
            if (sb == 0 || (gd.a.defined && sa != 2 && sb != 2 && sa != sb)) {
                if (leaf) return answer(a, b);
                prove(a, b);
            }
            // g defined with 0 inside its rounding error at both ends and at the midpoint: T lies
            // in a zone (a tangency, a root blurred by cancellation) where no point evaluation
            // decides a sign, so no proof is to be had by bisecting it, only ever more candidates
            // (up to width/ulp of them). It is one candidate.
            if (!leaf && sa == 2 && sb == 2 && undecided_defined(va) && undecided_defined(vb)) {
                zone = undecided_defined(g(Interval(midpoint(contracted))));
            }
        }
        if (leaf || zone) {
            unresolved(contracted);  // neither excluded nor proven: a candidate
            continue;
        }
        const double m = midpoint(contracted);
        stack.push_back(Interval(m, b));  // right half examined after the left one
        stack.push_back(Interval(a, m));
    }
    if (!std::isnan(proof_hi)) return answer(proof_lo, proof_hi);
    if (!std::isnan(cand_lo)) {
        const double p = sign_change_around(cand_lo, first_hi);
        if (!std::isnan(p)) return answer(cand_lo, p);
        return finish(Status::Unknown, cand_lo, cand_hi);
    }
    return finish(Status::Miss, 0, 0);
}

}  // namespace

RayResult certified_first_root(const expr::Tape& tape, const Ray& ray,
                               const CertifiedOptions& options) {
    NearestScope env;  // sound in any caller's floating-point environment (interval/interval.h)
    thread_local Scratch<Interval> scratch;
    const RayResult r = Solver<Interval>(tape, ray, options, scratch).solve();
    // Undecided, or wide on a polynomial scene: the exact oracle decides, within what is left of
    // the budget. A hit left wide on purpose (hit_width) stays as it is.
    return exact_fallback(
        tape, ray, r, options.budget,
        options.tighten && options.hit_width <= 0 && options.hit_width_absolute <= 0);
}

RayResult certified_first_root_reference(const expr::Tape& tape, const Ray& ray,
                                         const CertifiedOptions& options) {
    NearestScope env;
    thread_local Scratch<MpfrInterval> scratch;
    return Solver<MpfrInterval>(tape, ray, options, scratch).solve();
}

}  // namespace certray::solvers
