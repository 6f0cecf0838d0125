// interval/interval.h — binary64 intervals on Boost.Interval: sound outward rounding, decoration.
//
// Contract: for every operation op and all x in X (and y in Y) where op is defined, op(x, y) lies
// in op(X, Y). Set-based IEEE 1788 semantics: functions act on the intersection of the box with
// their domain (sqrt([-5, 25]) = [0, 5]), division by a box containing 0 gives the hull of the
// quotients ([1, 2] / [0, 1] = [1, +inf]), and division by [0, 0] is empty.
// The decoration `defined` says more: the function is defined and continuous on the *whole* input
// box. A certified root finder may trust a sign change only where it holds.
//
// Rounding: everything is computed in upward mode, lower bounds by negation (RD(x ∘ y) =
// −RU((−x) ∘ y), Boost's `rounded_arith_opp`). `Interval` sets the mode around every operation and
// restores the caller's; inside a `RoundingScope`, `UpInterval` skips that and costs a few doubles
// (docs/theory/interval.md, docs/benchmarks.md). Every rounded operation reads its operands through
// an empty `asm volatile` register barrier and writes its result through another (`opaque`, as
// CGAL's IA_opacify): the compiler can neither fold it, nor reuse a value computed under another
// mode, nor move it across a mode switch (volatile asms keep their order) — where Boost forces each
// result through a `volatile` memory store. On x86-64 the mode is switched by writing MXCSR and the
// x87 control word directly (what glibc's fesetround does, without the libm call).
// + − × square sqrt abs min max are branch-free on the common path (one predictable test sends
// infinities, NaN and empty operands to Boost's case tables: the same bounds, bit for bit, up to
// the sign of a zero bound); ÷ and pow are Boost's. exp and log on x86-64 (exp where |x| ≤ 708,
// x ≠ 0; log at normal x ≠ 1): the bounds of interval/exp_log_kernel.h (polynomials in upward
// mode, no libm); sin and cos on x86-64 over boxes within ±2¹⁹: interval/trig_kernel.h's.
// Otherwise exp, log, sin, cos: glibc ignores the rounding
// mode, so the round-to-nearest result is widened outward by kTranscUlps ulps (glibc documents
// ≤ 1 ulp for these on x86_64), with exact values at the points where the function value is
// exactly representable; both bounds of an interval are computed under one switch to
// round-to-nearest (WidenedTransc: exp_bounds, log_bounds, trig_bounds, which also places the
// extrema of sin and cos from outward bounds of x/π).
#pragma once

#include <bit>
#include <boost/numeric/interval.hpp>
#include <cassert>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <limits>

#if defined(__GNUC__) && defined(__x86_64__)
#include <emmintrin.h>
#define CERTRAY_X86_64_ROUNDING 1
#endif

#include "interval/exp_log_kernel.h"
#include "interval/trig_kernel.h"

