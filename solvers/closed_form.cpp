// solvers/closed_form.cpp — robust closed-form real roots of degree ≤ 4 (see closed_form.h).
//
// Pipeline for each degree n: reduce leading zeros, scale t = 2^k·u and the coefficients by a
// power of two (exact) so the leading coefficient lies in [1, 2) and every root satisfies
// |u| ≲ 4 (Fujiwara's bound), solve in u, polish, map back by ldexp (exact).
// Reference: docs/theory/closed_form.md.
#include "solvers/closed_form.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>

namespace certray::solvers {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// Scales p[0..n] (p[n] ≠ 0, p[j] the coefficient of t^j) into q: with t = 2^k·u,
/// q(u) = 2^(−M)·p(2^k u), k the smallest integer with |p_j|·2^(jk) ≲ |p_n|·2^(nk) for all j
/// (so |roots in u| ≤ 2·max (|q_j|/|q_n|)^(1/(n−j)) ≤ 4) and M making q_n ∈ [1, 2). Returns k.
/// Each coefficient is one ldexp: exact unless it underflows (only when it is below 2^−1022
/// relative to the leading one).
int scale_poly(const double* p, int n, double* q) {
    const int ln = std::ilogb(p[n]);
    int k = INT_MIN;
    for (int j = 0; j < n; ++j) {
        if (p[j] == 0) continue;
        const int kj = static_cast<int>(std::ceil(double(std::ilogb(p[j]) - ln) / (n - j)));
        k = std::max(k, kj);
    }
    if (k == INT_MIN) k = 0;
    const int m = ln + n * k;
    for (int j = 0; j <= n; ++j) q[j] = p[j] == 0 ? 0.0 : std::ldexp(p[j], j * k - m);
    return k;
}

/// b² − 4ac to nearly full precision (Kahan 2004): when the naive difference cancels, the exact
/// rounding errors of both products (recovered by fma) are added back.
double discriminant(double a, double b, double c) {
    const double p = b * b;
    const double q = (4.0 * a) * c;
    const double d = p - q;
    if (3.0 * std::abs(d) >= p + q) return d;
    const double dp = std::fma(b, b, -p);
    const double dq = std::fma(4.0 * a, c, -q);
    return (p - q) + (dp - dq);
}

/// Roots of a·u² + b·u + c (a ≠ 0, coefficients of moderate size) by the citardauq form.
/// `tolerant`: the coefficients were computed (deflation), so a negative discriminant within its
/// own rounding error (16 ε (b² + 4|ac|)) counts as a double root.
int quadratic_core(double a, double b, double c, double* r, bool tolerant) {
    double d = discriminant(a, b, c);
    if (d < 0) {
        if (!tolerant || -d > 16 * kEps * (b * b + 4 * std::abs(a * c))) return 0;
        d = 0;
    }
    const double q = -0.5 * (b + std::copysign(std::sqrt(d), b));
    if (q == 0) {  // b = 0 and d = 0, hence c = 0
        r[0] = r[1] = 0.0;
        return 2;
    }
    r[0] = q / a;
    r[1] = c / q;
    if (r[0] > r[1]) std::swap(r[0], r[1]);
    return 2;
}

/// p(x) by compensated Horner (Graillat, Langlois & Louvet 2005: as accurate as Horner in twice
/// the working precision; error-free products by fma) and p'(x) by plain Horner.
void horner2(const double* p, int n, double x, double& v, double& dv) {
    double s = p[n], err = 0;
    dv = 0;
    for (int j = n - 1; j >= 0; --j) {
        dv = dv * x + s;
        const double prod = s * x;
        const double prod_err = std::fma(s, x, -prod);
        const double sum = prod + p[j];
        const double z = sum - prod;
        const double sum_err = (prod - (sum - z)) + (p[j] - z);
        err = err * x + (prod_err + sum_err);
        s = sum;
    }
    v = s + err;
}

/// Sorts r[0..n) ascending (n ≤ 4): insertion sort.
void sort_small(double* r, int n) {
    for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && r[j] < r[j - 1]; --j) std::swap(r[j], r[j - 1]);
}

