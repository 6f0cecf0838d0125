// interval/grad_bound.h — GradBound: f, its generalised gradient and a bound on its norm over a
// box.
//
// Contract: evaluated over a box B (inside a live RoundingScope, like UpInterval), a GradBound
// holds (1) `d`, the Dual<UpInterval, 3> enclosure of f and of every generalised gradient of f on
// B, (2) `lip`, an upper bound on the Lipschitz constant of f on B (sup of ‖∂f‖₂; +inf when
// unknown), and (3) when `has_form`, a *root form*: f ≥ 0 on B, and B is covered by finitely many
// pieces on each of which f = Σₖ gₖ² + c (c ≥ 0, gₖ differentiable almost everywhere) with the
// Gram matrix Σₖ ∇gₖ ∇gₖᵀ inside the symmetric interval matrix `gram`, f continuous across pieces.
// Then √f = ‖(g, √c)‖ is Lipschitz on B with constant ‖J‖₂ ≤ √λmax(gram), bounded by Gershgorin.
//
// Why: the interval derivative of √u is unbounded wherever u may vanish, so the plain interval
// gradient gives no Lipschitz bound at all for a sphere, a capsule or any Euclidean distance whose
// zero lies in the box — exactly the primitives sphere tracing is for. The root form gives 1 for
// √(x² + y² + z²) on any box, and stays tight under translation, scaling and axis-aligned
// rotations. Every bound is rounded upward (the scope's mode); sums of non-negative terms only.
// Reference: docs/theory/lipschitz.md ("Root forms").
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "interval/dual.h"
#include "interval/interval.h"

namespace certray {

/// An enclosure of f and ∂f over a box with a Lipschitz bound and an optional root form (see the
/// file contract). Valid only inside a live RoundingScope.
struct GradBound {
    using D = Dual<UpInterval, 3>;
    static constexpr double kInf = std::numeric_limits<double>::infinity();

    D d;
    double lip = 0;  ///< upper bound on ‖∂f‖₂ over the box (+inf: unknown)
    bool has_form = false;
    std::array<UpInterval, 6> gram{};  ///< symmetric 3×3: 00 11 22 01 02 12