namespace certray {

namespace detail {

namespace bil = boost::numeric::interval_lib;

/// Ulps by which a glibc round-to-nearest transcendental result is widened outward.
inline constexpr int kTranscUlps = 2;

/// RD(π), RU(π), RD(π/2), RU(π/2).
inline constexpr double kPiLo = TrigKernel::kPiLo, kPiHi = TrigKernel::kPiHi;
inline constexpr double kHalfPiLo = 0x1.921fb54442d18p+0, kHalfPiHi = 0x1.921fb54442d19p+0;

/// The next double above v (std::nextafter(v, +inf) without the library call, whatever the
/// floating-point environment: the representation's order is the numbers' order); +inf and NaN
/// are kept.
inline double next_up(double v) {
    if (!(v < std::numeric_limits<double>::infinity())) return v;
    if (v == 0) return std::numeric_limits<double>::denorm_min();
    const std::uint64_t b = std::bit_cast<std::uint64_t>(v);
    return std::bit_cast<double>(v > 0 ? b + 1 : b - 1);
}

/// The next double below v; −inf and NaN are kept.
inline double next_down(double v) { return -next_up(-v); }

/// n steps of next_up. Where 2^-1000 ≤ |v| ≤ 2^1000 (and 0 ≤ n ≤ 2^20) no step crosses 0 or
/// reaches ±inf, and the representation's order is the numbers' order: the steps are one integer
/// addition (the loop elsewhere; tests/interval/interval_test.cpp checks both against nextafter).
inline double step_up(double v, int n) {
    const double a = v < 0 ? -v : v;
    if (a >= 0x1p-1000 && a <= 0x1p1000 && n >= 0 && n <= (1 << 20)) {
        const std::uint64_t b = std::bit_cast<std::uint64_t>(v);
        const auto k = static_cast<std::uint64_t>(n);
        return std::bit_cast<double>(v > 0 ? b + k : b - k);
    }
    for (int i = 0; i < n; ++i) v = next_up(v);
    return v;
}

/// n steps of next_down (as step_up, mirrored).
inline double step_down(double v, int n) { return -step_up(-v, n); }

/// Hides x from the optimiser at this point of the program: the compiler must assume any value
/// comes out, so an operation on the result cannot be constant-folded, merged with the same
/// operation computed under another rounding mode, or moved before a mode switch (the barrier is
/// an `asm volatile`, kept in order with the mode-switching asm). Costs no instruction.
inline double opaque(double x) {
#if defined(__GNUC__) && (defined(__x86_64__) || (defined(__i386__) && defined(__SSE2_MATH__)))
    asm volatile("" : "+x"(x));
#elif defined(__GNUC__) && defined(__aarch64__)
    asm volatile("" : "+w"(x));
#else
    volatile double v = x;
    x = v;
#endif
    return x;
}

#ifdef CERTRAY_X86_64_ROUNDING
/// Boost rounding control for x86-64: sets the rounding fields of both the SSE unit (MXCSR) and
/// the x87 unit, as glibc's fesetround does (fegetround reads the x87 one), by inline assembly
/// instead of two libm calls per switch; `set` leaves a unit already in the wanted mode alone.
/// `rounding_mode` holds both control words whole, and restoring it writes them back as they were
/// read (MXCSR's exception flags included: flags raised in between are dropped, not reported).
/// Results are forced to double by `opaque` instead of a volatile store.
struct X86RoundingControl {
    /// MXCSR and the x87 control word (rounding field: 0 nearest, 1 down, 2 up, 3 toward zero).
    struct rounding_mode {
        unsigned mxcsr = 0x1f80;
        unsigned short x87 = 0x037f;
    };
    static rounding_mode current() {
        rounding_mode m;
        asm volatile("stmxcsr %0" : "=m"(m.mxcsr));
        asm volatile("fnstcw %0" : "=m"(m.x87));
        return m;
    }
    /// The whole environment certray computes in, with rounding direction rc: MXCSR with every
    /// exception masked, flush-to-zero (bit 15) and denormals-are-zero (bit 6) clear; the x87 word
    /// with every exception masked, 64-bit precision and round-to-nearest whatever rc is. Nothing
    /// of the caller's MXCSR is kept: a host running with FTZ|DAZ (game engines, objects built
    /// with -ffast-math) would otherwise flush a subnormal bound to a zero that is not one. The
    /// x87 unit computes nothing of certray's (binary64 runs in SSE registers on x86-64, there is
    /// no long double, and glibc's exp, log, sin and cos ignore the x87 word: tests/interval/
    /// interval_test.cpp, "LibmIgnoresTheX87Word"), so its rounding field is not switched: fldcw
    /// is serialising, and a host in the default state then never has that word written. The
    /// caller's words are restored when the scope that called this ends.
    static constexpr rounding_mode canonical(unsigned rc) {
        rounding_mode m;
        m.mxcsr = 0x1f80u | (rc << 13);
        m.x87 = 0x037fu;
        return m;
    }
    /// Writes the words of `to` that differ from `from` (the current state).
    static void write(const rounding_mode& to, const rounding_mode& from) {
        if (to.mxcsr != from.mxcsr) asm volatile("ldmxcsr %0" : : "m"(to.mxcsr) : "memory");
        if (to.x87 != from.x87) asm volatile("fldcw %0" : : "m"(to.x87) : "memory");
    }
    static void set(unsigned rc) {
        const rounding_mode now = current();
        write(canonical(rc), now);
    }
    static void get_rounding_mode(rounding_mode& mode) { mode = current(); }
    /// Restores `mode` (Boost's save_state): MXCSR always, the x87 word only where it differs
    /// from the current one (it is canonical in every scope, so only a host's own word is ever
    /// written back; fldcw is serialising).
    static void set_rounding_mode(const rounding_mode& mode) {
        asm volatile("ldmxcsr %0" : : "m"(mode.mxcsr) : "memory");
        unsigned short x87;
        asm volatile("fnstcw %0" : "=m"(x87));
        if (x87 != mode.x87) asm volatile("fldcw %0" : : "m"(mode.x87) : "memory");
    }
    static void to_nearest() { set(0); }
    static void downward() { set(1); }
    static void upward() { set(2); }
    static void toward_zero() { set(3); }
    static double to_int(const double& r) { return std::rint(r); }
    static double force_rounding(const double& r) { return opaque(r); }
};
using RoundingControl = X86RoundingControl;
#else
using RoundingControl = bil::rounding_control<double>;
#endif

/// RD(√x) for x ≥ 0 (or +inf) in upward mode, without switching the mode: r = RU(√x) is exact iff
/// RU(r · r) = x (if r > √x then RU(r · r) ≥ r² > x), and otherwise RD(√x) is r's predecessor.
inline double sqrt_rd(double x) {
    const double r = opaque(std::sqrt(opaque(x)));
    const bool exact = opaque(r * r) == x;
    return exact ? r : std::bit_cast<double>(std::bit_cast<std::uint64_t>(r) - 1);
}

/// Transcendental point bounds for Boost's rounding policy: f_down(x) <= f(x) <= f_up(x).
/// Computes in round-to-nearest and returns to upward mode, the invariant of rounded_arith_opp.
template <class Rounding>
struct WidenedTransc : Rounding {
    /// f(x) in round-to-nearest; the mode before the call (upward) is restored.
    template <class F>
    double nearest(F f, double x) {
        x = opaque(x);  // computed before the switch
#ifdef CERTRAY_X86_64_ROUNDING
        const X86RoundingControl::rounding_mode saved = X86RoundingControl::current();
        X86RoundingControl::write(X86RoundingControl::canonical(0), saved);
        const double r = opaque(f(x));
        X86RoundingControl::write(saved, X86RoundingControl::canonical(0));
#else
        typename Rounding::rounding_mode saved;
        this->get_rounding_mode(saved);
        this->to_nearest();
        const double r = this->force_rounding(f(x));
        this->set_rounding_mode(saved);
#endif
        return r;
    }
    /// f(a) and f(b) in round-to-nearest under one switch of the mode, for the two bounds of a
    /// monotone function. Called only by the interval operations, whose state is always a
    /// RoundingScope's (canonical upward: ProtectedRounding's guard is one, UpwardRounding runs
    /// inside one), so on x86-64 MXCSR is written as constants, nearest then upward, without
    /// reading it first (the x87 word, never switched, is canonical already: canonical()).
    template <class F>
    void nearest2(F f, double& a, double& b) {
        a = opaque(a);
        b = opaque(b);
#ifdef CERTRAY_X86_64_ROUNDING
        static constexpr unsigned kNearest = X86RoundingControl::canonical(0).mxcsr;
        static constexpr unsigned kUpward = X86RoundingControl::canonical(2).mxcsr;
        assert((X86RoundingControl::current().mxcsr & ~0x3fu) == kUpward);  // flags aside
        asm volatile("ldmxcsr %0" : : "m"(kNearest) : "memory");
        a = opaque(f(a));
        b = opaque(f(b));
        asm volatile("ldmxcsr %0" : : "m"(kUpward) : "memory");
#else
        typename Rounding::rounding_mode saved;
        this->get_rounding_mode(saved);
        this->to_nearest();
        a = this->force_rounding(f(a));
        b = this->force_rounding(f(b));
        this->set_rounding_mode(saved);
#endif
    }
    /// [exp_down(lo), exp_up(hi)] in place (lo ≤ hi, not NaN), with one mode switch.
    void exp_bounds(double& lo, double& hi) {
        double ea = lo, eb = hi;
        nearest2(exp_rn, ea, eb);
        lo = exp_below(lo, ea);
        hi = exp_above(hi, eb);
    }
    /// [log_down(lo), log_up(hi)] in place (0 < lo ≤ hi, not NaN), with one mode switch.
    void log_bounds(double& lo, double& hi) {
        double la = lo, lb = hi;
        nearest2(log_rn, la, lb);
        lo = log_below(lo, la);
        hi = log_above(hi, lb);
    }
    static double exp_rn(double x) { return std::exp(x); }
    static double log_rn(double x) { return std::log(x); }
    static double sin_rn(double x) { return std::sin(x); }
    static double cos_rn(double x) { return std::cos(x); }

