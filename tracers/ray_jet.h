// tracers/ray_jet.h — RayJet, the number type of segment tracing (internal to
// tracers/segment_trace.cpp, the one file that includes it).
//
// RayJet is one more number type of the evaluator (expr/eval.h): along the ray x = o + τ·d it
// carries, in upward-mode intervals, the point part (g, g′ at the current t) and the segment part
// (G, G′, G″ over T) of every intermediate value, plus `k`: an enclosure of the value at every
// point of T where its derivative may jump (empty: C¹ on T). Rules, for u a value of the DAG:
//   • min/max of operands not ordered on T adds a kink with value in U ∩ V (and the hulls of
//     the derivatives, as Clarke's); abs of an operand straddling 0 adds a kink with value 0;
//   • φ(u) for a smooth φ maps the kink values by φ, and DROPS them when φ′(K) = {0}: the jump
//     of (φ∘u)′ at a kink t_k is φ′(u(t_k))·jump(u′), so pow(max(k, 0), n ≥ 2) is C¹ again;
//   • u ∘ w (+ − × ÷) keeps the kinks of both, with values u(K_u) ∘ W and U ∘ w(K_w).
// Where no kink remains, g′ is continuous and piecewise C¹ with |g″| bounded, so Taylor's formula
// with the integral remainder gives g(t + τ) ∈ g(t) + τ·g′(t) + τ²/2·G″(T).
// `vt` is the plain interval enclosure over the whole proposed segment, kept apart from `v` so that
// a pass whose segment a switch cut shortens still yields a list pruned for the whole proposal.
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include "interval/interval.h"
#include "solvers/ray.h"
#include "tracers/segment_trace.h"

namespace certray::tracers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using I = UpInterval;  // only inside a RoundingScope (segment_model, Scratch::eval)

bool has(const I& k) { return !k.is_empty(); }
bool is_zero(const I& x) { return x.lower() == 0 && x.upper() == 0; }
/// The same enclosure (bounds and decoration): φ of one is φ of the other, computed once (the
/// plain enclosure vt equals the segment's v wherever no switch cut shortened the segment).
bool same(const I& a, const I& b) {
    return a.lower() == b.lower() && a.upper() == b.upper() && a.defined == b.defined;
}
/// Hull ignoring empty operands (empty = no kink).
I khull(const I& a, const I& b) {
    if (a.is_empty()) return b;
    if (b.is_empty()) return a;
    return hull(a, b);
}

/// The second-order ray jet (see the file comment). p0, p1: point; v, d1, d2: segment; k: kinks;
/// vt: the plain enclosure over the whole proposed segment (with no branch fixed by a switch
/// cut, so valid for pruning over it); c: a constant (p1, d1, d2 are exactly 0, no kink).
struct RayJet {
    I p0, p1, v, d1, d2, k, vt;
    bool c;
    RayJet() : RayJet(0.0) {}
    RayJet(double x)  // NOLINT: implicit on purpose (the evaluator's T(c))
        : p0(x), p1(0.0), v(x), d1(0.0), d2(0.0), k(I::empty()), vt(x), c(true) {}
};

/// A constant from its point, segment and plain enclosures.
RayJet constant(const I& p0, const I& v, const I& vt) {
    RayJet r;
    r.p0 = p0;
    r.v = v;
    r.vt = vt;
    return r;
}

/// φ(u) from φ's values and derivatives: point (f0 = φ(p0), f1 = φ′(p0)), segment (s0 = φ(v),
/// s1 = φ′(v), s2 = φ″(v)), st = φ(vt), kinks (kv = φ(K), kd = φ′(K)).
/// (φ∘u)′ = φ′(u)·u′, (φ∘u)″ = φ″(u)·u′² + φ′(u)·u″.
RayJet chain(const RayJet& u, const I& f0, const I& f1, const I& s0, const I& s1, const I& s2,
             const I& st, const I& kv, const I& kd) {
    if (u.c) return constant(f0, s0, st);
    RayJet r;
    r.c = false;
    r.p0 = f0;
    r.p1 = f1 * u.p1;
    r.v = s0;
    r.vt = st;
    r.d1 = s1 * u.d1;
    r.d2 = s2 * square(u.d1) + s1 * u.d2;
    r.k = (!has(u.k) || is_zero(kd)) ? I::empty() : kv;
    return r;
}