    GradBound() = default;
    /// The constant c: gradient 0, and a root form when c ≥ 0.
    GradBound(double c)  // NOLINT: implicit on purpose (the Number concept's T(c))
        : d(UpInterval(c)), lip(0), has_form(c >= 0) {}
    /// The variable of index i over [lo, hi].
    static GradBound variable(const UpInterval& range, int i) {
        GradBound r;
        r.d = D::variable(range, i);
        r.lip = 1;
        return r;
    }
};

namespace detail {

/// max(|lo|, |hi|) of a non-empty interval, +inf for empty or NaN bounds.
inline double magnitude(const UpInterval& x) {
    const double m = std::max(-x.lower(), x.upper());
    return x.is_empty() || std::isnan(m) ? GradBound::kInf : m;
}

/// x·y rounded up for x, y ≥ 0, with 0·∞ = 0 (a zero factor is an exact zero here).
inline double mul_bound(double x, double y) { return x == 0 || y == 0 ? 0.0 : x * y; }

/// √λmax of a symmetric interval matrix by Gershgorin, rounded up (+inf when not finite).
inline double gram_root(const std::array<UpInterval, 6>& g) {
    const double m01 = magnitude(g[3]), m02 = magnitude(g[4]), m12 = magnitude(g[5]);
    double rows = 0;
    for (const double row :
         {g[0].upper() + m01 + m02, g[1].upper() + m01 + m12, g[2].upper() + m02 + m12}) {
        if (!(row >= 0)) return GradBound::kInf;  // NaN (an empty entry) → unknown
        rows = std::max(rows, row);
    }
    return std::sqrt(rows);
}

/// Tightens r: lip ≤ ‖components‖, each component within [−lip, lip] (replacing an unbounded or
/// undefined partial when lip is finite).
inline GradBound finish(GradBound r) {
    double sum = 0;
    for (const UpInterval& c : r.d.v) {
        const double m = c.defined ? magnitude(c) : GradBound::kInf;
        sum += mul_bound(m, m);
    }
    const double from_parts = std::sqrt(sum);
    if (!(r.lip >= 0)) r.lip = GradBound::kInf;
    r.lip = std::min(r.lip, from_parts);
    if (r.lip < GradBound::kInf) {
        for (UpInterval& c : r.d.v) {
            if (c.is_empty() || !c.defined) {
                c = UpInterval(-r.lip, r.lip);
            } else {
                c = UpInterval(std::max(c.lower(), -r.lip), std::min(c.upper(), r.lip));
            }
        }
    }
    return r;
}

/// The result with enclosure d and Lipschitz bound lip (no root form), tightened.
inline GradBound bounded(const GradBound::D& d, double lip) {
    GradBound r;
    r.d = d;
    r.lip = lip;
    return finish(r);
}

/// The Gram matrix ∇g∇gᵀ of one function whose gradient enclosure is v.
inline std::array<UpInterval, 6> outer(const std::array<UpInterval, 3>& v) {
    return {square(v[0]), square(v[1]), square(v[2]), v[0] * v[1], v[0] * v[2], v[1] * v[2]};
}

/// True when x is constant on the box (zero gradient bound) and certainly ≥ 0.
inline bool nonneg_constant(const GradBound& x) { return x.lip == 0 && x.d.a.lower() >= 0; }

inline GradBound scaled_form(GradBound r, const GradBound& u, const UpInterval& factor) {
    r.has_form = true;
    for (int i = 0; i < 6; ++i) r.gram[i] = u.gram[i] * factor;
    return r;
}

}  // namespace detail

inline GradBound operator-(const GradBound& a) {
    GradBound r;
    r.d = -a.d;
    r.lip = a.lip;
    return r;
}

inline GradBound operator+(const GradBound& a, const GradBound& b) {
    GradBound r;
    r.d = a.d + b.d;
    r.lip = a.lip + b.lip;
    if (a.has_form && b.has_form) {
        r.has_form = true;
        for (int i = 0; i < 6; ++i) r.gram[i] = a.gram[i] + b.gram[i];
    }
    return detail::finish(r);
}

inline GradBound operator-(const GradBound& a, const GradBound& b) {
    return detail::bounded(a.d - b.d, a.lip + b.lip);
}

inline GradBound operator*(const GradBound& a, const GradBound& b) {
    GradBound r;
    r.d = a.d * b.d;
    r.lip = detail::mul_bound(detail::magnitude(a.d.a), b.lip) +
            detail::mul_bound(detail::magnitude(b.d.a), a.lip);
    // c·Σ gₖ² = Σ (√c gₖ)²: the Gram matrix scales by c.
    if (a.has_form && detail::nonneg_constant(b)) r = detail::scaled_form(r, a, b.d.a);
    if (b.has_form && detail::nonneg_constant(a)) r = detail::scaled_form(r, b, a.d.a);
    return detail::finish(r);
}

inline GradBound operator/(const GradBound& a, const GradBound& b) {
    GradBound r;
    r.d = a.d / b.d;
    r.lip = GradBound::kInf;
    // |b| ≥ m > 0 on the box: ‖∇(a/b)‖ ≤ (‖∇a‖·|b| + |a|·‖∇b‖) / b², b² rounded down.
    const double m = b.d.a.lower() > 0 ? b.d.a.lower() : (b.d.a.upper() < 0 ? -b.d.a.upper() : 0);
    if (m > 0) {
        const double m2_down = -((-m) * m);
        if (m2_down > 0) {
            r.lip = (detail::mul_bound(a.lip, detail::magnitude(b.d.a)) +
                     detail::mul_bound(detail::magnitude(a.d.a), b.lip)) /
                    m2_down;
        }
    }
    if (a.has_form && b.lip == 0 && b.d.a.lower() > 0) {
        r = detail::scaled_form(r, a, UpInterval(1.0) / b.d.a);
    }
    return detail::finish(r);
}

inline GradBound abs(const GradBound& a) { return detail::bounded(abs(a.d), a.lip); }

/// g² is a root form with Gram matrix ∇g∇gᵀ.
inline GradBound square(const GradBound& a) {
    GradBound r;
    r.d = square(a.d);
    r.lip = detail::mul_bound(2 * detail::magnitude(a.d.a), a.lip);
    r.has_form = true;
    r.gram = detail::outer(a.d.v);
    return detail::finish(r);
}

/// gⁿ; for even n = 2k a root form (gᵏ)² with ∇gᵏ = k gᵏ⁻¹ ∇g.
inline GradBound pow(const GradBound& a, unsigned n) {
    GradBound r;
    r.d = pow(a.d, n);  // keeps a's decoration, also for n = 0
    if (n == 0) {
        r.lip = 0;
        r.has_form = true;  // the constant 1
        return r;
    }
    r.lip = detail::mul_bound(n * pow(UpInterval(detail::magnitude(a.d.a)), n - 1).upper(), a.lip);
    if (n % 2 == 0) {
        const unsigned k = n / 2;
        const UpInterval factor = UpInterval(static_cast<double>(k)) * pow(a.d.a, k - 1);
        std::array<UpInterval, 3> v;
        for (int i = 0; i < 3; ++i) v[i] = factor * a.d.v[i];
        r.has_form = true;
        r.gram = detail::outer(v);
    }
    return detail::finish(r);
}

/// √u: with a root form, Lipschitz ≤ √λmax(gram) even where u vanishes.
inline GradBound sqrt(const GradBound& a) {
    return detail::bounded(sqrt(a.d), a.has_form ? detail::gram_root(a.gram) : GradBound::kInf);
}

inline GradBound exp(const GradBound& a) {
    const GradBound::D d = exp(a.d);
    return detail::bounded(d, detail::mul_bound(detail::magnitude(d.a), a.lip));
}

inline GradBound log(const GradBound& a) {
    return detail::bounded(log(a.d), a.d.a.lower() > 0 ? a.lip / a.d.a.lower() : GradBound::kInf);
}

/// |sin′| ≤ 1.
inline GradBound sin(const GradBound& a) { return detail::bounded(sin(a.d), a.lip); }

/// |cos′| ≤ 1.
inline GradBound cos(const GradBound& a) { return detail::bounded(cos(a.d), a.lip); }

namespace detail {

/// min/max: the generalised gradient lies in the hull of the operands'; a root form of each
/// operand gives a piecewise root form with the hull of the Gram matrices.
inline GradBound choose(const GradBound& a, const GradBound& b, const GradBound::D& d) {
    GradBound r;
    r.d = d;
    r.lip = std::max(a.lip, b.lip);
    if (a.has_form && b.has_form) {
        r.has_form = true;
        for (int i = 0; i < 6; ++i) r.gram[i] = hull(a.gram[i], b.gram[i]);
    }
    return finish(r);
}

}  // namespace detail

inline GradBound min(const GradBound& a, const GradBound& b) {
    return detail::choose(a, b, min(a.d, b.d));
}

inline GradBound max(const GradBound& a, const GradBound& b) {
    return detail::choose(a, b, max(a.d, b.d));
}

// ---- Fidget's further ops (issue 14) ----------------------------------------------------------

namespace detail {
/// A piecewise-constant result: Lipschitz 0 where it does not jump on the box (then it is
/// constant there), +inf where it may.
inline GradBound piecewise_constant(const GradBound::D& d) {
    return bounded(d, d.a.defined ? 0.0 : GradBound::kInf);
}
/// φ(u) for a smooth φ with |φ′| ≤ magnitude(dphi) on the range: Lipschitz |φ′|·lip(u).
inline GradBound smooth(const GradBound::D& d, const UpInterval& dphi, double lip) {
    return bounded(d, mul_bound(magnitude(dphi), lip));
}
}  // namespace detail

/// ⌊u⌋, ⌈u⌉, round(u), not(u): constant where they do not jump (Lipschitz 0), else +inf.
inline GradBound floor(const GradBound& a) { return detail::piecewise_constant(floor(a.d)); }
inline GradBound ceil(const GradBound& a) { return detail::piecewise_constant(ceil(a.d)); }
inline GradBound round(const GradBound& a) { return detail::piecewise_constant(round(a.d)); }
inline GradBound logic_not(const GradBound& a) {
    return detail::piecewise_constant(logic_not(a.d));
}
inline GradBound compare(const GradBound& a, const GradBound& b) {
    return detail::piecewise_constant(compare(a.d, b.d));
}

/// |tan′| = 1 + tan², bounded on the box (+inf across a pole).
inline GradBound tan(const GradBound& a) {
    const GradBound::D d = tan(a.d);
    return detail::smooth(d, UpInterval(1.0) + square(d.a), a.lip);
}
/// |asin′| = |acos′| = 1/√(1 − u²) (+inf where |u| may reach 1).
inline GradBound asin(const GradBound& a) {
    return detail::smooth(asin(a.d), UpInterval(1.0) / sqrt(UpInterval(1.0) - square(a.d.a)),
                          a.lip);
}
inline GradBound acos(const GradBound& a) {
    return detail::smooth(acos(a.d), UpInterval(1.0) / sqrt(UpInterval(1.0) - square(a.d.a)),
                          a.lip);
}
/// |atan′| ≤ 1.
inline GradBound atan(const GradBound& a) { return detail::bounded(atan(a.d), a.lip); }

/// ‖∇atan2(y, x)‖ ≤ (lip y + lip x)/r with r = |(x, y)| bounded below on the box; +inf where
/// it jumps (the branch cut) or r may be 0.
inline GradBound atan2(const GradBound& y, const GradBound& x) {
    const GradBound::D d = atan2(y.d, x.d);
    if (!d.a.defined) return detail::bounded(d, GradBound::kInf);
    const UpInterval inv_r = UpInterval(1.0) / sqrt(square(y.d.a) + square(x.d.a));
    return detail::smooth(d, inv_r, y.lip + x.lip);
}

/// mod(a, b) = a − |b|·k with k constant where it does not jump: lip a + |k|·lip b; else +inf.
inline GradBound mod(const GradBound& a, const GradBound& b) {
    const GradBound::D d = mod(a.d, b.d);
    if (!d.a.defined) return detail::bounded(d, GradBound::kInf);
    const UpInterval k = floor(UpInterval(a.d.a / abs(b.d.a)));
    return detail::bounded(d, a.lip + detail::mul_bound(detail::magnitude(k), b.lip));
}

/// and/or: the selected operand's bound where the first operand decides on the box; else +inf
/// unless the result is continuous (then both operands' bounds).
inline GradBound logic_and(const GradBound& a, const GradBound& b) {
    const GradBound::D d = logic_and(a.d, b.d);
    const UpInterval& x = a.d.a;
    if (x.lower() > 0 || x.upper() < 0) return detail::bounded(d, b.lip);
    if (x.lower() == 0 && x.upper() == 0) return detail::bounded(d, a.lip);
    return detail::bounded(d, d.a.defined ? std::max(a.lip, b.lip) : GradBound::kInf);
}
inline GradBound logic_or(const GradBound& a, const GradBound& b) {
    const GradBound::D d = logic_or(a.d, b.d);
    const UpInterval& x = a.d.a;
    if (x.lower() > 0 || x.upper() < 0) return detail::bounded(d, a.lip);
    if (x.lower() == 0 && x.upper() == 0) return detail::bounded(d, b.lip);
    return detail::bounded(d, d.a.defined ? std::max(a.lip, b.lip) : GradBound::kInf);
}

}  // namespace certray