    // sqrt below without the two mode switches of rounded_arith_opp (x ≥ 0 here).
    double sqrt_down(double x) { return sqrt_rd(x); }

    // exp: exact at 0 and ±inf; below by kTranscUlps ulps, clamped at 0. exp_below(x, r) and
    // exp_above(x, r) turn r, exp(x) rounded to nearest, into the bounds.
    static double exp_below(double x, double r) {
        if (x == 0) return 1.0;
        if (std::isinf(x)) return x > 0 ? x : 0.0;
        r = step_down(r, kTranscUlps);
        return r < 0 ? 0.0 : r;
    }
    static double exp_above(double x, double r) {
        if (x == 0) return 1.0;
        if (std::isinf(x)) return x > 0 ? x : 0.0;
        return step_up(r, kTranscUlps);
    }
    double exp_down(double x) { return exp_below(x, nearest(exp_rn, x)); }
    double exp_up(double x) { return exp_above(x, nearest(exp_rn, x)); }
    // log (called by Boost only for x > 0): exact at 1 and +inf; log_below and log_above as for
    // exp.
    static double log_below(double x, double r) {
        return x == 1 ? 0.0 : std::isinf(x) ? x : step_down(r, kTranscUlps);
    }
    static double log_above(double x, double r) {
        return x == 1 ? 0.0 : std::isinf(x) ? x : step_up(r, kTranscUlps);
    }
    double log_down(double x) { return log_below(x, nearest(log_rn, x)); }
    double log_up(double x) { return log_above(x, nearest(log_rn, x)); }
    // sin, cos: exact at 0, clamped to [-1, 1].
    double sin_down(double x) {
        if (x == 0) return x;
        double r = step_down(nearest(sin_rn, x), kTranscUlps);
        return r < -1 ? -1.0 : r;
    }
    double sin_up(double x) {
        if (x == 0) return x;
        double r = step_up(nearest(sin_rn, x), kTranscUlps);
        return r > 1 ? 1.0 : r;
    }
    double cos_down(double x) {
        if (x == 0) return 1.0;
        double r = step_down(nearest(cos_rn, x), kTranscUlps);
        return r < -1 ? -1.0 : r;
    }
    double cos_up(double x) {
        if (x == 0) return 1.0;
        double r = step_up(nearest(cos_rn, x), kTranscUlps);
        return r > 1 ? 1.0 : r;
    }
    /// cos (sine = false) or sin over [lo, hi] (finite, lo ≤ hi) in place, in upward mode, with
    /// one mode switch: the endpoint values widened by kTranscUlps ulps (exact at 0), and ±1
    /// wherever an extremum may lie inside. The extrema of cos are at kπ, those of sin at
    /// π/2 + kπ (1 for even k, −1 for odd k): the k with kπ (+ π/2) in [lo, hi] lie between
    /// lo/π and hi/π (− 1/2), bounded outward with π ∈ [M_PI, next_up(M_PI)].
    void trig_bounds(bool sine, double& lo, double& hi) {
        const double l = lo, u = hi;
        if (!(u - l < 2 * kPiLo)) {  // a whole period (the width rounded up)
            lo = -1.0;
            hi = 1.0;
            return;
        }
        // Outward bounds of l/π and u/π (upward mode: a quotient rounded down is −((−a)/b)).
        double qlo = -((-l) / (l >= 0 ? kPiHi : kPiLo));
        double qhi = u / (u >= 0 ? kPiLo : kPiHi);
        if (sine) {
            qlo = -(0.5 - qlo);
            qhi = qhi - 0.5;
        }
        qlo = opaque(qlo);  // rounded upward, before the switch
        qhi = opaque(qhi);
        double a = l, b = u;
        nearest2(sine ? sin_rn : cos_rn, a, b);
        const double at0 = sine ? 0.0 : 1.0;  // exact values at 0
        const double la = l == 0 ? at0 : step_down(a, kTranscUlps);
        const double lb = u == 0 ? at0 : step_down(b, kTranscUlps);
        const double ua = l == 0 ? at0 : step_up(a, kTranscUlps);
        const double ub = u == 0 ? at0 : step_up(b, kTranscUlps);
        lo = std::max(-1.0, std::min(la, lb));
        hi = std::min(1.0, std::max(ua, ub));
        if (!(std::fabs(qlo) < 0x1p52 && std::fabs(qhi) < 0x1p52)) {  // k's parity unknown
            lo = -1.0;
            hi = 1.0;
            return;
        }
        const double k0 = std::ceil(qlo), k1 = std::floor(qhi);
        if (k0 > k1) return;  // no extremum inside: monotone
        if (k1 > k0) {        // two extrema, of both signs
            lo = -1.0;
            hi = 1.0;
            return;
        }
        if (std::fmod(k0, 2.0) == 0) {
            hi = 1.0;
        } else {
            lo = -1.0;
        }
    }
};

using IntervalArith = WidenedTransc<bil::rounded_arith_opp<double, RoundingControl>>;
using Checking = bil::checking_base<double>;

}  // namespace detail

/// Sets the rounding mode upward for its lifetime and restores the caller's mode at the end.
/// Hoist one scope out of a loop of `UpInterval` operations; do not call libm or code that assumes
/// round-to-nearest inside it. On x86-64 the caller's control words are written back as they were
/// read (MXCSR always, the x87 word only if it was not canonical already); floating-point exception
/// flags raised inside the scope are not kept.
class RoundingScope {
  public:
#ifdef CERTRAY_X86_64_ROUNDING
    RoundingScope() : saved_(detail::X86RoundingControl::current()) {
        detail::X86RoundingControl::write(detail::X86RoundingControl::canonical(2), saved_);
    }
    ~RoundingScope() {
        detail::X86RoundingControl::write(saved_, detail::X86RoundingControl::canonical(2));
    }
#else
    RoundingScope() = default;
#endif
    RoundingScope(const RoundingScope&) = delete;
    RoundingScope& operator=(const RoundingScope&) = delete;

