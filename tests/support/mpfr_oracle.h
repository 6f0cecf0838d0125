// The MPFR oracle for tests: exact comparisons between double enclosures and MPFR intervals.
//
// An MpfrInterval computed at high precision is the reference; a double interval [lo, hi] is a
// correct enclosure of it when every real of the reference lies in [lo, hi]. All comparisons are
// exact (mpfr_cmp_d), never through a rounded conversion.
#pragma once

#include <mpfr.h>

#include <array>
#include <string>

#include "expr/tape.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"

namespace certray::testing {

/// One MPFR number at 256 bits, cleared on scope exit: the exact side of a test of constants.
struct Mpfr256 {
    mpfr_t v;
    Mpfr256() { mpfr_init2(v, 256); }
    ~Mpfr256() { mpfr_clear(v); }
    Mpfr256(const Mpfr256&) = delete;
    Mpfr256& operator=(const Mpfr256&) = delete;
};

/// True iff [exact.lo, exact.hi] ⊆ [lo, hi], compared exactly. An empty `exact` is enclosed by
/// anything (even lo > hi); lo = −inf and hi = +inf are accepted; NaN bounds enclose nothing
/// nonempty.
bool encloses(double lo, double hi, const MpfrInterval& exact);

/// "[lo, hi] (prec P, defined|undefined)" with both bounds printed with 20 significant digits,
/// the lower rounded down and the upper rounded up; "[empty] (prec P)" for the empty set.
std::string describe(const MpfrInterval& x);

/// True iff |f(p) − f(q)| ≤ λ‖p − q‖, decided in MPFR (f evaluated in MpfrInterval at 256 bits at
/// both points; false also when f is undefined at either point).
bool lipschitz_holds(const expr::Tape& tape, double lambda, const std::array<double, 3>& p,
                     const std::array<double, 3>& q);

/// Whether the mean value form m + g1·(t − tc) along the segment {o + t·u : t ∈ [t0, t1]}, tc its
/// middle, holds f(o + t·u) at the nine t = t0 + k·(t1 − t0)/8 (points exact in double: a
/// DyadicSegment's, tests/support/generators.h), f by MPFR at 256 bits; false where f is undefined
/// at one of them. Points where f's value needs more than 100 bits (1e300 + (x² − 1e300): MPFR's
/// enclosure is wide and says nothing) are skipped.
bool mean_value_form_holds(const expr::Tape& tape, const std::array<double, 3>& o,
                           const std::array<double, 3>& u, double t0, double t1,
                           const UpInterval& m, const UpInterval& g1);

}  // namespace certray::testing
