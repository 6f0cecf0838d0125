// solvers/bernstein.cpp — Bernstein subdivision with Bézier clipping, leftmost first, in interval
// arithmetic (one upward RoundingScope per call).
//
// Invariant: every point of [tmin, a) is proven root-free for the interval [a, b] being popped
// (the stack holds disjoint pieces, leftmost on top). A proof [lo, hi] (certain sign change, or an
// exact zero at an end) found on a popped piece stays valid while the search narrows inside it.
#include "solvers/bernstein.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace certray::solvers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using I = UpInterval;

struct Scratch {
    std::vector<I> p;      // coefficients, as UpInterval
    std::vector<I> q;      // shifted / Bernstein coefficients
    std::vector<I> ratio;  // C(i,j)/C(n,j), row-major (n+1)²
    std::vector<I> binom;  // Pascal rows, scratch for the ratio table
    unsigned ratio_n = ~0u;
    std::vector<std::pair<double, double>> stack;
};

/// ratio[i*(n+1)+j] ⊇ C(i,j)/C(n,j) for j ≤ i ≤ n (binomials by Pascal's rule in intervals: exact
/// while they fit in 53 bits, enclosed beyond).
void build_ratios(Scratch& s, unsigned n) {
    if (s.ratio_n == n) return;
    const unsigned m = n + 1;
    s.binom.assign(m * m, I(0.0));
    for (unsigned i = 0; i < m; ++i) {
        s.binom[i * m] = I(1.0);
        for (unsigned j = 1; j <= i; ++j)
            s.binom[i * m + j] =
                s.binom[(i - 1) * m + j - 1] + (j < i ? s.binom[(i - 1) * m + j] : I(0.0));
    }
    s.ratio.assign(m * m, I(0.0));
    for (unsigned i = 0; i < m; ++i)
        for (unsigned j = 0; j <= i; ++j)
            s.ratio[i * m + j] = s.binom[i * m + j] / s.binom[n * m + j];
    s.ratio_n = n;
}

/// Sign of every polynomial of the family at x: +1, −1, 0 (exact zero enclosure), 2 (uncertain).
int sign_at(const std::vector<I>& p, double x) {
    const I X(x);
    I r = p.back();
    for (std::size_t k = p.size() - 1; k-- > 0;) r = r * X + p[k];
    if (r.is_empty()) return 2;
    if (r.lower() > 0) return 1;
    if (r.upper() < 0) return -1;
    if (r.lower() == 0 && r.upper() == 0) return 0;
    return 2;
}

/// {x ∈ [0,1] : hull(x) crosses 0 side `below`} for the control points (i/n, y_i): the x-range of
/// the convex hull of the points on the wanted side (y ≤ 0 if below, y ≥ 0 otherwise) and of the
/// crossings of every segment between points on opposite sides, rounded outward.
/// Returns false when the range is empty.
bool side_range(const std::vector<I>& b, bool below, double& lo, double& hi) {
    const std::size_t n = b.size() - 1;
    const I N(static_cast<double>(n));
    lo = kInf;
    hi = -kInf;
    auto y = [&](std::size_t i) { return below ? b[i].lower() : b[i].upper(); };
    auto in = [&](double v) { return below ? v <= 0 : v >= 0; };
    for (std::size_t i = 0; i <= n; ++i) {
        if (!in(y(i))) continue;
        const I x = I(static_cast<double>(i)) / N;
        lo = std::min(lo, x.lower());
        hi = std::max(hi, x.upper());
        for (std::size_t j = 0; j <= n; ++j) {
            if (in(y(j))) continue;
            // crossing of (x_i, y_i)–(x_j, y_j) with y = 0: x_i + (x_j − x_i)·y_i/(y_i − y_j)
            const I yi(y(i)), yj(y(j));
            const I xj = I(static_cast<double>(j)) / N;
            I c = x + (xj - x) * (yi / (yi - yj));
            c = intersect(c, I(0.0, 1.0));
            if (c.is_empty()) continue;
            lo = std::min(lo, c.lower());
            hi = std::max(hi, c.upper());
        }
    }
    lo = std::max(lo, 0.0);
    hi = std::min(hi, 1.0);
    return lo <= hi;
}

bool tiny(double a, double b) { return b <= detail::step_up(a, 4); }

RayResult make(Status st, double lo, double hi) {
    RayResult r;
    r.status = st;
    if (st != Status::Miss) {
        r.t_lo = lo;
        r.t_hi = hi;
        r.t = lo == hi ? lo : lo + (hi - lo) / 2;
        if (!(r.t >= lo && r.t <= hi)) r.t = lo;
    }
    return r;
}

}  // namespace