  private:
#ifdef CERTRAY_X86_64_ROUNDING
    detail::X86RoundingControl::rounding_mode saved_;
#else
    boost::numeric::interval_lib::save_state<detail::IntervalArith> state_;
#endif
};

/// The environment plain double arithmetic is sound in, for its lifetime: round-to-nearest,
/// flush-to-zero and denormals-are-zero clear, exceptions masked; the caller's control words are
/// restored exactly at the end (also when an exception leaves the scope). Every entry point of
/// the library that computes in doubles (a ray's points o + t·d rounded one ulp outward, the
/// batch walk's signs) opens one, so a host that runs with FTZ|DAZ or another rounding direction
/// gets the same answers as one that does not. Costs two control-word reads and writes.
class NearestScope {
  public:
#ifdef CERTRAY_X86_64_ROUNDING
    NearestScope() : saved_(detail::X86RoundingControl::current()) {
        detail::X86RoundingControl::write(detail::X86RoundingControl::canonical(0), saved_);
    }
    ~NearestScope() {
        detail::X86RoundingControl::write(saved_, detail::X86RoundingControl::canonical(0));
    }
#else
    NearestScope() : saved_(std::fegetround()) { std::fesetround(FE_TONEAREST); }
    ~NearestScope() { std::fesetround(saved_); }
#endif
    NearestScope(const NearestScope&) = delete;
    NearestScope& operator=(const NearestScope&) = delete;

  private:
#ifdef CERTRAY_X86_64_ROUNDING
    detail::X86RoundingControl::rounding_mode saved_;
#else
    int saved_;
#endif
};

/// Round-to-nearest for a stretch of code inside a live RoundingScope (upward mode): what
/// NearestScope does, with the two states known (every scope's x87 word is canonical, as nearest2
/// assumes): two constant MXCSR writes and no reads of the control words, which cost more than the
/// writes where a loop opens one per item (a coherent image's normals).
class NearestInUpward {
  public:
#ifdef CERTRAY_X86_64_ROUNDING
    NearestInUpward() {
        assert((detail::X86RoundingControl::current().mxcsr & ~0x3fu) == kUpward);  // flags aside
        asm volatile("ldmxcsr %0" : : "m"(kNearest) : "memory");
    }
    ~NearestInUpward() { asm volatile("ldmxcsr %0" : : "m"(kUpward) : "memory"); }
#else
    NearestInUpward() = default;
#endif
    NearestInUpward(const NearestInUpward&) = delete;
    NearestInUpward& operator=(const NearestInUpward&) = delete;

  private:
#ifdef CERTRAY_X86_64_ROUNDING
    static constexpr unsigned kNearest = detail::X86RoundingControl::canonical(0).mxcsr;
    static constexpr unsigned kUpward = detail::X86RoundingControl::canonical(2).mxcsr;
#else
    NearestScope scope_;
#endif
};

/// Every operation saves, sets and restores the rounding mode: safe anywhere.
struct ProtectedRounding {
    using Policies = boost::numeric::interval_lib::policies<
        boost::numeric::interval_lib::save_state<detail::IntervalArith>, detail::Checking>;
    /// Held for the duration of each operation.
    using Guard = RoundingScope;
};

/// Operations assume the mode is upward: valid only inside a live `RoundingScope`.
struct UpwardRounding {
    using Policies = boost::numeric::interval_lib::policies<
        boost::numeric::interval_lib::save_state_nothing<detail::IntervalArith>, detail::Checking>;
    /// Nothing to hold: the caller's scope has set the mode.
    struct Guard {};
};

/// A closed binary64 interval [lower, upper] (possibly unbounded or empty) with a decoration.
/// `Mode` says whether its operations protect the rounding mode (see ProtectedRounding).
template <class Mode>
struct BasicInterval {
    using Boost = boost::numeric::interval<double, typename Mode::Policies>;

    /// The enclosure itself; empty is represented by Boost as NaN bounds.
    Boost iv;
    /// True when the function that produced this interval is defined and continuous on the whole
    /// input box. False for empty intervals.
    bool defined;

