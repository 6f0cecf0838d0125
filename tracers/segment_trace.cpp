// tracers/segment_trace.cpp — segment tracing with a second-order ray jet evaluated over the DAG.
//
// The jet (tracers/ray_jet.h) gives, in one pass over the tape, g and g′ at the current t and
// G, G′, G″ over the proposed segment, with the kinks of g′ on it.
// SwitchObserver makes the switch cuts during the pass (expr::detail::run's observer); Scratch
// holds the jet slots and the stack of pruned lists. Invariant of the loop: g has no zero on
// [tmin, t).
#include "tracers/segment_trace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "expr/eval.h"
#include "expr/prune.h"
#include "tracers/ray_jet.h"
#include "tracers/region_tapes.h"

namespace certray::tracers {

namespace {

template <class J>
bool finite(const J& x) {
    return !x.is_empty() && std::isfinite(x.lower()) && std::isfinite(x.upper());
}

/// A lower bound on the first τ > 0 where c + b·τ + a·τ² = 0 (c > 0), +inf if there is none.
/// The first zero is 2c/(−b + √(b² − 4ac)); the bound uses the denominator rounded up.
/// J: Interval, or UpInterval inside a RoundingScope.
template <class J>
double first_zero_down(double c, double b, double a) {
    const J disc = square(J(b)) - J(4.0) * J(a) * J(c);
    if (disc.upper() < 0) return kInf;
    const J den = -J(b) + sqrt(J(0.0, disc.upper()));
    if (!(den.upper() > 0)) return kInf;
    return (J(2.0) * J(c) / J(den.upper())).lower();
}

/// Whether c + b·τ + a·τ² ≤ 0 is proven at τ (interval evaluation at the exact τ).
bool proven_nonpositive(double c, double b, double a, double tau) {
    const Interval x(tau);
    return (Interval(c) + Interval(b) * x + Interval(a) * square(x)).upper() <= 0;
}

/// The smallest τ ≤ len found where the upper bound c + b·τ + a·τ² is proven ≤ 0 (c > 0), or
/// +inf. Candidate: the real first zero of the quadratic, nudged up until the check holds.
double first_upper_zero(double c, double b, double a, double len) {
    const double disc = b * b - 4 * a * c;
    if (!(disc >= 0)) return kInf;
    const double den = -b + std::sqrt(disc);
    if (!(den > 0)) return kInf;
    double tau = 2 * c / den;
    for (int i = 0; i < 4 && tau <= len; ++i) {
        if (proven_nonpositive(c, b, a, tau)) return tau;
        tau = tau * (1 + 1e-12) + 1e-300;
    }
    return kInf;
}

/// A model's parts in the interval type J (SegmentModel is the one for Interval).
template <class J>
struct ModelOf {
    J g0, g1, g, dg, ddg;
    bool smooth = false;
};

/// For a model on [t, t + len] with 0 ∉ g0 and g continuous on the segment: δ such that g has
/// no zero on [t, t + δ) (+inf: none on the segment by the bounds), and τ* ≤ len such that a zero
/// is proven in (t, t + τ*] (+inf: none proven). See the file contract of segment_trace.h.
struct Steps {
    double delta = 0;
    double tau = kInf;
};
template <class J, class M>
Steps steps(const M& m, double len, bool second_order, bool certify) {
    const bool neg = m.g0.upper() < 0;  // h = σ·g > 0 at t
    auto lo = [&](const J& x) { return neg ? -x.upper() : x.lower(); };
    auto hi = [&](const J& x) { return neg ? -x.lower() : x.upper(); };
    Steps r;
    const double c = lo(m.g0);
    if (finite(m.dg)) {  // h(t + τ) ≥ h(t) + τ·inf σG′
        const double l1 = lo(m.dg);
        r.delta = l1 >= 0 ? kInf : (J(c) / J(-l1)).lower();
        if (certify && hi(m.dg) < 0) r.tau = first_upper_zero(hi(m.g0), hi(m.dg), 0, len);
    }
    if (second_order && m.smooth && finite(m.g1) && finite(m.ddg)) {
        // h(t + τ) ≥ h(t) + τ·inf σg′(t) + τ²/2·inf σG″
        r.delta = std::max(r.delta, first_zero_down<J>(c, lo(m.g1), lo(m.ddg) / 2));
        if (certify) {
            r.tau = std::min(r.tau, first_upper_zero(hi(m.g0), hi(m.g1), hi(m.ddg) / 2, len));
        }
    }
    return r;
}

/// The jet of a − b (point and segment parts; kinks of either make it non-smooth). Upward mode.
ModelOf<I> difference(const RayJet& a, const RayJet& b) {
    ModelOf<I> m;
    m.g0 = a.p0 - b.p0;
    m.g1 = a.p1 - b.p1;
    m.g = a.v - b.v;
    m.dg = a.d1 - b.d1;
    m.ddg = a.d2 - b.d2;
    m.smooth = a.k.is_empty() && b.k.is_empty();
    return m;
}

/// The observer of one jet pass (expr::detail::run): at each min, max or abs whose branches are
/// not ordered on the segment, it bounds the distance τ from t over which the branch taken at t
/// stays taken (the safe step of a − b, or of the operand of abs). If τ covers the segment, or
/// τ ≥ `floor` and the segment is cut to [t, t + τ], the node is replaced by that branch: on the
/// (possibly shorter) segment it IS that branch, smooth, with no hull. Every enclosure computed
/// before a cut is over a longer segment, so it stays valid on the shorter one.
struct SwitchObserver {
    double t;
    double* end;       ///< the segment's end, lowered by cuts
    double* next_end;  ///< the nearest later switch seen (a bound from below, ≥ *end), or +inf
    double floor;      ///< the shortest segment a cut may leave
    bool second_order;