RayResult first_root_bernstein(std::span<const Interval> c, double tmin, double tmax,
                               const BernsteinOptions& options) {
    if (std::isnan(tmin) || std::isnan(tmax) || tmin > tmax)
        return make(Status::Unknown, tmin, tmax);
    thread_local Scratch s;
    RoundingScope scope;
    // Strip leading coefficients that are exactly [0, 0]; the zero polynomial is zero at tmin.
    std::size_t m = c.size();
    while (m > 0 && c[m - 1].lower() == 0 && c[m - 1].upper() == 0) --m;
    if (m == 0) return make(Status::Hit, tmin, tmin);
    for (std::size_t k = 0; k < m; ++k)
        if (c[k].is_empty()) return make(Status::Unknown, tmin, tmax);
    s.p.resize(m);
    for (std::size_t k = 0; k < m; ++k) s.p[k] = I(c[k]);
    const std::size_t n = m - 1;
    if (n == 0 || tmin == tmax) {
        const int sg = n == 0 ? sign_at(s.p, 0.0) : sign_at(s.p, tmin);
        if (sg == 0) return make(Status::Hit, tmin, tmin);
        if (sg == 2) return make(Status::Unknown, tmin, tmax);
        return make(Status::Miss, 0, 0);
    }
    // Cauchy bound: every root t has |t| ≤ 1 + max_k |c_k| / |c_n|.
    double a0 = tmin, b0 = tmax;
    const I& lead = s.p[n];
    if (lead.lower() > 0 || lead.upper() < 0) {
        const double mig = std::min(std::abs(lead.lower()), std::abs(lead.upper()));
        double big = 0;
        for (std::size_t k = 0; k < n; ++k) {
            const double mag = std::max(std::abs(s.p[k].lower()), std::abs(s.p[k].upper()));
            big = std::max(big, (I(mag) / I(mig)).upper());
        }
        const double bound = (I(1.0) + I(big)).upper();
        if (std::isfinite(bound)) {
            a0 = std::max(a0, -bound);
            b0 = std::min(b0, bound);
            if (a0 > b0) return make(Status::Miss, 0, 0);
        }
    }
    if (!std::isfinite(a0) || !std::isfinite(b0)) return make(Status::Unknown, tmin, tmax);

    build_ratios(s, static_cast<unsigned>(n));
    s.q.resize(m);
    s.stack.clear();
    s.stack.emplace_back(a0, b0);
    bool proven = false;
    int sl = 0;  // certain sign of every member just left of the current piece; 0: unknown
    double best_lo = 0, best_hi = 0;
    unsigned steps = 0;
    while (!s.stack.empty()) {
        auto [a, b] = s.stack.back();
        s.stack.pop_back();
        if (++steps > options.max_steps) {
            if (proven) return make(Status::Hit, best_lo, best_hi);
            return make(Status::Unknown, a, tmax);
        }
        // Proofs on [a, b]: [tmin, a) is root-free, so every member keeps one sign on [xL, a)
        // for the last point xL < a of certain sign sL; an opposite certain sign (or an exact zero)
        // at b proves a zero in [a, b].
        const int sa = sign_at(s.p, a);
        if (sa == 0) return make(Status::Hit, a, a);
        if (sa != 2) sl = sa;
        if (sl != 0) {
            const int sb = sign_at(s.p, b);
            if (sb == -sl || sb == 0) {
                proven = true;
                best_lo = a;
                best_hi = b;
                s.stack.clear();  // the first root is in [a, b]: pieces to the right are moot
            }
        }
        // Taylor shift to s ∈ [0, 1]: q(s) = p(a + h·s) with h = b − a (enclosed).
        const I A(a), H = I(b) - I(a);
        for (std::size_t k = 0; k < m; ++k) s.q[k] = s.p[k];
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t k = n - 1; k + 1 > i; --k) s.q[k] = s.q[k] + A * s.q[k + 1];
        I hp(1.0);
        for (std::size_t k = 1; k < m; ++k) {
            hp = hp * H;
            s.q[k] = s.q[k] * hp;
        }
        // Bernstein coefficients b_i = Σ_{j≤i} C(i,j)/C(n,j)·q_j, in place from the top.
        bool finite = true;
        for (std::size_t i = n + 1; i-- > 0;) {
            I acc(0.0);
            for (std::size_t j = 0; j <= i; ++j) acc = acc + s.ratio[i * m + j] * s.q[j];
            s.q[i] = acc;  // q_j for j < i still unchanged
            if (acc.is_empty() || !std::isfinite(acc.lower()) || !std::isfinite(acc.upper()))
                finite = false;
        }
        double lo = 0, hi = 1;
        if (finite) {
            // Convex hull property: the graph lies in the hull of (i/n, b_i) for every member.
            double l1, h1, l2, h2;
            if (!side_range(s.q, true, l1, h1) || !side_range(s.q, false, l2, h2)) continue;
            lo = std::max(l1, l2);
            hi = std::min(h1, h2);
            if (lo > hi) continue;
        }
        double na = lo == 0 ? a : std::max(a, (A + H * I(lo)).lower());
        double nb = hi == 1 ? b : std::min(b, (A + H * I(hi)).upper());
        if (na > nb) continue;
        if (tiny(na, nb)) {
            // [tmin, na) is root-free: look for a certain opposite sign at nb or a little right.
            const int sla = sign_at(s.p, na);
            if (sla == 0) return make(Status::Hit, na, na);
            if (sla != 2) sl = sla;
            if (sl != 0) {
                double x = nb, w = std::max(nb - na, std::numeric_limits<double>::denorm_min());
                for (int k = 0; k < 24 && x <= b0; ++k, w *= 2) {
                    const int sx = sign_at(s.p, x);
                    if (sx == -sl || sx == 0) {
                        if (proven && x > best_hi) break;
                        return make(Status::Hit, na, x);
                    }
                    x = (I(nb) + I(w)).upper();
                }
            }
            if (proven) return make(Status::Hit, best_lo, best_hi);
            return make(Status::Unknown, na, nb);
        }
        if (nb - na > 0.8 * (b - a)) {
            double mid = na + (nb - na) / 2;
            if (!(mid > na && mid < nb)) mid = na;
            if (mid == na) {
                s.stack.emplace_back(na, nb);
                continue;
            }
            s.stack.emplace_back(mid, nb);
            s.stack.emplace_back(na, mid);
        } else {
            s.stack.emplace_back(na, nb);
        }
    }
    if (proven) return make(Status::Hit, best_lo, best_hi);
    return make(Status::Miss, 0, 0);
}

}  // namespace certray::solvers
