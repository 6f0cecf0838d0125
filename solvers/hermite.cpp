// solvers/hermite.cpp — piecewise cubic Hermite root finding along a ray (Sherstyuk 1999).
//
// On [t_i, t_{i+1}], h = t_{i+1} − t_i, the Hermite cubic in s ∈ [0, 1] has Bernstein control
// points g_i, g_i + h·g′_i/3, g_{i+1} − h·g′_{i+1}/3, g_{i+1}. Its first root on [0, 1] is found by
// splitting [0, 1] at the roots of the derivative (a quadratic) into monotone pieces and bisecting
// the first piece with a sign change; then one optional Newton step on the real g.
#include "solvers/hermite.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "expr/eval.h"
#include "interval/dual.h"
#include "solvers/closed_form.h"

namespace certray::solvers {

namespace {

using D = Dual<double, 1>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The cubic Σ c_i B_i³(s) by de Casteljau.
double bez(const std::array<double, 4>& c, double s) {
    const double u = 1 - s;
    const double a = u * c[0] + s * c[1], b = u * c[1] + s * c[2], d = u * c[2] + s * c[3];
    const double e = u * a + s * b, f = u * b + s * d;
    return u * e + s * f;
}

/// First root in [0, 1] of the Bernstein cubic with control points c, or NaN.
double first_root_cubic(const std::array<double, 4>& c) {
    // derivative / 3 = d0 (1−s)² + 2 d1 s(1−s) + d2 s² = d0 + 2(d1 − d0) s + (d0 − 2 d1 + d2) s²
    const double d0 = c[1] - c[0], d1 = c[2] - c[1], d2 = c[3] - c[2];
    double crit[2];
    const int nc = solve_quadratic(d0 - 2 * d1 + d2, 2 * (d1 - d0), d0, crit);
    std::array<double, 4> br{0, 0, 0, 1};
    int nb = 1;
    for (int i = 0; i < nc; ++i)
        if (crit[i] > 0 && crit[i] < 1 && crit[i] > br[nb - 1]) br[nb++] = crit[i];
    br[nb] = 1;
    for (int p = 0; p < nb; ++p) {
        double u = br[p], v = br[p + 1];
        double fu = p == 0 ? c[0] : bez(c, u);
        const double fv = p + 1 == nb ? c[3] : bez(c, v);
        if (fu == 0) return u;
        if (fv == 0) return v;
        if ((fu < 0) == (fv < 0)) continue;
        for (int it = 0; it < 80; ++it) {  // bisection on a monotone piece
            const double m = u + (v - u) / 2;
            if (m <= u || m >= v) break;
            const double fm = bez(c, m);
            if (fm == 0) return m;
            if ((fm < 0) == (fu < 0)) {
                u = m;
                fu = fm;
            } else {
                v = m;
            }
        }
        return u + (v - u) / 2;
    }
    return kNaN;
}

RayResult make(Status st, double t, double hi = kNaN) {
    RayResult r;
    r.status = st;
    if (st == Status::Hit) r.t_lo = r.t_hi = r.t = t;
    if (st == Status::Unknown) {
        r.t_lo = r.t = t;
        r.t_hi = hi;
    }
    return r;
}

}  // namespace

RayResult hermite_first_root(const expr::Tape& tape, const Ray& ray,
                             const HermiteOptions& options) {
    thread_local expr::Evaluator<D> ev;
    RayResult r;
    auto g = [&](double t) {
        std::array<D, 3> p;
        for (int i = 0; i < 3; ++i) p[i] = D(ray.o[i] + t * ray.d[i], {ray.d[i]});
        ++r.evals.gradient;
        return ev(tape, p);
    };
    const bool zero_dir = ray.d[0] == 0 && ray.d[1] == 0 && ray.d[2] == 0;
    if (zero_dir || ray.tmin == ray.tmax) {
        const double v = g(ray.tmin).a;
        const EvalCounts e = r.evals;
        r = std::isnan(v) ? make(Status::Unknown, ray.tmin, ray.tmax)
            : v == 0      ? make(Status::Hit, ray.tmin)
                          : make(Status::Miss, 0);
        r.evals = e;
        return r;
    }
    if (!std::isfinite(ray.tmin) || !std::isfinite(ray.tmax) || !(ray.tmin < ray.tmax)) {
        r.status = Status::Unknown;
        r.t_lo = r.t = ray.tmin;
        r.t_hi = ray.tmax;
        return r;
    }
    const unsigned n = std::max(1u, options.samples);
    const double len = ray.tmax - ray.tmin;
    auto at = [&](unsigned k) { return k == n ? ray.tmax : ray.tmin + len * k / n; };
    auto finish = [&](Status st, double t, double hi = kNaN) {
        const EvalCounts e = r.evals;
        r = make(st, t, hi);
        r.evals = e;
        return r;
    };
    double t0 = ray.tmin;
    D g0 = g(t0);
    if (!std::isfinite(g0.a) || !std::isfinite(g0.v[0]))
        return finish(Status::Unknown, t0, ray.tmax);
    if (g0.a == 0) return finish(Status::Hit, t0);
    for (unsigned k = 1; k <= n; ++k) {
        const double t1 = at(k);
        const D g1 = g(t1);
        if (!std::isfinite(g1.a) || !std::isfinite(g1.v[0]))
            return finish(Status::Unknown, t0, ray.tmax);
        const double h = t1 - t0;
        const std::array<double, 4> c{g0.a, g0.a + h * g0.v[0] / 3, g1.a - h * g1.v[0] / 3, g1.a};
        const double s = first_root_cubic(c);
        if (!std::isnan(s)) {
            double t = std::clamp(t0 + h * s, t0, t1);
            if (options.newton) {
                const D gt = g(t);
                if (std::isfinite(gt.a) && gt.v[0] != 0 && std::isfinite(gt.v[0])) {
                    const double tn = t - gt.a / gt.v[0];
                    if (tn >= t0 && tn <= t1) t = tn;
                }
            }
            return finish(Status::Hit, t);
        }
        t0 = t1;
        g0 = g1;
    }
    return finish(Status::Miss, 0);
}

}  // namespace certray::solvers