    void operator()(const expr::Instr& in, RayJet* r) const {
        if (in.op != expr::Op::Min && in.op != expr::Op::Max && in.op != expr::Op::Abs) return;
        const RayJet& a = r[in.a];
        const bool is_abs = in.op == expr::Op::Abs;
        const RayJet zero(0.0);
        const RayJet& b = is_abs ? zero : r[in.b];
        if (a.v.lower() >= b.v.upper() || b.v.lower() >= a.v.upper()) return;  // ordered on T
        const ModelOf<I> u = difference(a, b);
        if (u.g0.is_empty() || possibly_zero(u.g0) || u.g.is_empty() || !u.g.defined) return;
        const I span = I(*end) - I(t);
        const double tau = steps<I>(u, span.lower(), second_order, false).delta;
        // a − b ≠ 0 on [t, t + τ) (and at t + τ, where a = b, both branches agree): the branch
        // taken at t is the node on the closed segment if τ ≥ its length.
        if (tau < span.upper()) {
            if (!(tau >= floor)) return;
            const double cut = (I(t) + I(tau)).lower();
            if (!(cut > t)) return;
            *next_end = std::min(*next_end, *end);
            *end = cut;
        } else if (tau < kInf) {
            *next_end = std::min(*next_end, (I(t) + I(tau)).lower());
        }
        const bool a_above = u.g0.lower() > 0;
        const bool take_a = is_abs ? a_above : (in.op == expr::Op::Max) == a_above;
        RayJet& out = r[in.out];
        const I vt = out.vt;  // the plain enclosure stays the one over the whole segment
        const bool defined_v = a.v.defined && b.v.defined, defined_p = a.p0.defined && b.p0.defined;
        out = is_abs ? (a_above ? a : -a) : (take_a ? a : b);
        out.v.defined = out.v.defined && defined_v;
        out.p0.defined = out.p0.defined && defined_p;
        if (is_abs) {  // |a| ≥ 0 whatever the branch
            out.v = intersect(out.v, I(0.0, kInf));
            out.v.defined = out.v.defined && defined_v;
        }
        out.vt = vt;
    }
};

/// Per-thread scratch of one ray: jet slots and a stack of SSA lists pruned to nested windows
/// [lo, hi] of t (level 0: the whole tape), so that each evaluation runs on the list pruned to
/// the smallest window holding its segment (expr/prune.h: the pruned list equals f on the
/// window's box, so every enclosure over a sub-segment is one of f). No allocation once warm.
struct Scratch {
    static constexpr int kLevels = 12;
    static constexpr std::size_t kSweep = 256;  ///< a whole tape longer than this is swept first
    std::size_t sweep_above = std::numeric_limits<std::size_t>::max();  ///< pruned lists: same
    std::vector<RayJet> regs;
    std::vector<UpInterval> values;
    expr::PruneWorkspace ws;
    std::array<std::vector<expr::Instr>, kLevels> lists;
    std::array<const std::vector<expr::Instr>*, kLevels> list{};
    std::array<double, kLevels> lo{}, hi{};
    int depth = 0;

