// solvers/ray_field.h — g(t) = f(o + t·d) and g′ over parameter intervals, for the certified
// solvers along a ray (solvers/certified.cpp: the zero surface; solvers/solid.cpp: the solid).
//
// Contract: Field<E>::g(tape, ray, T) ⊇ {g(t) : t ∈ T}, computed in the enclosure type E and
// rounded outward to double intervals, `defined` only where g is defined and continuous on all of
// T; g_dual adds G′(T); refine_affine intersects with the affine form of g in T's one noise
// symbol; g_pair gives a union of at most two intervals (interval/interval_pair.h) where a
// division splits. One Field per thread: it owns the evaluators and their registers.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include "expr/derived.h"
#include "expr/eval.h"
#include "interval/affine.h"
#include "interval/dual.h"
#include "interval/interval.h"
#include "interval/interval_pair.h"
#include "solvers/ray.h"
#include "solvers/width.h"

namespace certray::solvers::detail {

using D1 = Dual<Interval, 1>;

/// g and g′ over parameter intervals, computed in the enclosure type E and rounded outward to
/// double intervals (the identity for E = Interval). One per thread: it owns the evaluators.
template <class E>
struct Field {
    using DE = Dual<E, 1>;
    expr::Evaluator<E> value;
    expr::Evaluator<DE> dual;
    expr::Evaluator<Affine<1>> affine;
    expr::Evaluator<IntervalPair> pair;
    std::vector<UpInterval> up_regs;            ///< registers of g (E = Interval)
    std::vector<Dual<UpInterval, 1>> up_duals;  ///< registers of g_dual (E = Interval)

    /// Whether `tape` has poles for g_pair to see past (a division, a tan); remembered for the
    /// last tape.
    bool has_poles(const expr::Tape& tape) {
        if (tape.serial() == 0 || tape.serial() != poles_serial_) {
            poles_ =
                std::any_of(tape.instrs().begin(), tape.instrs().end(), [](const expr::Instr& in) {
                    return in.op == expr::Op::Div || in.op == expr::Op::Tan;
                });
            poles_serial_ = tape.serial();
        }
        return poles_;
    }

    static E lift(const Interval& x) {
        if constexpr (std::is_same_v<E, Interval>) {
            return x;
        } else {
            if (x.is_empty()) return E::empty();
            E r(x.lower(), x.upper());
            r.defined = x.defined;
            return r;
        }
    }
    static Interval drop(const E& x) {
        if constexpr (std::is_same_v<E, Interval>) {
            return x;
        } else {
            if (x.is_empty()) return Interval::empty();
            Interval r(x.lower(), x.upper());
            r.defined = x.defined;
            return r;
        }
    }

    /// The box o + T·d (each coordinate rounded outward).
    static std::array<E, 3> points(const Ray& ray, const Interval& t) {
        std::array<E, 3> p;
        const E tt = lift(t);
        for (int i = 0; i < 3; ++i) p[i] = E(ray.o[i]) + tt * E(ray.d[i]);
        return p;
    }

    /// G(T) ⊇ {g(t) : t ∈ T}. For double intervals the box and the walk run in one RoundingScope
    /// (the same bounds as Interval's operations, without a mode switch per operation).
    Interval g(const expr::Tape& tape, const Ray& ray, const Interval& t) {
        if constexpr (std::is_same_v<E, Interval>) {
            if (up_regs.size() < tape.registers()) up_regs.resize(tape.registers());
            RoundingScope scope;
            const UpInterval tt(t);
            std::array<UpInterval, 3> p;
            for (int i = 0; i < 3; ++i) p[i] = UpInterval(ray.o[i]) + tt * UpInterval(ray.d[i]);
            expr::detail::run<UpInterval>(tape.instrs(), p, up_regs.data());
            return Interval(up_regs[tape.output()]);
        } else {
            return drop(value(tape, points(ray, t)));
        }
    }
    /// G(T) ∩ the affine form of g in the one noise symbol of T (tighter along long segments,
    /// where interval arithmetic loses the correlation between the coordinates), given v = G(T).
    Interval refine_affine(const expr::Tape& tape, const Ray& ray, const Interval& t, Interval v) {
        const Affine<1> s = Affine<1>::variable(t, 0);
        std::array<Affine<1>, 3> q;
        for (int i = 0; i < 3; ++i) q[i] = Affine<1>(ray.o[i]) + s * Affine<1>(ray.d[i]);
        const Interval a = affine(tape, q).to_interval();
        // Both enclose g over T, so their intersection does; g is defined and continuous on T if
        // either proves it (a decoration states a fact about g, not about the method).
        if (!a.is_empty() && !v.is_empty()) {
            const bool defined = v.defined || a.defined;
            v = intersect(v, a);
            v.defined = defined && !v.is_empty();
        }
        return v;
    }

  private:
    std::uint64_t poles_serial_ = 0;
    bool poles_ = false;

  public:
    /// g over T as a union of at most two intervals (interval/interval_pair.h), in double
    /// intervals whatever E is: ⊇ {g(t) : t ∈ T, g defined at t}.
    IntervalPair g_pair(const expr::Tape& tape, const Ray& ray, const Interval& t) {
        std::array<IntervalPair, 3> p;
        for (int i = 0; i < 3; ++i)
            p[i] = IntervalPair(Interval(ray.o[i]) + t * Interval(ray.d[i]));
        return pair(tape, p);
    }
    /// G(T) and G′(T).
    D1 g_dual(const expr::Tape& tape, const Ray& ray, const Interval& t) {
        if constexpr (std::is_same_v<E, Interval>) {
            using UD = Dual<UpInterval, 1>;
            if (up_duals.size() < tape.registers()) up_duals.resize(tape.registers());
            RoundingScope scope;
            const UpInterval tt(t);
            std::array<UD, 3> p;
            for (int i = 0; i < 3; ++i) {
                const UpInterval d(ray.d[i]);
                p[i] = UD(UpInterval(ray.o[i]) + tt * d, {d});
            }
            expr::detail::run<UD>(tape.instrs(), p, up_duals.data());
            const UD& r = up_duals[tape.output()];
            return D1(Interval(r.a), {Interval(r.v[0])});
        } else {
            const std::array<E, 3> x = points(ray, t);
            std::array<DE, 3> p;
            for (int i = 0; i < 3; ++i) p[i] = DE(x[i], {E(ray.d[i])});
            const DE r = dual(tape, p);
            return D1(drop(r.a), {drop(r.v[0])});
        }
    }
};

/// Scratch space of one thread: the field evaluators and the stack of intervals to examine.
template <class E>
struct Scratch {
    Field<E> field;
    std::vector<Interval> stack;
};

/// result with `status` and, unless it is a Miss, the enclosure [lo, hi] and a point t in it (its
/// midpoint, or lo when hi is infinite): how both certified solvers end.
inline RayResult finish(RayResult& result, Status status, double lo, double hi) {
    result.status = status;
    if (status != Status::Miss) {
        result.t_lo = lo;
        result.t_hi = hi;
        result.t = std::isfinite(hi) ? midpoint(Interval(lo, hi)) : lo;
    }
    return result;
}

}  // namespace certray::solvers::detail