    /// The point 0.
    constexpr BasicInterval() : iv(0.0), defined(true) {}
    /// The point x; NaN gives the empty interval.
    BasicInterval(double x) : iv(x), defined(!std::isnan(x)) {}  // NOLINT: implicit on purpose
    /// [lo, hi]; lo > hi or a NaN bound gives the empty interval.
    BasicInterval(double lo, double hi) : iv(lo, hi), defined(!boost::numeric::empty(iv)) {}
    BasicInterval(const Boost& b, bool def) : iv(b), defined(def && !boost::numeric::empty(b)) {}
    /// Same bounds under another rounding mode.
    template <class M2>
    explicit BasicInterval(const BasicInterval<M2>& o)
        : iv(o.lower(), o.upper(), true), defined(o.defined) {
        if (o.is_empty()) *this = empty();
    }

    static BasicInterval empty() { return {Boost::empty(), false}; }
    static BasicInterval entire() { return {Boost::whole(), true}; }

    double lower() const { return iv.lower(); }
    double upper() const { return iv.upper(); }
    bool is_empty() const { return boost::numeric::empty(iv); }
};

/// The safe default: every operation saves, sets and restores the rounding mode.
using Interval = BasicInterval<ProtectedRounding>;
/// The fast variant for hot loops: correct only inside a live RoundingScope.
using UpInterval = BasicInterval<UpwardRounding>;

// ---- queries ---------------------------------------------------------------------------------

template <class M>
double lower(const BasicInterval<M>& x) {
    return x.lower();
}
template <class M>
double upper(const BasicInterval<M>& x) {
    return x.upper();
}
template <class M>
bool is_defined(const BasicInterval<M>& x) {
    return x.defined;
}
template <class M>
bool is_empty(const BasicInterval<M>& x) {
    return x.is_empty();
}
/// Width rounded upward (+inf when unbounded, 0 for empty).
template <class M>
double width(const BasicInterval<M>& x) {
    return x.is_empty() ? 0.0 : boost::numeric::width(x.iv);
}
/// A point inside a non-empty interval (0 for entire, finite for half-unbounded intervals).
template <class M>
double midpoint(const BasicInterval<M>& x) {
    double l = x.lower(), u = x.upper();
    if (std::isinf(l) && std::isinf(u)) return 0.0;
    if (std::isinf(l)) return u > 0 ? 0.0 : (u == 0 ? -1.0 : 2 * u - 1.0);
    if (std::isinf(u)) return l < 0 ? 0.0 : (l == 0 ? 1.0 : 2 * l + 1.0);
    double m = 0.5 * l + 0.5 * u;
    return m < l ? l : (m > u ? u : m);
}
template <class M>
bool contains(const BasicInterval<M>& x, double v) {
    return x.lower() <= v && v <= x.upper();
}
/// True when y ⊆ x (empty y is a subset of everything).
template <class M>
bool contains(const BasicInterval<M>& x, const BasicInterval<M>& y) {
    return y.is_empty() || (x.lower() <= y.lower() && y.upper() <= x.upper());
}
template <class M>
BasicInterval<M> hull(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return {boost::numeric::hull(a.iv, b.iv), a.defined && b.defined};
}
template <class M>
BasicInterval<M> intersect(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return {boost::numeric::intersect(a.iv, b.iv), a.defined && b.defined};
}

// ---- comparisons: certainly_* holds for every pair of members, possibly_* for some pair
// ---------- They compare bounds in the calling thread's environment: under a host's
// ---------- denormals-are-zero a subnormal bound reads as 0, so code that decides anything from
// ---------- them runs inside a NearestScope (the library's entry points open one).
// ---------- Empty operands: certainly_* is vacuously true, possibly_* false.

template <class M>
bool certainly_lt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a.is_empty() || b.is_empty() || a.upper() < b.lower();
}
template <class M>
bool certainly_le(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a.is_empty() || b.is_empty() || a.upper() <= b.lower();
}
template <class M>
bool certainly_gt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return certainly_lt(b, a);
}
template <class M>
bool certainly_ge(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return certainly_le(b, a);
}
template <class M>
bool possibly_lt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return !a.is_empty() && !b.is_empty() && a.lower() < b.upper();
}
template <class M>
bool possibly_le(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return !a.is_empty() && !b.is_empty() && a.lower() <= b.upper();
}
template <class M>
bool possibly_gt(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return possibly_lt(b, a);
}
template <class M>
bool possibly_ge(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    return possibly_le(b, a);
}
/// 0 ∈ x.
template <class M>
bool possibly_zero(const BasicInterval<M>& x) {
    return contains(x, 0.0);
}

// ---- arithmetic ------------------------------------------------------------------------------
// Every result is defined where both operands are, and the operation is defined on the whole box.
// Each operation but negation holds the mode's Guard from its first line: for `Interval` the whole
// body, comparisons of bounds included, runs in the library's environment (canonical(2): no
// flush-to-zero, no denormals-are-zero), so that a subnormal bound is never read as 0.