    const RegionTapes* regions = nullptr;

    void start(const expr::Tape& tape, std::size_t sweep_pruned_above, const RegionTapes* r) {
        regions = r;
        depth = 0;
        sweep_above = sweep_pruned_above;
        list[0] = &tape.ssa();
        lo[0] = -kInf;
        hi[0] = kInf;
    }

    /// Prunes `ssa` (the list at the current depth) by the plain (vt) or cut (v) enclosures and
    /// pushes the result for the window [t, hi_t].
    void push(const std::vector<expr::Instr>& ssa, std::size_t n, double t, double hi_t,
              bool plain) {
        if (values.size() < n) values.resize(n);
        for (std::size_t i = 0; i < n; ++i) values[i] = plain ? regs[i].vt : regs[i].v;
        push_values(ssa, t, hi_t);
    }
    /// Prunes `ssa` by `values` (slot-indexed enclosures over the window's box) and pushes the
    /// result for the window [t, hi_t]; false when nothing was pruned or the stack is full.
    bool push_values(const std::vector<expr::Instr>& ssa, double t, double hi_t) {
        if (depth + 1 >= kLevels) return false;
        std::vector<expr::Instr>& out = lists[depth + 1];
        if (!expr::prune_ssa(ssa, values.data(), ws, out)) return false;
        ++depth;
        list[depth] = &out;
        lo[depth] = t;
        hi[depth] = hi_t;
        return true;
    }

    /// What one step evaluated: `sweep` — an interval evaluation of a long list over the segment
    /// (to prune it); if that alone proves g ≠ 0 on the whole segment, `free` and no jet pass;
    /// otherwise `jet` — one jet pass, whose result is `m`.
    struct Step {
        SegmentModel m;
        bool sweep = false, jet = false, free = false;
    };

