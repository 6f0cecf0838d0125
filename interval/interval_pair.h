// interval/interval_pair.h — a union of at most two intervals, with IEEE 1788's two-output
// division: the set-valued enclosure that sees past a pole.
//
// Contract: for every operation op and all x in X (and y in Y) where op is defined, op(x, y) lies
// in op(X, Y), as for Interval (interval/interval.h), where X and Y are now unions of at most two
// closed intervals. Division by a piece holding 0 in its interior, of a piece that excludes 0,
// gives two pieces (a / [c, 0] ∪ a / [0, d]: the two unbounded rays of IEEE 1788's mulRevToPair,
// as in extended interval Newton); every other operation is applied piece by piece (all pairs of
// pieces for binary ones: a superset, since both operands' values at one point lie in some pair).
// When more than two pieces result, the two closest are replaced by their hull until two remain
// (sound: the hull holds both). The decoration `defined` is that of Interval: true only when the
// function is defined and continuous on the whole box (never after a division by a piece holding
// 0). Used by the certified solver to exclude parameter intervals around poles
// (docs/theory/certified.md, "Poles").
#pragma once

#include <algorithm>
#include <array>

#include "interval/interval.h"

namespace certray {

/// A union of at most two intervals; piece 1 is empty when one suffices, both when the set is.
struct IntervalPair {
    std::array<Interval, 2> p{Interval::empty(), Interval::empty()};
    bool defined = true;

    IntervalPair() = default;
    /// The point [x, x].
    IntervalPair(double x) : IntervalPair(Interval(x)) {}  // NOLINT: implicit, like Interval
    /// The interval x, as one piece.
    IntervalPair(const Interval& x) : p{x, Interval::empty()}, defined(x.defined) {}  // NOLINT

    bool is_empty() const { return p[0].is_empty() && p[1].is_empty(); }
    /// The hull of the pieces, decorated.
    Interval hull() const {
        Interval h = p[0].is_empty() ? p[1] : (p[1].is_empty() ? p[0] : certray::hull(p[0], p[1]));
        if (!h.is_empty()) h.defined = defined;
        return h;
    }
};

namespace detail {

/// The union of the pieces v[0 … n), reduced to two (v is scratch; n ≤ 8): sorted, overlapping
/// pieces merged, then the two nearest joined by their hull while more than two remain.
inline IntervalPair reduce(std::array<Interval, 8>& v, int n, bool defined) {
    int m = 0;
    for (int i = 0; i < n && i < 8; ++i)
        if (!v[i].is_empty()) v[m++] = v[i];
    std::sort(v.begin(), v.begin() + m,
              [](const Interval& a, const Interval& b) { return a.lower() < b.lower(); });
    int k = 0;
    for (int i = 0; i < m; ++i) {
        if (k > 0 && v[i].lower() <= v[k - 1].upper()) {
            v[k - 1] = hull(v[k - 1], v[i]);
        } else {
            v[k++] = v[i];
        }
    }
    while (k > 2) {  // join the pair with the smallest gap
        int best = 0;
        double gap = v[1].lower() - v[0].upper();
        for (int i = 1; i + 1 < k; ++i) {
            const double g = v[i + 1].lower() - v[i].upper();
            if (g < gap) {
                gap = g;
                best = i;
            }
        }
        v[best] = hull(v[best], v[best + 1]);
        for (int i = best + 1; i + 1 < k; ++i) v[i] = v[i + 1];
        --k;
    }
    IntervalPair r;
    for (int i = 0; i < k; ++i) r.p[i] = v[i];
    r.defined = defined && k > 0;
    return r;
}

template <class F>
IntervalPair unary(const IntervalPair& x, F f) {
    std::array<Interval, 8> v;
    v.fill(Interval::empty());
    bool defined = x.defined;
    for (int i = 0; i < 2; ++i) {
        if (x.p[i].is_empty()) continue;
        v[i] = f(x.p[i]);
        defined = defined && v[i].defined;
    }
    return reduce(v, 2, defined);
}

template <class F>
IntervalPair binary(const IntervalPair& x, const IntervalPair& y, F f) {
    std::array<Interval, 8> v;
    v.fill(Interval::empty());
    bool defined = x.defined && y.defined;
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            if (x.p[i].is_empty() || y.p[j].is_empty()) continue;
            v[2 * i + j] = f(x.p[i], y.p[j]);
            defined = defined && v[2 * i + j].defined;
        }
    }
    return reduce(v, 4, defined);
}

}  // namespace detail