namespace detail {
/// Boost yields NaN bounds (read as empty) for inf − inf and 0 · inf on non-empty operands at
/// infinite bounds; the sound answer for a non-empty input is then the whole line.
template <class M>
BasicInterval<M> repair(const BasicInterval<M>& r, const BasicInterval<M>& a,
                        const BasicInterval<M>& b) {
    if (r.is_empty() && !a.is_empty() && !b.is_empty()) {
        return {BasicInterval<M>::Boost::whole(), a.defined && b.defined};
    }
    return r;
}

/// Boost's operations with the repair, out of line: the rare cases (empty operands, infinite
/// bounds) of the branch-free kernels below.
template <class M>
[[gnu::cold, gnu::noinline]] BasicInterval<M> boost_add(const BasicInterval<M>& a,
                                                        const BasicInterval<M>& b) {
    return repair(BasicInterval<M>{a.iv + b.iv, a.defined && b.defined}, a, b);
}
template <class M>
[[gnu::cold, gnu::noinline]] BasicInterval<M> boost_sub(const BasicInterval<M>& a,
                                                        const BasicInterval<M>& b) {
    return repair(BasicInterval<M>{a.iv - b.iv, a.defined && b.defined}, a, b);
}
template <class M>
[[gnu::cold, gnu::noinline]] BasicInterval<M> boost_mul(const BasicInterval<M>& a,
                                                        const BasicInterval<M>& b) {
    return repair(BasicInterval<M>{a.iv * b.iv, a.defined && b.defined}, a, b);
}

/// [lo, hi] with the decoration def, unchecked: the caller knows lo ≤ hi.
template <class M>
BasicInterval<M> from_bounds(double lo, double hi, bool def) {
    BasicInterval<M> r;
    r.iv = typename BasicInterval<M>::Boost(lo, hi, true);
    r.defined = def;
    return r;
}

// Kernels on bounds, valid in upward mode (a Guard or the caller's RoundingScope holds it). Each
// reads its operands through `opaque` and returns results through it; a lower bound is the
// negation of an upward-rounded result on negated operands.
inline double max2(double a, double b) { return a > b ? a : b; }  // no NaN here
inline double min2(double a, double b) { return a < b ? a : b; }

/// [RD(alo + blo), RU(ahi + bhi)].
inline void add_bounds(double alo, double ahi, double blo, double bhi, double& lo, double& hi) {
    lo = -opaque(opaque(-alo) - opaque(blo));
    hi = opaque(opaque(ahi) + opaque(bhi));
}

/// [RD(alo − bhi), RU(ahi − blo)].
inline void sub_bounds(double alo, double ahi, double blo, double bhi, double& lo, double& hi) {
    lo = -opaque(opaque(bhi) - opaque(alo));
    hi = opaque(opaque(ahi) - opaque(blo));
}

/// [min RD(corner products), max RU(corner products)]; false when a product is NaN (0 · ∞ or an
/// empty operand), which the caller sends to Boost's sign-case table. A false alarm (two products
/// of opposite infinite sign) only costs that detour.
inline bool mul_bounds(double alo, double ahi, double blo, double bhi, double& lo, double& hi) {
#ifdef CERTRAY_X86_64_ROUNDING
    // Two lanes: b = (blo, bhi); products of alo and of ahi with both, and of their negations.
    const auto hide = [](__m128d v) {
        asm volatile("" : "+x"(v));
        return v;
    };
    const __m128d sign = _mm_set1_pd(-0.0);
    // Scalar loads (a 16-byte load of bounds stored as two 8-byte halves would miss store
    // forwarding).
    const __m128d b = hide(_mm_unpacklo_pd(_mm_set_sd(opaque(blo)), _mm_set_sd(opaque(bhi))));
    const __m128d al = hide(_mm_set1_pd(opaque(alo))), ah = hide(_mm_set1_pd(opaque(ahi)));
    const __m128d nal = hide(_mm_xor_pd(al, sign)), nah = hide(_mm_xor_pd(ah, sign));
    const __m128d p1 = hide(_mm_mul_pd(al, b)), p2 = hide(_mm_mul_pd(ah, b));
    const __m128d n1 = hide(_mm_mul_pd(nal, b)), n2 = hide(_mm_mul_pd(nah, b));
    const int nan = _mm_movemask_pd(_mm_cmpunord_pd(p1, p2));
    const __m128d hp = _mm_max_pd(p1, p2), hn = _mm_max_pd(n1, n2);
    // (max of negated products, max of products) = (−lo, hi).
    const __m128d r = _mm_max_pd(_mm_unpacklo_pd(hn, hp), _mm_unpackhi_pd(hn, hp));
    lo = -_mm_cvtsd_f64(r);
    hi = _mm_cvtsd_f64(_mm_unpackhi_pd(r, r));
    return nan == 0;
#else
    alo = opaque(alo);
    ahi = opaque(ahi);
    blo = opaque(blo);
    bhi = opaque(bhi);
    const double nalo = opaque(-alo), nahi = opaque(-ahi);
    const double p1 = opaque(alo * blo), p2 = opaque(alo * bhi), p3 = opaque(ahi * blo),
                 p4 = opaque(ahi * bhi);
    const double n1 = opaque(nalo * blo), n2 = opaque(nalo * bhi), n3 = opaque(nahi * blo),
                 n4 = opaque(nahi * bhi);
    const double check = (p1 + p2) + (p3 + p4);
    hi = max2(max2(p1, p2), max2(p3, p4));
    lo = -max2(max2(n1, n2), max2(n3, n4));
    return check == check;
#endif
}

/// [lo, hi]² for a non-empty box: m = distance from 0 to the box, M = largest magnitude;
/// [RD(m²), RU(M²)].
inline void square_bounds(double xlo, double xhi, double& lo, double& hi) {
    const double m = opaque(max2(max2(xlo, -xhi), 0.0)), big = opaque(max2(-xlo, xhi));
    lo = -opaque(opaque(-m) * m);
    hi = opaque(big * big);
}
}  // namespace detail