    /// One step for the segment [t, end] (end may be lowered by switch cuts, floor = the
    /// shortest cut; floor = +inf: no switching); prunes to the final segment's box.
    Step eval(const Ray& ray, double t, double& end, double& next_end, double floor,
              bool second_order, bool prune, bool may_sweep) {
        Step step;
        next_end = kInf;
        while (depth > 0 && !(lo[depth] <= t && end <= hi[depth])) --depth;
        const double end0 = end;
        bool plain_pushed = false;
        // The list to start from: the window's, or the tape of the region holding the segment's
        // box when shorter (the same function there).
        const std::vector<expr::Instr>* base = list[depth];
        bool whole = depth == 0;
        if (prune && regions != nullptr && end < kInf) {
            std::array<Interval, 3> box;
            for (int i = 0; i < 3; ++i) {
                box[i] = Interval(ray.o[i]) + Interval(t, end) * Interval(ray.d[i]);
            }
            const std::vector<expr::Instr>& cell = regions->at(box).ssa();
            if (cell.size() < base->size()) {
                base = &cell;
                whole = false;
            }
        }
        if (prune && may_sweep && base->size() > (whole ? kSweep : sweep_above)) {
            // The plain enclosures first (the vt parts of this same evaluation), and the
            // derivative parts below only for the instructions that survive pruning by them.
            const std::vector<expr::Instr>& src = *base;
            if (values.size() < src.size()) values.resize(src.size());
            {
                RoundingScope scope;
                const std::array<RayJet, 3> p = ray_jets(ray, t, end);
                expr::detail::run<UpInterval>(src, {p[0].v, p[1].v, p[2].v}, values.data());
            }
            step.sweep = true;
            const UpInterval& g = values[src.back().out];
            if (!possibly_zero(g)) {
                step.free = true;  // g ≠ 0 on [t, end] wherever it is defined
                return step;
            }
            plain_pushed = push_values(src, t, end);
        }
        const std::vector<expr::Instr>& ssa = plain_pushed ? *list[depth] : *base;
        const std::size_t n = ssa.size();
        if (regs.size() < n) regs.resize(n);
        SegmentModel& m = step.m;
        step.jet = true;
        {
            RoundingScope scope;
            const std::array<RayJet, 3> p = ray_jets(ray, t, end);
            if (floor < kInf) {
                expr::detail::run<RayJet>(ssa, p, regs.data(),
                                          SwitchObserver{t, &end, &next_end, floor, second_order});
            } else {
                expr::detail::run<RayJet>(ssa, p, regs.data());
            }
            m = model_of(regs[ssa.back().out]);  // the output: the last instruction's slot
        }
        if (prune && n > 1) {
            // A cut: the plain enclosures give a list for the whole proposed segment, the cut
            // ones (branches fixed) a shorter list for the cut segment inside it.
            if (end < end0 && !plain_pushed) push(ssa, n, t, end0, true);
            push(ssa, n, t, end, false);
        }
        return step;
    }
};

}  // namespace

SegmentModel segment_model(const expr::Tape& tape, const Ray& ray, double t, double end) {
    thread_local std::vector<RayJet> regs;
    if (regs.size() < tape.registers()) regs.resize(tape.registers());
    RoundingScope scope;
    expr::detail::run<RayJet>(tape.instrs(), ray_jets(ray, t, end), regs.data());
    return model_of(regs[tape.output()]);
}

RayResult segment_trace(const expr::Tape& tape, const Ray& ray, const TraceOptions& opt,
                        const SegmentOptions& so) {
    RayResult r;
    auto unknown = [&](double lo) {
        r.status = Status::Unknown;
        r.t_lo = r.t = lo;
        r.t_hi = ray.tmax;
        return r;
    };
    auto hit = [&](double lo, double hi) {
        r.status = Status::Hit;
        r.t_lo = r.t = lo;
        r.t_hi = hi;
        return r;
    };
    const double dn = detail::norm_up(ray.d);
    if (dn == 0 || ray.tmin == ray.tmax) return detail::degenerate(tape, ray);
    const double eps_t = detail::div_down(opt.epsilon, dn);  // epsilon in units of t
    thread_local Scratch scratch;
    scratch.start(tape, so.sweep_pruned_above, so.regions);
    double t = ray.tmin;
    // The first segment: the whole ray, or first_length in space units.
    double s = so.first_length > 0 ? so.first_length / dn : kInf;
    const Deadline deadline(opt.seconds);
    while (true) {
        if (r.evals.total() >= opt.budget || deadline.passed()) return unknown(t);
        double end = std::min(detail::add_up(t, s), ray.tmax);
        const double proposed = (Interval(end) - Interval(t)).lower();
        const double floor = so.switch_floor > 0 ? so.switch_floor * proposed : kInf;
        double next_end = kInf;
        const bool may_sweep = r.evals.total() + 2 <= opt.budget;  // a sweep and a jet pass
        const Scratch::Step step =
            scratch.eval(ray, t, end, next_end, floor, so.second_order, so.prune, may_sweep);
        r.evals.interval += step.sweep;
        r.evals.gradient += step.jet;
        if (step.free) {
            if (end >= ray.tmax) break;  // [t, tmax] is free
            t = end;
            s = so.growth * proposed;
            if (so.tail > 0 && s > so.tail * (ray.tmax - t)) s = kInf;
            continue;
        }
        const SegmentModel& m = step.m;
        const Interval span = Interval(end) - Interval(t);
        const double len = span.lower();  // |T| rounded down
        // 0 ∉ G(T): no zero on T, where g is defined or not (a zero needs g defined; a pole or a
        // gap of f's domain inside T is passed, as the certified solver passes it).
        bool free = !possibly_zero(m.g);
        // g proven defined at t (else, at a pole or outside f's domain, no bound starts at t: a
        // shorter segment may still exclude a zero by its value).
        const bool at_t = !m.g0.is_empty() && m.g0.defined;
        if (!free && at_t) {
            if (possibly_zero(m.g0)) return hit(t, t);  // |g(t)| cannot be told from 0
            if (t >= ray.tmax) break;                   // g(tmax) ≠ 0 and [tmin, tmax) is free
        }
        const bool cont = at_t && m.g.defined && !m.g.is_empty();
        Steps st;
        if (!free && cont) {
            st = steps<Interval>(m, len, so.second_order, so.certify);
            st.delta *= so.step_scale;
            if (st.delta > span.upper()) free = true;  // h > 0 on [t, t + δ) ⊇ [t, end]
        }
        if (free) {
            if (end >= ray.tmax) break;  // [t, tmax] is free
            t = end;
            // Next: longer, or up to a few times the next switch seen when this one was cut at a
            // switch, or the rest of the ray when that is not much longer.
            s = so.growth * len;
            // (A switch seen at the very end of the cut segment gives no length: growth then.)
            if (len < proposed && so.next_factor > 0 && next_end < kInf && next_end > end) {
                s = so.next_factor * (next_end - end);
            }
            if (so.tail > 0 && s > so.tail * (ray.tmax - t)) s = kInf;
            continue;
        }
        if (!cont) {
            // No bound on this segment (g undefined at t, or undefined or not continuous somewhere
            // in it): shrink.
            const double shorter = s == kInf ? std::max(1.0, std::fabs(t)) / dn : len / 8;
            if (!(shorter > 0) || !(detail::add_up(t, shorter) > t)) return unknown(t);
            s = shorter;
            continue;
        }
        const double delta = st.delta, tau = st.tau;
        // A zero is proven in (t, t + τ] and none lies in [t, t + δ).
        if (tau < kInf && tau - delta <= eps_t) {
            return hit(detail::add_down(t, delta), detail::add_up(t, tau));
        }
        if (tau == kInf && delta < eps_t && len <= 4 * eps_t) return hit(t, t);  // approximate
        const double next = detail::add_down(t, delta);
        if (!(next > t)) {
            // The step vanished: retry on a shorter segment, or give up at the spacing of doubles.
            if (len <= 4 * eps_t || !(len > 0)) return delta < eps_t ? hit(t, t) : unknown(t);
            s = len * so.shrink;
            continue;
        }
        t = next;
        s = tau < kInf ? (tau - delta) * 1.0000001
                       : std::max(so.growth_partial * delta, len * so.shrink);
    }
    r.status = Status::Miss;
    return r;
}

RayResult segment_trace(const expr::Tape& tape, const Ray& ray, const TraceOptions& options) {
    return segment_trace(tape, ray, options, SegmentOptions{});
}

std::vector<SegmentOptions> segment_presets() {
    std::vector<SegmentOptions> v(7);
    v[1].name = "no-sweep";  // sweep the whole tape only (the default before session 6)
    v[1].sweep_pruned_above = std::numeric_limits<std::size_t>::max();
    v[2].name = "no-switch";
    v[2].switch_floor = 0;
    v[3].name = "1st-order";
    v[3].second_order = false;
    v[4].name = "no-prune";
    v[4].prune = false;
    v[5].name = "no-cert";
    v[5].certify = false;
    // Galin's step rule alone: first-order bounds, no switch cuts, growth 1.5.
    v[6].name = "galin";
    v[6].second_order = false;
    v[6].switch_floor = 0;
    v[6].growth = v[6].growth_partial = 1.5;
    v[6].next_factor = v[6].tail = 0;
    return v;
}

}  // namespace certray::tracers