/// Newton steps on p (coefficients p[0..n]), each kept only if |p| (compensated) decreases; stops
/// after a step below an ulp or after kPolishSteps (a far start converges quadratically).
constexpr int kPolishSteps = 6;
double polish(const double* p, int n, double x) {
    double v, dv;
    horner2(p, n, x, v, dv);
    for (int it = 0; it < kPolishSteps && v != 0 && dv != 0; ++it) {
        const double step = v / dv;
        const double y = x - step;
        double w, dw;
        horner2(p, n, y, w, dw);
        if (!(std::abs(w) < std::abs(v))) break;
        x = y;
        v = w;
        dv = dw;
        if (std::abs(step) <= kEps * std::abs(x)) break;
    }
    return x;
}

/// Kahan's QBC on A·u³ + B·u² + C·u + D (A ≠ 0): one real root X by a Newton iteration that
/// approaches it monotonically from outside, then deflation to A·u² + b1·u + c2.
int cubic_core(double A, double B, double C, double D, double* r) {
    double X, b1, c2;
    if (D == 0) {
        X = 0;
        b1 = B;
        c2 = C;
    } else {
        double q0, Q, dQ;
        auto eval = [&](double x) {
            q0 = A * x;
            b1 = q0 + B;
            c2 = b1 * x + C;
            dQ = (q0 + b1) * x + c2;
            Q = c2 * x + D;
        };
        X = -(B / A) / 3;
        eval(X);
        double t = Q / A;
        double rr = std::cbrt(std::abs(t));
        const double s = t < 0 ? -1.0 : 1.0;
        t = -dQ / A;
        if (t > 0) rr = 1.324718 * std::max(rr, std::sqrt(t));
        double x0 = X - s * rr;
        if (x0 != X) {
            for (int it = 0; it < 500; ++it) {
                X = x0;
                eval(X);
                x0 = dQ == 0 ? X : X - (Q / dQ) / 1.000000000000001;
                if (!(s * x0 > s * X)) break;
            }
            if (std::abs(A) * X * X > std::abs(D / X)) {  // deflate backwards from D
                c2 = -D / X;
                b1 = (c2 - C) / X;
            }
        }
    }
    const double p[4] = {D, C, B, A};
    int n = quadratic_core(A, b1, c2, r, true);
    for (int i = 0; i < n; ++i) r[i] = polish(p, 3, r[i]);
    r[n++] = polish(p, 3, X);
    sort_small(r, n);
    return n;
}

/// Residual F of the factorisation x⁴+ax³+bx²+cx+d = (x²+α1x+β1)(x²+α2x+β2), f = (α1, β1, α2,
/// β2); returns Σ|F_i| / (the magnitude of the terms of F_i): a relative backward error per
/// equation, so that the factors of tiny roots are refined as well as those of large ones.
double factor_residual(const double* f, double a, double b, double c, double d, double* F) {
    F[0] = f[0] + f[2] - a;
    F[1] = f[1] + f[3] + f[0] * f[2] - b;
    F[2] = f[0] * f[3] + f[2] * f[1] - c;
    F[3] = f[1] * f[3] - d;
    const double m0 = std::abs(f[0]) + std::abs(f[2]) + std::abs(a);
    const double m1 = std::abs(f[1]) + std::abs(f[3]) + std::abs(f[0] * f[2]) + std::abs(b);
    const double m2 = std::abs(f[0] * f[3]) + std::abs(f[2] * f[1]) + std::abs(c);
    const double m3 = std::abs(f[1] * f[3]) + std::abs(d);
    auto rel = [](double r, double m) { return m > 0 ? std::abs(r) / m : std::abs(r); };
    return rel(F[0], m0) + rel(F[1], m1) + rel(F[2], m2) + rel(F[3], m3);
}

/// Solves the 4×4 system M x = v by Gaussian elimination with partial pivoting; false if singular.
bool solve4(double M[4][4], double v[4]) {
    for (int col = 0; col < 4; ++col) {
        int piv = col;
        for (int i = col + 1; i < 4; ++i)
            if (std::abs(M[i][col]) > std::abs(M[piv][col])) piv = i;
        if (M[piv][col] == 0 || !std::isfinite(M[piv][col])) return false;
        if (piv != col) {
            for (int j = 0; j < 4; ++j) std::swap(M[col][j], M[piv][j]);
            std::swap(v[col], v[piv]);
        }
        for (int i = col + 1; i < 4; ++i) {
            const double m = M[i][col] / M[col][col];
            for (int j = col; j < 4; ++j) M[i][j] -= m * M[col][j];
            v[i] -= m * v[col];
        }
    }
    for (int i = 3; i >= 0; --i) {
        for (int j = i + 1; j < 4; ++j) v[i] -= M[i][j] * v[j];
        v[i] /= M[i][i];
    }
    return true;
}