/// [a, b] + [c, d] = [a + c rounded down, b + d rounded up]; an empty operand gives empty,
/// ∞ − ∞ at an infinite bound gives the whole line.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> operator+(const BasicInterval<M>& a,
                                                         const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;
    double lo, hi;
    detail::add_bounds(a.lower(), a.upper(), b.lower(), b.upper(), lo, hi);
    if (lo <= hi) [[likely]]
        return detail::from_bounds<M>(lo, hi, a.defined & b.defined);
    return detail::boost_add(a, b);
}
/// [a, b] − [c, d] = [a − d rounded down, b − c rounded up]; empty and ∞ − ∞ as for +.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> operator-(const BasicInterval<M>& a,
                                                         const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;
    double lo, hi;
    detail::sub_bounds(a.lower(), a.upper(), b.lower(), b.upper(), lo, hi);
    if (lo <= hi) [[likely]]
        return detail::from_bounds<M>(lo, hi, a.defined & b.defined);
    return detail::boost_sub(a, b);
}
/// −[a, b] = [−b, −a] (exact).
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> operator-(const BasicInterval<M>& a) {
    if (a.is_empty()) [[unlikely]]
        return BasicInterval<M>::empty();
    return detail::from_bounds<M>(-a.upper(), -a.lower(), a.defined);
}
/// Product: the least and greatest of the four corner products, rounded outward (the bounds of
/// Boost's 9-case sign table, without its branches). When a corner is 0 · ∞ or an operand is
/// empty: Boost's table, where 0 · ∞ counts as 0.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> operator*(const BasicInterval<M>& a,
                                                         const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;
    double lo, hi;
    if (detail::mul_bounds(a.lower(), a.upper(), b.lower(), b.upper(), lo, hi)) [[likely]]
        return detail::from_bounds<M>(lo, hi, a.defined & b.defined);
    return detail::boost_mul(a, b);
}

/// Set-based quotient {x / y : x ∈ a, y ∈ b, y ≠ 0}:
///   0 ∉ b            → Boost's quotient, rounded outward
///   b = [0, 0]       → empty
///   b = [0, d], d>0  → a = [0,0]: [0,0]; a ≤ 0 with a.hi<0: [−∞, a.hi/d]; a.hi = 0: [−∞, 0];
///                      a ≥ 0 with a.lo>0: [a.lo/d, +∞]; a.lo = 0: [0, +∞]; else entire
///   b = [c, 0], c<0  → the mirror image
///   c < 0 < d        → a = [0,0]: [0,0]; else entire
/// The result is never `defined` when 0 ∈ b.
template <class M>
BasicInterval<M> operator/(const BasicInterval<M>& a, const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;
    using I = BasicInterval<M>;
    if (a.is_empty() || b.is_empty()) return I::empty();
    const double c = b.lower(), d = b.upper();
    if (c > 0 || d < 0) return detail::repair(I{a.iv / b.iv, a.defined && b.defined}, a, b);
    const double lo = a.lower(), hi = a.upper();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if (c == 0 && d == 0) return I::empty();
    if (lo == 0 && hi == 0) return I{typename I::Boost(0.0), false};
    typename M::Policies::rounding rnd;
    if (c == 0) {  // b = [0, d]: quotients with y → 0⁺
        if (hi < 0) return I{typename I::Boost(-kInf, rnd.div_up(hi, d)), false};
        if (hi == 0) return I{typename I::Boost(-kInf, 0.0), false};
        if (lo > 0) return I{typename I::Boost(rnd.div_down(lo, d), kInf), false};
        if (lo == 0) return I{typename I::Boost(0.0, kInf), false};
        return I{I::Boost::whole(), false};
    }
    if (d == 0) {  // b = [c, 0]: quotients with y → 0⁻
        if (hi < 0) return I{typename I::Boost(rnd.div_down(hi, c), kInf), false};
        if (hi == 0) return I{typename I::Boost(0.0, kInf), false};
        if (lo > 0) return I{typename I::Boost(-kInf, rnd.div_up(lo, c)), false};
        if (lo == 0) return I{typename I::Boost(-kInf, 0.0), false};
        return I{I::Boost::whole(), false};
    }
    return I{I::Boost::whole(), false};
}

template <class M>
BasicInterval<M> operator+(const BasicInterval<M>& a, double b) {
    return a + BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator+(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) + b;
}
template <class M>
BasicInterval<M> operator-(const BasicInterval<M>& a, double b) {
    return a - BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator-(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) - b;
}
template <class M>
BasicInterval<M> operator*(const BasicInterval<M>& a, double b) {
    return a * BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator*(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) * b;
}
template <class M>
BasicInterval<M> operator/(const BasicInterval<M>& a, double b) {
    return a / BasicInterval<M>(b);
}
template <class M>
BasicInterval<M> operator/(double a, const BasicInterval<M>& b) {
    return BasicInterval<M>(a) / b;
}

template <class M>
BasicInterval<M>& operator+=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a + b;
}
template <class M>
BasicInterval<M>& operator-=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a - b;
}
template <class M>
BasicInterval<M>& operator*=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a * b;
}
template <class M>
BasicInterval<M>& operator/=(BasicInterval<M>& a, const BasicInterval<M>& b) {
    return a = a / b;
}

// ---- elementary functions ----------------------------------------------------------------------

