// solvers/closed_form.h — real roots of polynomials of degree ≤ 4 in double, by robust closed
// forms.
//
// Contract: approximate, not certified. For polynomials with finite double coefficients the
// returned roots are real roots of the exact polynomial up to its conditioning: quadratics by the
// cancellation-free (citardauq) formula with the discriminant computed to nearly full precision
// (Kahan 2004, fma), cubics by Kahan's QBC (one root by a monotone Newton iteration, deflation,
// quadratic), quartics by isolating the real roots between the critical points (roots of p', a
// cubic) with sign tests in compensated arithmetic and bracketed Newton started from a Ferrari
// factorisation refined on its coefficients (Strobach 2010, Flocke 2015); cubic roots get Newton
// polishing on the original polynomial. The variable and the coefficients are first scaled by
// powers of two (exact) so that the largest root is of order 1: no overflow for coefficients of
// magnitude 1e-150 … 1e150. Roots come out ascending; a double root appears twice when the
// computed discriminant is ≥ 0. Leading zero coefficients reduce the degree; a zero polynomial
// returns 0 roots and sets *all_zero. Non-finite coefficients give 0 roots.
//
// References: docs/theory/closed_form.md; W. Kahan, "On the cost of floating-point computation
// without extra-precise arithmetic", 2004; W. Kahan, "To solve a real cubic equation", 1986;
// J. F. Blinn, "How to solve a cubic equation", IEEE CG&A 2006–2007; P. Strobach, "The fast
// quartic solver", J. Comput. Appl. Math. 234, 2010; N. Flocke, "Algorithm 954", ACM TOMS 41, 2015;
// D. Herbison-Evans, "Solving quartics and cubics for graphics", Graphics Gems V, 1995.
#pragma once

namespace certray::solvers {

/// Real roots of a·t² + b·t + c, ascending (a double root twice); returns their count (0–2).
/// a = 0 reduces to the linear case; all coefficients 0 → 0 roots and *all_zero = true if given.
int solve_quadratic(double a, double b, double c, double roots[2], bool* all_zero = nullptr);

/// Real roots of a·t³ + b·t² + c·t + d, ascending with multiplicities as found; count (0–3).
int solve_cubic(double a, double b, double c, double d, double roots[3], bool* all_zero = nullptr);

/// Real roots of a·t⁴ + b·t³ + c·t² + d·t + e, ascending with multiplicities as found; count
/// (0–4).
int solve_quartic(double a, double b, double c, double d, double e, double roots[4],
                  bool* all_zero = nullptr);

}  // namespace certray::solvers