/// Quartic A·u⁴ + … + E (A ∈ [1, 2), E ≠ 0): Ferrari's factorisation from the largest root of
/// the resolvent cubic, refined by Newton's method on the factor coefficients (Strobach 2010),
/// then two quadratics and Newton polishing on the quartic. Used as starting points.
int ferrari_roots(double A, double B, double C, double D, double E, double* r) {
    const double a = B / A, b = C / A, c = D / A, d = E / A;
    double y3[3];
    const int ny = cubic_core(1.0, -b, a * c - 4 * d, -(a * a * d - 4 * b * d + c * c), y3);
    const double y = y3[ny - 1];  // the resolvent always has a real root
    const double e = a * a / 4 - b + y;
    const double g = e > 0 ? std::sqrt(e) : 0.0;
    const double k0 = a * y / 2 - c;
    const double h_sq = std::sqrt(std::max(0.0, y * y / 4 - d));
    // Two candidate constant offsets h; keep the factorisation with the smaller residual.
    double best[4] = {0, 0, 0, 0}, F[4];
    double best_res = std::numeric_limits<double>::infinity();
    const double hs[2] = {g > 0 ? k0 / (2 * g) : h_sq, std::copysign(h_sq, k0)};
    for (double h : hs) {
        double f[4] = {a / 2 + g, y / 2 + h, a / 2 - g, y / 2 - h};
        // Recompute the cancelling member of each pair from the larger one.
        if (std::abs(f[1]) > std::abs(f[3]) && f[1] != 0)
            f[3] = d / f[1];
        else if (f[3] != 0)
            f[1] = d / f[3];
        const double res = factor_residual(f, a, b, c, d, F);
        if (res < best_res) {
            best_res = res;
            std::copy(f, f + 4, best);
        }
    }
    for (int it = 0; it < 16 && best_res > 4 * kEps; ++it) {
        factor_residual(best, a, b, c, d, F);
        double M[4][4] = {{1, 0, 1, 0},
                          {best[2], 1, best[0], 1},
                          {best[3], best[2], best[1], best[0]},
                          {0, best[3], 0, best[1]}};
        double v[4] = {-F[0], -F[1], -F[2], -F[3]};
        if (!solve4(M, v)) break;
        double next[4];
        for (int i = 0; i < 4; ++i) next[i] = best[i] + v[i];
        const double res = factor_residual(next, a, b, c, d, F);
        if (!(res < best_res)) break;
        best_res = res;
        std::copy(next, next + 4, best);
    }
    int n = quadratic_core(1.0, best[0], best[1], r, true);
    n += quadratic_core(1.0, best[2], best[3], r + n, true);
    const double p[5] = {E, D, C, B, A};
    for (int i = 0; i < n; ++i) r[i] = polish(p, 4, r[i]);
    sort_small(r, n);
    return n;
}

/// The root of p in (l, h), where p(l) has sign sl and p(h) the opposite: Newton from x0,
/// falling back to bisection whenever a step leaves the bracket (which shrinks by sign).
double bracketed_root(const double* p, int n, double l, double h, double sl, double x) {
    if (!(x > l && x < h)) x = l + 0.5 * (h - l);
    for (int it = 0; it < 200; ++it) {
        double v, dv;
        horner2(p, n, x, v, dv);
        if (v == 0) return x;
        if ((v < 0) == (sl < 0))
            l = x;
        else
            h = x;
        const double step = dv != 0 ? v / dv : 0.0;
        // A step of a few ulps means x is the root to working accuracy (its sign is noise).
        if (dv != 0 && std::abs(step) <= 4 * kEps * std::abs(x) + 1e-300) return x - step;
        double next = x - step;
        if (!(next > l && next < h)) next = l + 0.5 * (h - l);
        if (next == x || !(h - l > 2 * kEps * std::max(std::abs(l), std::abs(h)))) return next;
        x = next;
    }
    return x;
}