/// |[a, b]|: [a, b] if a ≥ 0; [−b, −a] if b ≤ 0; [0, max(−a, b)] otherwise. Exact: the lower
/// bound is max(a, −b, 0), the upper max(−a, b). abs, min and max round nothing but still hold
/// the guard: a caller's denormals-are-zero would make max(0, 2^-1074) = 0.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> abs(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;
    const double l = x.lower(), u = x.upper();
    if (!(l <= u)) [[unlikely]]
        return BasicInterval<M>::empty();
    return detail::from_bounds<M>(detail::max2(detail::max2(l, -u), 0.0), detail::max2(-l, u),
                                  x.defined);
}
/// [a, b]²: [a², b²] if a ≥ 0; [b², a²] if b ≤ 0; [0, max(a², b²)] otherwise; rounded outward.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> square(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;
    const double l = x.lower(), u = x.upper();
    if (!(l <= u)) [[unlikely]]
        return BasicInterval<M>::empty();
    double lo, hi;
    detail::square_bounds(l, u, lo, hi);
    return detail::from_bounds<M>(lo, hi, x.defined);
}
/// xⁿ for a non-negative integer n: x⁰ = [1, 1]; even n as square, odd n monotone.
template <class M>
BasicInterval<M> pow(const BasicInterval<M>& x, unsigned n) {
    [[maybe_unused]] typename M::Guard guard;
    if (x.is_empty()) return BasicInterval<M>::empty();
    if (n == 0) return {typename BasicInterval<M>::Boost(1.0), x.defined};
    return detail::repair(
        BasicInterval<M>{boost::numeric::pow(x.iv, static_cast<int>(n)), x.defined}, x, x);
}
/// √ on [a, b] ∩ [0, ∞): [√max(a,0) down, √b up]; empty if b < 0; defined only if a ≥ 0.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> sqrt(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;
    const double l = x.lower(), u = x.upper();
    if (!(l <= u) || u < 0) [[unlikely]]
        return BasicInterval<M>::empty();
    const double lo = l > 0 ? detail::sqrt_rd(l) : 0.0;
    const double hi = detail::opaque(std::sqrt(detail::opaque(u)));
    return detail::from_bounds<M>(lo, hi, x.defined && l >= 0);
}
/// exp is increasing: [exp_down(a), exp_up(b)].
template <class M>
BasicInterval<M> exp(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;
    if (x.is_empty()) return BasicInterval<M>::empty();
    typename M::Policies::rounding rnd;
    double lo = x.lower(), hi = x.upper();
#ifdef CERTRAY_X86_64_ROUNDING
    detail::kernel_or_libm(lo, hi, detail::exp_kernel_applies, detail::exp_kernel_bounds,
                           [&](double& l, double& h) { rnd.exp_bounds(l, h); });
#else
    rnd.exp_bounds(lo, hi);  // both bounds under one mode switch
#endif
    return {typename BasicInterval<M>::Boost(lo, hi), x.defined};
}
/// log on [a, b] ∩ (0, ∞): [log_down(a) or −∞ if a ≤ 0, log_up(b)]; empty if b ≤ 0;
/// defined only if a > 0.
template <class M>
BasicInterval<M> log(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;
    if (x.is_empty() || !(x.upper() > 0)) return {boost::numeric::log(x.iv), false};
    if (!(x.lower() > 0)) return {boost::numeric::log(x.iv), false};  // [−inf, log_up(b)]
    typename M::Policies::rounding rnd;
    double lo = x.lower(), hi = x.upper();
#ifdef CERTRAY_X86_64_ROUNDING
    detail::kernel_or_libm(lo, hi, detail::log_kernel_applies, detail::log_kernel_bounds,
                           [&](double& l, double& h) { rnd.log_bounds(l, h); });
#else
    rnd.log_bounds(lo, hi);  // both bounds under one mode switch
#endif
    return {typename BasicInterval<M>::Boost(lo, hi), x.defined};
}
/// cos: the endpoint values, and ±1 where an extremum kπ may lie inside (WidenedTransc::
/// trig_bounds); a box of width ≥ 2π or an unbounded box gives [−1, 1].
template <class M>
BasicInterval<M> cos(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;
    if (x.is_empty()) return BasicInterval<M>::empty();
    if (!std::isfinite(x.lower()) || !std::isfinite(x.upper()))
        return {BasicInterval<M>(-1.0, 1.0).iv, x.defined};
    typename M::Policies::rounding rnd;
    double lo = x.lower(), hi = x.upper();
#ifdef CERTRAY_X86_64_ROUNDING
    if (detail::trig_kernel_applies(lo) && detail::trig_kernel_applies(hi)) {
        detail::trig_kernel_bounds(false, lo, hi);
        return {typename BasicInterval<M>::Boost(lo, hi), x.defined};
    }
#endif
    rnd.trig_bounds(false, lo, hi);  // both bounds under one mode switch
    return {typename BasicInterval<M>::Boost(lo, hi), x.defined};
}
/// sin: as cos, with the extrema at π/2 + kπ.
template <class M>
BasicInterval<M> sin(const BasicInterval<M>& x) {
    [[maybe_unused]] typename M::Guard guard;
    if (x.is_empty()) return BasicInterval<M>::empty();
    if (!std::isfinite(x.lower()) || !std::isfinite(x.upper()))
        return {BasicInterval<M>(-1.0, 1.0).iv, x.defined};
    typename M::Policies::rounding rnd;
    double lo = x.lower(), hi = x.upper();
#ifdef CERTRAY_X86_64_ROUNDING
    if (detail::trig_kernel_applies(lo) && detail::trig_kernel_applies(hi)) {
        detail::trig_kernel_bounds(true, lo, hi);
        return {typename BasicInterval<M>::Boost(lo, hi), x.defined};
    }
#endif
    rnd.trig_bounds(true, lo, hi);  // both bounds under one mode switch
    return {typename BasicInterval<M>::Boost(lo, hi), x.defined};
}
/// min([a, b], [c, d]) = [min(a, c), min(b, d)]. Exact.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> min(const BasicInterval<M>& a,
                                                   const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;
    if (!(a.lower() <= a.upper()) || !(b.lower() <= b.upper())) [[unlikely]]
        return BasicInterval<M>::empty();
    return detail::from_bounds<M>(detail::min2(a.lower(), b.lower()),
                                  detail::min2(a.upper(), b.upper()), a.defined & b.defined);
}
/// max([a, b], [c, d]) = [max(a, c), max(b, d)]. Exact.
template <class M>
[[gnu::always_inline]] inline BasicInterval<M> max(const BasicInterval<M>& a,
                                                   const BasicInterval<M>& b) {
    [[maybe_unused]] typename M::Guard guard;
    if (!(a.lower() <= a.upper()) || !(b.lower() <= b.upper())) [[unlikely]]
        return BasicInterval<M>::empty();
    return detail::from_bounds<M>(detail::max2(a.lower(), b.lower()),
                                  detail::max2(a.upper(), b.upper()), a.defined & b.defined);
}

}  // namespace certray

#include "interval/interval_ext.h"  // IWYU pragma: export