RayJet operator-(const RayJet& u) {
    RayJet r = u;
    r.p0 = -u.p0;
    r.p1 = -u.p1;
    r.v = -u.v;
    r.vt = -u.vt;
    r.d1 = -u.d1;
    r.d2 = -u.d2;
    r.k = has(u.k) ? I(-u.k) : u.k;
    return r;
}
/// (u ± w)′ = u′ ± w′, (u ± w)″ = u″ ± w″ (sign = −1 for −).
template <int Sign>
RayJet add(const RayJet& u, const RayJet& w) {
    auto op = [](const I& a, const I& b) { return Sign > 0 ? I(a + b) : I(a - b); };
    if (u.c && w.c) return constant(op(u.p0, w.p0), op(u.v, w.v), op(u.vt, w.vt));
    RayJet r;
    r.c = false;
    r.p0 = op(u.p0, w.p0);
    r.v = op(u.v, w.v);
    r.vt = op(u.vt, w.vt);
    if (w.c) {
        r.p1 = u.p1, r.d1 = u.d1, r.d2 = u.d2;
    } else if (u.c) {
        r.p1 = Sign > 0 ? w.p1 : I(-w.p1);
        r.d1 = Sign > 0 ? w.d1 : I(-w.d1);
        r.d2 = Sign > 0 ? w.d2 : I(-w.d2);
    } else {
        r.p1 = op(u.p1, w.p1);
        r.d1 = op(u.d1, w.d1);
        r.d2 = op(u.d2, w.d2);
    }
    r.k = khull(has(u.k) ? op(u.k, w.v) : u.k, has(w.k) ? op(u.v, w.k) : w.k);
    return r;
}
RayJet operator+(const RayJet& u, const RayJet& w) { return add<1>(u, w); }
RayJet operator-(const RayJet& u, const RayJet& w) { return add<-1>(u, w); }
/// (uw)′ = u′w + uw′, (uw)″ = u″w + 2u′w′ + uw″.
RayJet operator*(const RayJet& u, const RayJet& w) {
    if (u.c && w.c) return constant(u.p0 * w.p0, u.v * w.v, u.vt * w.vt);
    if (u.c) return w * u;
    RayJet r;
    r.c = false;
    r.p0 = u.p0 * w.p0;
    r.v = u.v * w.v;
    r.vt = u.vt * w.vt;
    if (w.c) {
        r.p1 = u.p1 * w.p0;
        r.d1 = u.d1 * w.v;
        r.d2 = u.d2 * w.v;
    } else {
        r.p1 = u.p1 * w.p0 + u.p0 * w.p1;
        r.d1 = u.d1 * w.v + u.v * w.d1;
        r.d2 = u.d2 * w.v + 2.0 * (u.d1 * w.d1) + u.v * w.d2;
    }
    r.k = khull(has(u.k) ? I(u.k * w.v) : u.k, has(w.k) ? I(u.v * w.k) : w.k);
    return r;
}
/// q = u/w: q′ = (u′ − q·w′)/w, q″ = (u″ − 2q′w′ − q·w″)/w (from u = q·w).
RayJet operator/(const RayJet& u, const RayJet& w) {
    if (u.c && w.c) return constant(u.p0 / w.p0, u.v / w.v, u.vt / w.vt);
    RayJet r;
    r.c = false;
    r.p0 = u.p0 / w.p0;
    r.v = u.v / w.v;
    r.vt = u.vt / w.vt;
    if (w.c) {
        r.p1 = u.p1 / w.p0;
        r.d1 = u.d1 / w.v;
        r.d2 = u.d2 / w.v;
    } else {
        r.p1 = (u.p1 - r.p0 * w.p1) / w.p0;
        r.d1 = (u.d1 - r.v * w.d1) / w.v;
        r.d2 = (u.d2 - 2.0 * (r.d1 * w.d1) - r.v * w.d2) / w.v;
    }
    r.k = khull(has(u.k) ? I(u.k / w.v) : u.k, has(w.k) ? I(u.v / w.k) : w.k);
    return r;
}
/// (u²)′ = 2uu′, (u²)″ = 2u′² + 2uu″.
RayJet square(const RayJet& u) {
    if (u.c) return constant(square(u.p0), square(u.v), square(u.vt));
    const I two(2.0);
    return chain(u, square(u.p0), two * u.p0, square(u.v), two * u.v, two, square(u.vt),
                 square(u.k), two * u.k);
}
/// (uⁿ)′ = n·uⁿ⁻¹·u′, (uⁿ)″ = n(n−1)·uⁿ⁻²·u′² + n·uⁿ⁻¹·u″.
RayJet pow(const RayJet& u, unsigned n) {
    if (u.c || n == 0) return constant(pow(u.p0, n), pow(u.v, n), pow(u.vt, n));
    if (n == 1) return u;
    const I nn(static_cast<double>(n)), nn1(static_cast<double>(n) * (n - 1));
    const I v1 = pow(u.v, n - 1);
    return chain(u, pow(u.p0, n), nn * pow(u.p0, n - 1), pow(u.v, n), nn * v1,
                 nn1 * pow(u.v, n - 2), pow(u.vt, n), pow(u.k, n), nn * pow(u.k, n - 1));
}
/// (√u)′ = u′/(2√u), (√u)″ = (u″ − 2·(√u)′²)/(2√u); unbounded where u may be 0.
RayJet sqrt(const RayJet& u) {
    if (u.c) return constant(sqrt(u.p0), sqrt(u.v), sqrt(u.vt));
    RayJet r;
    r.c = false;
    r.p0 = sqrt(u.p0);
    r.p1 = u.p0.lower() > 0 ? I(u.p1 / (2.0 * r.p0)) : I::entire();
    r.v = sqrt(u.v);
    r.vt = sqrt(u.vt);
    if (u.v.lower() > 0) {
        const I two_s = 2.0 * r.v;
        r.d1 = u.d1 / two_s;
        r.d2 = (u.d2 - 2.0 * square(r.d1)) / two_s;
    } else {
        r.d1 = r.d2 = I::entire();
    }
    r.k = has(u.k) ? sqrt(u.k) : u.k;  // φ′ = 1/(2√u) is never 0
    return r;
}
/// (eᵘ)′ = eᵘu′, (eᵘ)″ = eᵘ(u″ + u′²).
RayJet exp(const RayJet& u) {
    if (u.c) return constant(exp(u.p0), exp(u.v), exp(u.vt));
    RayJet r;
    r.c = false;
    r.p0 = exp(u.p0);
    r.p1 = r.p0 * u.p1;
    r.v = exp(u.v);
    r.vt = same(u.vt, u.v) ? r.v : exp(u.vt);
    r.d1 = r.v * u.d1;
    r.d2 = r.v * (u.d2 + square(u.d1));
    r.k = has(u.k) ? exp(u.k) : u.k;
    return r;
}
/// (log u)′ = u′/u, (log u)″ = u″/u − (u′/u)².
RayJet log(const RayJet& u) {
    if (u.c) return constant(log(u.p0), log(u.v), log(u.vt));
    RayJet r;
    r.c = false;
    r.p0 = log(u.p0);
    r.p1 = u.p1 / u.p0;
    r.v = log(u.v);
    r.vt = same(u.vt, u.v) ? r.v : log(u.vt);
    r.d1 = u.d1 / u.v;
    r.d2 = u.d2 / u.v - square(r.d1);
    r.k = has(u.k) ? log(u.k) : u.k;
    return r;
}
/// (sin u)′ = cos u·u′, (sin u)″ = cos u·u″ − sin u·u′².
RayJet sin(const RayJet& u) {
    if (u.c) return constant(sin(u.p0), sin(u.v), sin(u.vt));
    const I c = cos(u.v);
    return chain(u, sin(u.p0), cos(u.p0), sin(u.v), c, -sin(u.v), sin(u.vt), sin(u.k), cos(u.k));
}
/// (cos u)′ = −sin u·u′, (cos u)″ = −sin u·u″ − cos u·u′².
RayJet cos(const RayJet& u) {
    if (u.c) return constant(cos(u.p0), cos(u.v), cos(u.vt));
    const I s = sin(u.v);
    return chain(u, cos(u.p0), -sin(u.p0), cos(u.v), -s, -cos(u.v), cos(u.vt), cos(u.k), -sin(u.k));
}
/// |u| = u where u ≥ 0 on T, −u where u ≤ 0; else Clarke hulls and a kink of value 0.
RayJet abs(const RayJet& u) {
    if (u.c) return constant(abs(u.p0), abs(u.v), abs(u.vt));
    RayJet r = u;
    if (u.v.lower() >= 0) {
        // |u| = u on T.
    } else if (u.v.upper() <= 0) {
        r = -u;
    } else {
        r.d1 = hull(u.d1, I(-u.d1));
        r.d2 = hull(u.d2, I(-u.d2));
        r.k = khull(I(0.0), has(u.k) ? abs(u.k) : u.k);
    }
    r.v = abs(u.v);
    r.vt = abs(u.vt);
    r.p0 = abs(u.p0);
    if (u.p0.upper() < 0) {
        r.p1 = -u.p1;
    } else if (!(u.p0.lower() > 0)) {
        r.p1 = hull(u.p1, I(-u.p1));
    } else {
        r.p1 = u.p1;
    }
    return r;
}
/// min/max: the operand that wins on all of T (point: at t), else hulls and a kink in U ∩ W.
RayJet pick(const RayJet& u, const RayJet& w, bool u_wins_t, bool w_wins_t, bool u_wins_T,
            bool w_wins_T) {
    RayJet r;
    r.c = u.c && w.c;
    r.p1 = u_wins_t ? u.p1 : w_wins_t ? w.p1 : hull(u.p1, w.p1);
    if (u_wins_T) {
        r.d1 = u.d1, r.d2 = u.d2, r.k = u.k, r.c = u.c;
    } else if (w_wins_T) {
        r.d1 = w.d1, r.d2 = w.d2, r.k = w.k, r.c = w.c;
    } else {
        r.d1 = hull(u.d1, w.d1);
        r.d2 = hull(u.d2, w.d2);
        r.k = r.c ? I::empty() : khull(khull(u.k, w.k), intersect(u.v, w.v));
    }
    return r;
}
RayJet min(const RayJet& u, const RayJet& w) {
    RayJet r = pick(u, w, u.p0.upper() < w.p0.lower(), w.p0.upper() < u.p0.lower(),
                    u.v.upper() <= w.v.lower(), w.v.upper() <= u.v.lower());
    r.p0 = min(u.p0, w.p0);
    r.v = min(u.v, w.v);
    r.vt = min(u.vt, w.vt);
    return r;
}
RayJet max(const RayJet& u, const RayJet& w) {
    RayJet r = pick(u, w, u.p0.lower() > w.p0.upper(), w.p0.lower() > u.p0.upper(),
                    u.v.lower() >= w.v.upper(), w.v.lower() >= u.v.upper());
    r.p0 = max(u.p0, w.p0);
    r.v = max(u.v, w.v);
    r.vt = max(u.vt, w.vt);
    return r;
}