/// Quartic A·u⁴ + … + E (A ∈ [1, 2)). The real roots are isolated by the critical points (the
/// real roots of the derivative, a cubic) and Fujiwara's bound: p is monotone between them, so
/// each sign change holds exactly one root, found by bracketed Newton started from the Ferrari
/// root inside; a critical point where p is exactly 0 is a multiple root (multiplicity: the
/// Ferrari roots near it, at least 2). The count is thus decided by signs of p evaluated with
/// compensated Horner, which clustered roots do not fool the way a factorisation can.
int quartic_core(double A, double B, double C, double D, double E, double* r) {
    if (E == 0) {
        int n = cubic_core(A, B, C, D, r);
        r[n++] = 0.0;
        sort_small(r, n);
        return n;
    }
    double f[4];
    const int nf = ferrari_roots(A, B, C, D, E, f);
    const double p[5] = {E, D, C, B, A};
    double crit[3];
    const int nc = cubic_core(4 * A, 3 * B, 2 * C, D, crit);
    // Fujiwara: every root has |u| ≤ 2·max |p_j/p_4|^(1/(4−j)) < 4, since scale_poly made
    // p_4 ∈ [1, 2) and every |p_j| < 2.
    const double bound = 4.5;
    double pts[5];
    int np = 0;
    pts[np++] = -bound;
    for (int i = 0; i < nc; ++i)
        if (crit[i] > pts[np - 1] && crit[i] < bound) pts[np++] = crit[i];
    pts[np++] = bound;
    double val[5];
    for (int i = 0; i < np; ++i) {
        double dv;
        horner2(p, 4, pts[i], val[i], dv);
    }
    int n = 0;
    for (int i = 0; i + 1 < np && n < 4; ++i) {
        if (i > 0 && val[i] == 0) {  // a multiple root at a critical point
            int m = 0;
            const double tol = 1e-4 * (1 + std::abs(pts[i]));
            for (int k = 0; k < nf; ++k)
                if (std::abs(f[k] - pts[i]) <= tol) ++m;
            for (int k = 0; k < std::max(m, 2) && n < 4; ++k) r[n++] = pts[i];
            continue;
        }
        if (val[i] == 0 || val[i + 1] == 0 || (val[i] < 0) == (val[i + 1] < 0)) continue;
        double start = pts[i] + 0.5 * (pts[i + 1] - pts[i]);
        for (int k = 0; k < nf; ++k)
            if (f[k] > pts[i] && f[k] < pts[i + 1]) start = f[k];
        r[n++] = bracketed_root(p, 4, pts[i], pts[i + 1], val[i], start);
    }
    sort_small(r, n);
    return n;
}

/// Maps roots u back to t = 2^k·u, dropping those beyond the double range.
int unscale(double* r, int n, int k, double* out) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const double t = std::ldexp(r[i], k);
        if (std::isfinite(t)) out[m++] = t;
    }
    return m;
}

bool all_finite(std::initializer_list<double> v) {
    for (double x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

}  // namespace

int solve_quadratic(double a, double b, double c, double roots[2], bool* all_zero) {
    if (all_zero) *all_zero = false;
    if (!all_finite({a, b, c})) return 0;
    if (a == 0) {
        if (b == 0) {
            if (all_zero) *all_zero = c == 0;
            return 0;
        }
        const double t = -c / b;
        if (!std::isfinite(t)) return 0;
        roots[0] = t;
        return 1;
    }
    const double p[3] = {c, b, a};
    double q[3], r[2];
    const int k = scale_poly(p, 2, q);
    const int n = quadratic_core(q[2], q[1], q[0], r, false);
    return unscale(r, n, k, roots);
}

int solve_cubic(double a, double b, double c, double d, double roots[3], bool* all_zero) {
    if (a == 0) return solve_quadratic(b, c, d, roots, all_zero);
    if (all_zero) *all_zero = false;
    if (!all_finite({a, b, c, d})) return 0;
    const double p[4] = {d, c, b, a};
    double q[4], r[3];
    const int k = scale_poly(p, 3, q);
    const int n = cubic_core(q[3], q[2], q[1], q[0], r);
    return unscale(r, n, k, roots);
}

int solve_quartic(double a, double b, double c, double d, double e, double roots[4],
                  bool* all_zero) {
    if (a == 0) return solve_cubic(b, c, d, e, roots, all_zero);
    if (all_zero) *all_zero = false;
    if (!all_finite({a, b, c, d, e})) return 0;
    const double p[5] = {e, d, c, b, a};
    double q[5], r[4];
    const int k = scale_poly(p, 4, q);
    const int n = quartic_core(q[4], q[3], q[2], q[1], q[0], r);
    return unscale(r, n, k, roots);
}

}  // namespace certray::solvers
