// tests/support/independent_oracle.h — a judge of certified answers that shares no root logic with
// the solvers it judges.
//
// Contract: judge_claim(tape, ray, claim) checks one RayResult of a certified method against the
// semantics of solvers/ray.h, by two routes that do not call solvers/certified.h:
//  - exact (polynomial tapes, solvers::is_polynomial): solvers::exact_first_root (GMP rationals,
//    Sturm sequences) on the ray and on its sub-ranges [tmin, t_lo] and [t_lo, t_hi] decides
//    whether the exact first root lies in the claimed [t_lo, t_hi], or that there is none (Miss);
//  - MPFR (any tape): g(t) = f(o + t·d) is enclosed by expr::eval<MpfrInterval> at 256 bits over
//    dyadic pieces of t built exactly from the ray's doubles; a Hit's zero is proven by an exact
//    zero at a double t, or by strict opposite signs at two doubles a ≤ b of [t_lo, t_hi] with
//    every piece of [a, b] decorated defined (continuity); "no zero in [tmin, t_lo)" and a Miss's
//    "no zero in [tmin, tmax]" by adaptive subdivision until each piece's enclosure excludes 0 (an
//    infinite tmax is covered by doubling pieces and one unbounded tail). A proven zero before
//    t_lo (or anywhere, for a Miss), found by sampling, refutes the claim.
// Refuted means the claim is proven wrong; Unverified means neither route could decide within
// its budget (never a failure by itself: tests bound how often it happens). Unknown answers are
// always allowed; their "no zero in [tmin, t_lo)" is checked for refutation only.
// Reference: docs/theory/certified.md, "Who judges the judge".
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::testing {

enum class Verdict : std::uint8_t { Confirmed, Unverified, Refuted, NotApplicable };

std::string_view name(Verdict v) noexcept;

struct OracleOptions {
    /// MPFR precision in bits of every enclosure.
    long precision = 256;
    /// MPFR enclosures spent on excluding zeros from [tmin, t_lo) or [tmin, tmax] (4 per piece:
    /// the piece, its two ends, its derivative).
    long exclusion_budget = 3000;
    /// MPFR enclosures spent on proving continuity between two points of opposite sign.
    long continuity_budget = 200;
    /// Interior sample points of [t_lo, t_hi] tried for a sign change (besides both ends).
    int existence_samples = 16;
    /// Sample points of [tmin, t_lo) tried for a proven zero when exclusion fails (refutation).
    int refute_samples = 64;
    /// Budget of each exact_first_root call.
    std::uint64_t exact_budget = 1u << 14;
    /// Run the exact route on polynomial tapes.
    bool use_exact = true;
    /// Run the MPFR route.
    bool use_mpfr = true;
};

/// The judge's answer for one claim.
struct Judgement {
    /// Refuted if either route refutes, else Confirmed if either confirms, else Unverified;
    /// Confirmed for an Unknown claim that is not refuted.
    Verdict verdict = Verdict::Unverified;
    /// The exact route's answer; NotApplicable when the tape is not polynomial (or disabled).
    Verdict exact = Verdict::NotApplicable;
    /// The MPFR route's answer; NotApplicable when disabled.
    Verdict mpfr = Verdict::NotApplicable;
    /// What was decided and why, for failure messages.
    std::string why;
};

/// Judges `claim`, the answer of a certified method for g(t) = f(o + t·d) on [ray.tmin, ray.tmax].
/// Thread-safe (no shared state).
Judgement judge_claim(const expr::Tape& tape, const Ray& ray, const RayResult& claim,
                      const OracleOptions& options = {});

/// Counts of claims and verdicts over a property run (not thread-safe).
struct OracleTally {
    std::uint64_t hits = 0, misses = 0, unknowns = 0;
    std::uint64_t confirmed = 0, unverified = 0, refuted = 0;
    /// Hit/Miss claims confirmed by the exact route, by the MPFR route.
    std::uint64_t exact_confirmed = 0, mpfr_confirmed = 0;
    /// Hit/Miss claims on polynomial tapes that the MPFR route left unverified.
    std::uint64_t mpfr_unverified_polynomial = 0;

    void add(const RayResult& claim, const Judgement& j);
    /// judge_claim, counted; with CERTRAY_ORACLE_VERBOSE set in the environment, prints every
    /// unverified claim with the reason (what the budget could not decide).
    Judgement judge(const expr::Tape& tape, const Ray& ray, const RayResult& claim,
                    const OracleOptions& options = {});
    /// At most `fraction` of the Hit and Miss claims unverified.
    bool unverified_at_most(double fraction) const noexcept {
        return static_cast<double>(unverified) <= fraction * static_cast<double>(claims());
    }
    /// Hit and Miss claims (the ones a verdict is about).
    std::uint64_t claims() const noexcept { return hits + misses; }
    /// One line: "NAME: H hits, M misses, U unknowns; confirmed C (exact E, mpfr P), unverified V,
    /// refuted R".
    std::string summary(std::string_view what) const;
};

/// "ray o (..) d (..) t [tmin, tmax]: hit [t_lo, t_hi]" with 17 significant digits.
std::string describe(const Ray& ray, const RayResult& r);

}  // namespace certray::testing