// ---- Fidget's further ops (issue 14) ----------------------------------------------------------

/// A result whose derivatives are not tracked: values by the interval op, derivatives the whole
/// line and a kink anywhere (not smooth), unless every operand is constant.
RayJet untracked(bool constant_operands, const I& p0, const I& v, const I& vt) {
    if (constant_operands) return constant(p0, v, vt);
    RayJet r;
    r.c = false;
    r.p0 = p0;
    r.v = v;
    r.vt = vt;
    r.p1 = r.d1 = r.d2 = r.k = I::entire();
    return r;
}
/// A piecewise-constant result: constant (zero derivatives, no kink) where its segment enclosure
/// is continuous on T, else untracked.
RayJet flat(bool constant_operands, const I& p0, const I& v, const I& vt) {
    if (constant_operands || !v.defined || !p0.defined)
        return untracked(constant_operands, p0, v, vt);
    RayJet r = constant(p0, v, vt);
    r.c = false;
    return r;
}
RayJet floor(const RayJet& u) { return flat(u.c, floor(u.p0), floor(u.v), floor(u.vt)); }
RayJet ceil(const RayJet& u) { return flat(u.c, ceil(u.p0), ceil(u.v), ceil(u.vt)); }
RayJet round(const RayJet& u) { return flat(u.c, round(u.p0), round(u.v), round(u.vt)); }
RayJet logic_not(const RayJet& u) {
    return flat(u.c, logic_not(u.p0), logic_not(u.v), logic_not(u.vt));
}
RayJet compare(const RayJet& u, const RayJet& w) {
    return flat(u.c && w.c, compare(u.p0, w.p0), compare(u.v, w.v), compare(u.vt, w.vt));
}
/// (tan u)′ = (1 + tan²u)·u′, (tan u)″ = 2·tan u·(1 + tan²u)·u′² + (1 + tan²u)·u″.
RayJet tan(const RayJet& u) {
    if (u.c) return constant(tan(u.p0), tan(u.v), tan(u.vt));
    const I t = tan(u.v), s1 = 1.0 + square(t), tk = tan(u.k);
    return chain(u, tan(u.p0), 1.0 + square(tan(u.p0)), t, s1, 2.0 * t * s1, tan(u.vt), tk,
                 1.0 + square(tk));
}
/// (atan u)′ = 1/(1 + u²), (atan u)″ = −2u/(1 + u²)².
RayJet atan(const RayJet& u) {
    if (u.c) return constant(atan(u.p0), atan(u.v), atan(u.vt));
    const I s1 = 1.0 / (1.0 + square(u.v));
    return chain(u, atan(u.p0), 1.0 / (1.0 + square(u.p0)), atan(u.v), s1, -2.0 * u.v * square(s1),
                 atan(u.vt), atan(u.k), 1.0 / (1.0 + square(u.k)));
}
/// (asin u)′ = 1/√(1 − u²), (asin u)″ = u/(1 − u²)^{3/2}; acos: the negatives.
RayJet asin_acos(const RayJet& u, bool is_acos) {
    const auto f = [is_acos](const I& x) { return is_acos ? acos(x) : asin(x); };
    if (u.c) return constant(f(u.p0), f(u.v), f(u.vt));
    const double sign = is_acos ? -1.0 : 1.0;
    const auto d = [sign](const I& x) { return sign / sqrt(1.0 - square(x)); };
    const I s1 = d(u.v);
    return chain(u, f(u.p0), d(u.p0), f(u.v), s1, sign * u.v * pow(I(sign * s1), 3), f(u.vt),
                 f(u.k), d(u.k));
}
RayJet asin(const RayJet& u) { return asin_acos(u, false); }
RayJet acos(const RayJet& u) { return asin_acos(u, true); }
/// atan2 and mod: values only (derivatives untracked).
RayJet atan2(const RayJet& u, const RayJet& w) {
    return untracked(u.c && w.c, atan2(u.p0, w.p0), atan2(u.v, w.v), atan2(u.vt, w.vt));
}
RayJet mod(const RayJet& u, const RayJet& w) {
    return untracked(u.c && w.c, mod(u.p0, w.p0), mod(u.v, w.v), mod(u.vt, w.vt));
}
/// and/or: the selected operand's jet where the first operand decides it on T (values by the
/// interval op, which carries the decoration); else untracked.
RayJet select(const RayJet& u, const RayJet& w, bool is_and) {
    const auto f = [is_and](const I& a, const I& b) {
        return is_and ? logic_and(a, b) : logic_or(a, b);
    };
    const bool nonzero = u.v.lower() > 0 || u.v.upper() < 0;
    const bool zero = is_zero(u.v);
    if (!nonzero && !zero) return untracked(u.c && w.c, f(u.p0, w.p0), f(u.v, w.v), f(u.vt, w.vt));
    RayJet r = (nonzero == is_and) ? w : u;
    r.p0 = f(u.p0, w.p0);
    r.v = f(u.v, w.v);
    r.vt = f(u.vt, w.vt);
    return r;
}
RayJet logic_and(const RayJet& u, const RayJet& w) { return select(u, w, true); }
RayJet logic_or(const RayJet& u, const RayJet& w) { return select(u, w, false); }

/// The enclosures of the output of a jet evaluation.
SegmentModel model_of(const RayJet& r) {
    SegmentModel m;
    m.g0 = Interval(r.p0);
    m.g1 = Interval(r.p1);
    m.g = Interval(r.v);
    m.dg = Interval(r.d1);
    m.ddg = Interval(r.d2);
    m.smooth = r.k.is_empty();
    return m;
}

/// The ray's variables at t (point part) and over [t, end] (segment part). Upward mode.
std::array<RayJet, 3> ray_jets(const Ray& ray, double t, double end) {
    std::array<RayJet, 3> p;
    const I tt(t), seg(t, end);
    for (int i = 0; i < 3; ++i) {
        const I o(ray.o[i]), d(ray.d[i]);
        p[i].p0 = o + tt * d;
        p[i].p1 = d;
        p[i].v = p[i].vt = o + seg * d;
        p[i].d1 = d;
        p[i].c = false;
    }
    return p;
}

}  // namespace
}  // namespace certray::tracers
