// solvers/analytic.cpp — piecewise-polynomial first roots: Poly evaluation on parameter
// intervals, split where a branch is undecided, each piece solved in closed form or certified by
// Bernstein isolation (see analytic.h).
#include "solvers/analytic.h"

#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "expr/eval.h"
#include "expr/op.h"
#include "interval/interval.h"
#include "interval/poly.h"
#include "solvers/bernstein.h"
#include "solvers/certified.h"
#include "solvers/closed_form.h"
#include "solvers/exact.h"
#include "solvers/polynomial_check.h"

namespace certray::solvers {
namespace {

using P = Poly<Interval>;

/// Scratch space of one thread.
struct Scratch {
    expr::Evaluator<P> eval;
    std::vector<Interval> stack;
    std::vector<Interval> coeffs;
};

/// The first root of the piece `g` on [a, b] by the closed forms (degree ≤ 4, approximate).
RayResult closed_form_piece(const P& g, double a, double b) {
    std::array<double, 5> c{};
    for (int k = 0; k <= g.degree; ++k) c[k] = midpoint(g.c[k]);
    std::array<double, 4> roots{};
    int n = 0;
    switch (g.degree) {
        case 1:
            if (c[1] != 0) roots[n++] = -c[0] / c[1];
            break;
        case 2:
            n = solve_quadratic(c[2], c[1], c[0], roots.data());
            break;
        case 3:
            n = solve_cubic(c[3], c[2], c[1], c[0], roots.data());
            break;
        default:
            n = solve_quartic(c[4], c[3], c[2], c[1], c[0], roots.data());
            break;
    }
    // A root a rounding error left of the piece is the root at its start.
    const double slack = 4 * std::numeric_limits<double>::epsilon() * std::fabs(a);
    RayResult r;
    for (int i = 0; i < n; ++i) {
        if (roots[i] >= a - slack && roots[i] <= b) {
            r.status = Status::Hit;
            r.t = std::max(a, roots[i]);
            r.t_lo = r.t_hi = r.t;
            return r;
        }
    }
    r.status = Status::Miss;
    return r;
}

/// The first root of one valid piece on [a, b].
RayResult solve_piece(const P& g, double a, double b, AnalyticOptions::Mode mode,
                      std::vector<Interval>& coeffs) {
    RayResult r;
    if (g.degree == 0) {  // constant on the piece
        const Interval& c = g.c[0];
        if (c.defined && c.lower() == 0 && c.upper() == 0) {
            r.status = Status::Hit;
            r.t_lo = r.t_hi = r.t = a;
        } else if (!possibly_zero(c)) {
            r.status = Status::Miss;
        } else {
            r.status = Status::Unknown;
            r.t_lo = a;
            r.t_hi = b;
            r.t = a;
        }
        return r;
    }
    if (mode == AnalyticOptions::Mode::ClosedForm && g.degree <= 4) {
        return closed_form_piece(g, a, b);
    }
    coeffs.assign(g.c.begin(), g.c.begin() + g.degree + 1);
    return first_root_bernstein(std::span<const Interval>(coeffs), a, b);
}

/// The analytic methods' rule: g is piecewise polynomial along every ray when every op but the
/// polynomial ones (and min, max, abs, split where they switch) sees only constants, and every
/// divisor is constant.
OpRule piecewise_polynomial_rule(expr::Op op) {
    switch (op) {
        case expr::Op::Sqrt:
        case expr::Op::Exp:
        case expr::Op::Log:
        case expr::Op::Sin:
        case expr::Op::Cos:
        case expr::Op::Floor:
        case expr::Op::Ceil:
        case expr::Op::Round:
        case expr::Op::Tan:
        case expr::Op::Asin:
        case expr::Op::Acos:
        case expr::Op::Atan:
        case expr::Op::Recip:
        case expr::Op::Not:
            return {Along::Refused, Along::Refused};
        case expr::Op::Atan2:
        case expr::Op::Compare:
        case expr::Op::Mod:
        case expr::Op::And:
        case expr::Op::Or:
            return {Along::Refused, Along::Refused};
        case expr::Op::Div:
            return {Along::Passes, Along::Refused};
        case expr::Op::Const:
        case expr::Op::VarX:
        case expr::Op::VarY:
        case expr::Op::VarZ:
        case expr::Op::Neg:
        case expr::Op::Abs:
        case expr::Op::Square:
        case expr::Op::Add:
        case expr::Op::Sub:
        case expr::Op::Mul:
        case expr::Op::Min:
        case expr::Op::Max:
        case expr::Op::Pow:
            return {};
    }
    return {Along::Never, Along::Never};
}

}  // namespace

std::string why_not_polynomial(const expr::Tape& tape) {
    return why_not_along(tape, &piecewise_polynomial_rule);
}

namespace {

RayResult analytic_search(const expr::Tape& tape, const Ray& ray, const AnalyticOptions& options) {
    thread_local Scratch s;
    RayResult result;
    auto unknown = [&](double lo, double hi) {
        result.status = Status::Unknown;
        result.t_lo = lo;
        result.t_hi = hi;
        result.t = lo;
        return result;
    };
    std::vector<Interval>& stack = s.stack;
    stack.clear();
    const double span = std::isfinite(ray.tmax - ray.tmin) ? ray.tmax - ray.tmin : 0.0;
    stack.push_back(Interval(ray.tmin, ray.tmax));
    while (!stack.empty()) {
        const Interval t = stack.back();
        stack.pop_back();
        if (result.evals.total() >= options.budget) return unknown(t.lower(), ray.tmax);
        std::array<P, 3> p;
        for (int i = 0; i < 3; ++i) p[i] = ray_coordinate(ray.o[i], ray.d[i], t);
        ++result.evals.interval;
        const P g = s.eval(tape, p);
        const double a = t.lower(), b = t.upper();
        if (!g.valid) {
            // A branch of min/max/abs is undecided on T (or g is not polynomial): split T, as a
            // blob field splits at the boundaries of its kernels' supports. Around a breakpoint
            // the branch stays undecided however small T gets: below 2⁻¹² of the ray's span (or
            // when T is unbounded) the certified solver takes that piece.
            const double m = midpoint(t);
            const bool small = !(b - a > span * 0x1p-12);
            if (!(std::isfinite(a) && std::isfinite(b) && a < m && m < b) || small) {
                CertifiedOptions co;
                co.budget = options.budget > result.evals.total()
                                ? options.budget - result.evals.total()
                                : 1;
                const RayResult c = certified_first_root(tape, Ray{ray.o, ray.d, a, b}, co);
                result.evals += c.evals;
                if (c.status == Status::Miss) continue;
                result.status = c.status;
                result.t_lo = c.t_lo;
                result.t_hi = c.t_hi;
                result.t = c.t;
                return result;
            }
            stack.push_back(Interval(m, b));
            stack.push_back(Interval(a, m));
            continue;
        }
        const RayResult piece = solve_piece(g, a, b, options.mode, s.coeffs);
        if (piece.status == Status::Miss) continue;
        result.status = piece.status;
        result.t_lo = piece.t_lo;
        result.t_hi = piece.t_hi;
        result.t = piece.t;
        // A proven enclosure from the coefficients is only as narrow as their enclosures allow
        // (1e-7 on the Barth sextic, where the coefficients cancel): the certified solver on the
        // tape itself, restricted to it, narrows it to ulps. Its first zero there is g's first.
        if (piece.status == Status::Hit && piece.t_lo < piece.t_hi &&
            piece.t_hi - piece.t_lo > 8 * std::numeric_limits<double>::epsilon() *
                                          std::max(std::fabs(piece.t_lo), std::fabs(piece.t_hi)) &&
            result.evals.total() < options.budget) {
            CertifiedOptions co;
            co.budget = options.budget - result.evals.total();
            const RayResult c =
                certified_first_root(tape, Ray{ray.o, ray.d, piece.t_lo, piece.t_hi}, co);
            result.evals += c.evals;
            if (c.status == Status::Hit) {
                result.t_lo = c.t_lo;
                result.t_hi = c.t_hi;
                result.t = c.t;
            }
        }
        return result;
    }
    result.status = Status::Miss;
    return result;
}

}  // namespace

RayResult analytic_first_root(const expr::Tape& tape, const Ray& ray,
                              const AnalyticOptions& options) {
    NearestScope env;  // sound in any caller's floating-point environment
    const RayResult r = analytic_search(tape, ray, options);
    // Certified (Bernstein) answers that floating point left undecided, or wider than 4 ulps,
    // re-decided by the exact oracle on a polynomial scene, as certified_first_root does.
    if (options.mode != AnalyticOptions::Mode::Bernstein) return r;
    return exact_fallback(tape, ray, r, options.budget);
}

}  // namespace certray::solvers
