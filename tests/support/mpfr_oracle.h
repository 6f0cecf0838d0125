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

}  // namespace certray::testing