inline IntervalPair operator+(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return x + y; });
}
inline IntervalPair operator-(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return x - y; });
}
inline IntervalPair operator*(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return x * y; });
}
/// Piece by piece; a piece a that excludes 0 divided by a piece [c, d] with c < 0 < d gives the
/// two pieces a / [c, 0] and a / [0, d] (each unbounded on one side); both are returned, and the
/// reduction to two pieces keeps them apart unless other pieces lie between.
inline IntervalPair operator/(const IntervalPair& a, const IntervalPair& b) {
    std::array<Interval, 8> w;
    int m = 0;
    bool defined = a.defined && b.defined;
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            const Interval& x = a.p[i];
            const Interval& y = b.p[j];
            if (x.is_empty() || y.is_empty()) continue;
            if (y.lower() < 0 && y.upper() > 0 && (x.lower() > 0 || x.upper() < 0)) {
                w[m++] = x / Interval(y.lower(), 0.0);  // quotients with y → 0⁻
                w[m++] = x / Interval(0.0, y.upper());  // and with y → 0⁺
                defined = false;                        // a pole: neither defined nor continuous
            } else {
                w[m] = x / y;
                defined = defined && w[m].defined;
                ++m;
            }
        }
    }
    return detail::reduce(w, m, defined);
}
inline IntervalPair operator-(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return -x; });
}
inline IntervalPair abs(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return abs(x); });
}
inline IntervalPair square(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return square(x); });
}
inline IntervalPair pow(const IntervalPair& a, unsigned n) {
    return detail::unary(a, [n](const Interval& x) { return pow(x, n); });
}
inline IntervalPair sqrt(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return sqrt(x); });
}
inline IntervalPair exp(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return exp(x); });
}
inline IntervalPair log(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return log(x); });
}
inline IntervalPair sin(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return sin(x); });
}
inline IntervalPair cos(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return cos(x); });
}
inline IntervalPair min(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return min(x, y); });
}
inline IntervalPair max(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return max(x, y); });
}
// Fidget's ops (interval/interval_ext.h), piece by piece: each piece's enclosure holds the op's
// values on it, so their union holds the values on the union.
inline IntervalPair floor(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return floor(x); });
}
inline IntervalPair ceil(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return ceil(x); });
}
inline IntervalPair round(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return round(x); });
}
/// tan piece by piece; a piece across one pole gives its two branches (tan_branches), so that a
/// sign change across the pole is never taken for a root and the pieces beyond it are seen.
inline IntervalPair tan(const IntervalPair& a) {
    std::array<Interval, 8> w;
    int m = 0;
    bool defined = a.defined;
    for (const Interval& x : a.p) {
        if (x.is_empty()) continue;
        if (const auto branches = tan_branches(x)) {
            w[m++] = (*branches)[0];
            w[m++] = (*branches)[1];
            defined = false;
        } else {
            w[m] = tan(x);
            defined = defined && w[m].defined;
            ++m;
        }
    }
    return detail::reduce(w, m, defined);
}
inline IntervalPair asin(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return asin(x); });
}
inline IntervalPair acos(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return acos(x); });
}
inline IntervalPair atan(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return atan(x); });
}
inline IntervalPair logic_not(const IntervalPair& a) {
    return detail::unary(a, [](const Interval& x) { return logic_not(x); });
}
inline IntervalPair atan2(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return atan2(x, y); });
}
inline IntervalPair compare(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return compare(x, y); });
}
inline IntervalPair mod(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b, [](const Interval& x, const Interval& y) { return mod(x, y); });
}
inline IntervalPair logic_and(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b,
                          [](const Interval& x, const Interval& y) { return logic_and(x, y); });
}
inline IntervalPair logic_or(const IntervalPair& a, const IntervalPair& b) {
    return detail::binary(a, b,
                          [](const Interval& x, const Interval& y) { return logic_or(x, y); });
}
/// 0 lies in a piece.
inline bool possibly_zero(const IntervalPair& x) {
    return possibly_zero(x.p[0]) || possibly_zero(x.p[1]);
}

}  // namespace certray
