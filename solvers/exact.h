// solvers/exact.h — the exact oracle for polynomial scenes: g(t) = f(o + t·d) with exact rational
// coefficients, its first root on [tmin, tmax] isolated by a Sturm sequence (Sturm 1829) and
// bisection at doubles.
//
// Contract (solvers/ray.h, DESIGN.md "Certification semantics"): every double of the tape and of
// the ray is taken at its exact rational value and every operation is exact (GMP rationals), so a
// Hit [t_lo, t_hi] encloses a real zero of g with none in [tmin, t_lo), a Miss proves none in
// [tmin, tmax]; nothing is rounded anywhere. A Hit is two adjacent doubles, or a single double
// when the root is exactly a double, unless the budget ran out first (then still a proven, wider
// Hit). Unknown only when the tape is not polynomial, the degree or the coefficients are beyond
// the limits below, or the budget ran out before the first count. Reference: docs/theory/exact.md.
#pragma once

#include <gmpxx.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::solvers {

/// The largest degree of g (and of any intermediate polynomial of the tape walk) the exact oracle
/// takes on; above it the answer is Unknown.
inline constexpr int kMaxExactDegree = 64;

/// The largest size, in bits, of one coefficient of the tape walk (a constant raised to a huge
/// power, say); above it the answer is Unknown.
inline constexpr long kMaxExactBits = 1L << 20;

/// g(t) = Σ c[k] t^k with exact rational coefficients; c is empty for the zero polynomial and its
/// last entry is never 0 otherwise.
struct ExactPoly {
    std::vector<mpq_class> c;
    /// The degree; −1 for the zero polynomial.
    int degree() const noexcept { return static_cast<int>(c.size()) - 1; }
};

struct ExactOptions {
    /// The most exact evaluations at a point (a Sturm sequence or one polynomial, see exact_root)
    /// spent on one ray; then the answer is Unknown, or a proven but wider Hit.
    std::uint64_t budget = 4096;
};

/// The first root with its multiplicity.
struct ExactRoot {
    RayResult result;
    /// For a Hit: the multiplicity of the root in g (1 simple, 2 tangent, …); 0 when g ≡ 0 (every
    /// t is a root) or when the budget ran out before the root was isolated. 0 for Miss, Unknown.
    int multiplicity = 0;
};

/// Empty when the tape is a polynomial in x, y, z with rational coefficients (Const, Var*, Neg,
/// Add, Sub, Mul, Square, Pow; Div by, and Abs, Min, Max of, expressions free of x, y, z), else a
/// sentence naming the first instruction that is not, e.g. "sqrt, not rational (instruction 7
/// of 11)".
/// Depends on the instructions only, not on a ray.
std::string why_not_exact_polynomial(const expr::Tape& tape);

/// why_not_exact_polynomial(tape).empty(), remembered per thread for the last tape asked
/// (Tape::serial), so that asking again for every ray of a scene costs a comparison.
bool is_polynomial(const expr::Tape& tape);

/// g(t) = f(o + t·d) exactly, as a polynomial in t; nullopt when the tape is not polynomial
/// (why_not_exact_polynomial), when a ray component is not finite, when a division by a constant
/// 0 is met, or when a degree or a coefficient exceeds kMaxExactDegree / kMaxExactBits.
std::optional<ExactPoly> exact_polynomial(const expr::Tape& tape, const Ray& ray);

/// The first root of g on [ray.tmin, ray.tmax] (tmin included: an exact zero there is the hit
/// [tmin, tmin]; g ≡ 0 is the hit [tmin, tmin] too). Evaluations: the tape walk over exact
/// polynomials counts as one interval evaluation (it gives g on the whole segment), each exact
/// evaluation at a point (of the Sturm sequence, or of one factor of g) as one value evaluation.
/// Thread-safe.
ExactRoot exact_root(const expr::Tape& tape, const Ray& ray, const ExactOptions& options = {});

/// exact_root(tape, ray, options).result.
RayResult exact_first_root(const expr::Tape& tape, const Ray& ray,
                           const ExactOptions& options = {});

/// `r`, the answer of a certified floating-point search on `ray`, re-decided by the exact oracle
/// when it is Unknown, or a Hit wider than 4 ulps (solvers/width.h, narrow) and `tighten`, and the
/// tape is a polynomial, within what is left of `budget` (its evaluations added); `r` itself
/// otherwise, or when the oracle gives up. The fallback of certified_first_root and of the
/// Bernstein method.
RayResult exact_fallback(const expr::Tape& tape, const Ray& ray, RayResult r, std::uint64_t budget,
                         bool tighten = true);

}  // namespace certray::solvers
