// MpfrInterval implementation: every lower bound rounded by MPFR toward −∞ (MPFR_RNDD), every
// upper bound toward +∞ (MPFR_RNDU); see mpfr_interval.h for the contract and the case tables.
#include "interval/mpfr_interval.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "interval/interval.h"  // NearestScope: MPFR reads and writes doubles with the FPU

namespace certray {

namespace detail {

/// Friend of MpfrInterval: lets the free operations build a result in place.
struct MpfrAccess {
    /// A result at `prec` with NaN bounds and defined == false (i.e. empty until filled).
    static MpfrInterval make(mpfr_prec_t prec) {
        return MpfrInterval(MpfrInterval::Uninit{}, prec);
    }
    static mpfr_ptr lo(MpfrInterval& x) { return x.lo_; }
    static mpfr_ptr hi(MpfrInterval& x) { return x.hi_; }
};

}  // namespace detail

namespace {

using detail::MpfrAccess;

mpfr_prec_t clamp_precision(mpfr_prec_t prec) {
    return std::clamp<mpfr_prec_t>(prec, MPFR_PREC_MIN, MPFR_PREC_MAX);
}

/// One scratch mpfr_t (RAII), for intermediate products and constants.
class Scratch {
  public:
    explicit Scratch(mpfr_prec_t prec) { mpfr_init2(v_, prec); }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
    ~Scratch() { mpfr_clear(v_); }
    mpfr_ptr get() { return v_; }
    operator mpfr_ptr() { return v_; }  // NOLINT(google-explicit-constructor): reads like mpfr_t.

  private:
    mpfr_t v_;
};

mpfr_prec_t join_precision(const MpfrInterval& x, const MpfrInterval& y) {
    return std::max(x.precision(), y.precision());
}

/// The empty set at `prec` (bounds NaN, defined == false).
MpfrInterval empty_at(mpfr_prec_t prec) { return MpfrAccess::make(prec); }

/// [lo, hi] given exactly by MPFR values, rounded outward into `prec` bits.
MpfrInterval from_bounds(mpfr_srcptr lo, mpfr_srcptr hi, mpfr_prec_t prec, bool defined) {
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_set(MpfrAccess::lo(r), lo, MPFR_RNDD);
    mpfr_set(MpfrAccess::hi(r), hi, MPFR_RNDU);
    r.defined = defined;
    return r;
}

/// A bound product with the interval convention 0 · ±∞ = 0: a bound at ∞ stands for a limit of
/// reals, and 0 times any real is 0.
void mul_bound(mpfr_ptr r, mpfr_srcptr a, mpfr_srcptr b, mpfr_rnd_t rnd) {
    if (mpfr_zero_p(a) || mpfr_zero_p(b)) {
        mpfr_set_zero(r, 1);
    } else {
        mpfr_mul(r, a, b, rnd);
    }
}

bool nonneg(mpfr_srcptr v) { return mpfr_sgn(v) >= 0; }
bool nonpos(mpfr_srcptr v) { return mpfr_sgn(v) <= 0; }

/// Which critical points (m + offset)·π, m integer, the finite box [a, b] may contain: `even`
/// when some m is even, `odd` when some m is odd. Decided with an outward enclosure of π at a
/// working precision above the magnitude of the bounds, so that a "no" is a proof and a doubt
/// answers "yes".
struct CriticalPoints {
    bool even = false;
    bool odd = false;
};

CriticalPoints critical_points(mpfr_srcptr a, mpfr_srcptr b, bool half_offset, mpfr_prec_t prec) {
    mpfr_exp_t magnitude = 0;
    for (mpfr_srcptr v : {a, b}) {
        if (mpfr_regular_p(v)) {
            magnitude = std::max(magnitude, mpfr_get_exp(v));
        }
    }
    const mpfr_prec_t wp = clamp_precision(prec + static_cast<mpfr_prec_t>(magnitude) + 64);
    Scratch pi_lo(wp);
    Scratch pi_hi(wp);
    mpfr_const_pi(pi_lo, MPFR_RNDD);
    mpfr_const_pi(pi_hi, MPFR_RNDU);

    // q_lo ≤ a/π − offset and q_hi ≥ b/π − offset.
    Scratch q_lo(wp);
    Scratch q_hi(wp);
    mpfr_div(q_lo, a, nonneg(a) ? pi_hi.get() : pi_lo.get(), MPFR_RNDD);
    mpfr_div(q_hi, b, nonneg(b) ? pi_lo.get() : pi_hi.get(), MPFR_RNDU);
    if (half_offset) {
        mpfr_sub_d(q_lo, q_lo, 0.5, MPFR_RNDD);
        mpfr_sub_d(q_hi, q_hi, 0.5, MPFR_RNDU);
    }
    // Every m with (m + offset)π ∈ [a, b] lies in [ceil(q_lo), floor(q_hi)]. These integers have
    // at most magnitude + 2 bits, far below wp, so ceil, floor and the difference are exact.
    Scratch m_lo(wp);
    Scratch m_hi(wp);
    mpfr_ceil(m_lo, q_lo);
    mpfr_floor(m_hi, q_hi);
    CriticalPoints result;
    if (mpfr_greater_p(m_lo, m_hi)) {
        return result;
    }
    Scratch diff(wp);
    mpfr_sub(diff, m_hi, m_lo, MPFR_RNDU);
    if (mpfr_cmp_ui(diff, 1) >= 0) {
        result.even = result.odd = true;
        return result;
    }
    Scratch half(wp);
    mpfr_div_2ui(half, m_lo, 1, MPFR_RNDN);  // exact
    if (mpfr_integer_p(half)) {
        result.even = true;
    } else {
        result.odd = true;
    }
    return result;
}

/// Shared body of sin and cos: endpoint values, widened to ±1 at the critical points that the
/// box may contain (for offset 0 even m are maxima of cos; for offset ½ even m are maxima of sin).
MpfrInterval periodic(const MpfrInterval& x, bool is_sin) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    r.defined = x.defined;
    mpfr_ptr lo = MpfrAccess::lo(r);
    mpfr_ptr hi = MpfrAccess::hi(r);
    bool full = !mpfr_number_p(x.lo()) || !mpfr_number_p(x.hi());
    if (!full) {
        // A box wider than 2π holds both extrema; 6.5 < 2π would be wrong, 7 > 2π is safe.
        Scratch width(prec);
        mpfr_sub(width, x.hi(), x.lo(), MPFR_RNDD);
        full = mpfr_cmp_ui(width, 7) >= 0;
    }
    if (full) {
        mpfr_set_si(lo, -1, MPFR_RNDD);
        mpfr_set_si(hi, 1, MPFR_RNDU);
        return r;
    }
    auto fn = is_sin ? mpfr_sin : mpfr_cos;
    Scratch a_d(prec);
    Scratch b_d(prec);
    fn(a_d, x.lo(), MPFR_RNDD);
    fn(b_d, x.hi(), MPFR_RNDD);
    mpfr_min(lo, a_d, b_d, MPFR_RNDD);
    fn(a_d, x.lo(), MPFR_RNDU);
    fn(b_d, x.hi(), MPFR_RNDU);
    mpfr_max(hi, a_d, b_d, MPFR_RNDU);
    const CriticalPoints cp = critical_points(x.lo(), x.hi(), is_sin, prec);
    if (cp.even) {
        mpfr_set_si(hi, 1, MPFR_RNDU);
    }
    if (cp.odd) {
        mpfr_set_si(lo, -1, MPFR_RNDD);
    }
    return r;
}

/// [f(a) ↓, f(b) ↑] for a non-decreasing f given as an MPFR function.
template <typename F>
MpfrInterval monotone(const MpfrInterval& x, F f) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    f(MpfrAccess::lo(r), x.lo(), MPFR_RNDD);
    f(MpfrAccess::hi(r), x.hi(), MPFR_RNDU);
    r.defined = x.defined;
    return r;
}

}  // namespace

// ---- construction, RAII ---------------------------------------------------------------------

MpfrInterval::MpfrInterval(Uninit, Precision prec) : defined(false) {
    const mpfr_prec_t bits = clamp_precision(prec.bits);
    mpfr_init2(lo_, bits);
    mpfr_init2(hi_, bits);
}

// MPFR converts between doubles and its numbers with double arithmetic: under a caller's
// denormals-are-zero or flush-to-zero a subnormal would read or come out as 0. Every conversion
// runs in the library's environment (NearestScope).

MpfrInterval::MpfrInterval(double x, Precision prec) : MpfrInterval(Uninit{}, prec) {
    NearestScope env;
    if (std::isfinite(x)) {
        mpfr_set_d(lo_, x, MPFR_RNDD);
        mpfr_set_d(hi_, x, MPFR_RNDU);
        defined = true;
    }
}

MpfrInterval::MpfrInterval(double lo, double hi, Precision prec) : MpfrInterval(Uninit{}, prec) {
    const bool valid =
        !std::isnan(lo) && !std::isnan(hi) && lo <= hi && lo != HUGE_VAL && hi != -HUGE_VAL;
    if (valid) {
        NearestScope env;
        mpfr_set_d(lo_, lo, MPFR_RNDD);
        mpfr_set_d(hi_, hi, MPFR_RNDU);
        defined = true;
    }
}

MpfrInterval MpfrInterval::empty(Precision prec) { return MpfrInterval(Uninit{}, prec); }

MpfrInterval MpfrInterval::entire(Precision prec) {
    MpfrInterval r(Uninit{}, prec);
    mpfr_set_inf(r.lo_, -1);
    mpfr_set_inf(r.hi_, 1);
    r.defined = true;
    return r;
}

MpfrInterval::MpfrInterval(const MpfrInterval& other) : defined(other.defined) {
    mpfr_init2(lo_, other.precision());
    mpfr_init2(hi_, other.precision());
    mpfr_set(lo_, other.lo_, MPFR_RNDD);  // same precision: exact
    mpfr_set(hi_, other.hi_, MPFR_RNDU);
}

// MPFR has no "moved-from" state, so the source receives a fresh minimal-precision NaN pair
// (an empty interval, still valid to destroy or assign to).
MpfrInterval::MpfrInterval(MpfrInterval&& other) noexcept : defined(other.defined) {
    mpfr_init2(lo_, MPFR_PREC_MIN);
    mpfr_init2(hi_, MPFR_PREC_MIN);
    mpfr_swap(lo_, other.lo_);
    mpfr_swap(hi_, other.hi_);
    other.defined = false;
}

MpfrInterval& MpfrInterval::operator=(const MpfrInterval& other) {
    if (this != &other) {
        if (precision() != other.precision()) {
            mpfr_set_prec(lo_, other.precision());
            mpfr_set_prec(hi_, other.precision());
        }
        mpfr_set(lo_, other.lo_, MPFR_RNDD);
        mpfr_set(hi_, other.hi_, MPFR_RNDU);
        defined = other.defined;
    }
    return *this;
}

MpfrInterval& MpfrInterval::operator=(MpfrInterval&& other) noexcept {
    if (this != &other) {
        mpfr_swap(lo_, other.lo_);
        mpfr_swap(hi_, other.hi_);
        std::swap(defined, other.defined);
    }
    return *this;
}

MpfrInterval::~MpfrInterval() {
    mpfr_clear(lo_);
    mpfr_clear(hi_);
}

double MpfrInterval::lower_down() const {
    NearestScope env;
    return mpfr_get_d(lo_, MPFR_RNDD);
}
double MpfrInterval::upper_up() const {
    NearestScope env;
    return mpfr_get_d(hi_, MPFR_RNDU);
}
bool MpfrInterval::is_empty() const { return mpfr_nan_p(lo_) != 0; }

// ---- arithmetic -----------------------------------------------------------------------------

MpfrInterval operator+(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    if (x.is_empty() || y.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    // lo is never +∞ and hi never −∞, so no ∞ − ∞ can occur.
    mpfr_add(MpfrAccess::lo(r), x.lo(), y.lo(), MPFR_RNDD);
    mpfr_add(MpfrAccess::hi(r), x.hi(), y.hi(), MPFR_RNDU);
    r.defined = x.defined && y.defined;
    return r;
}

MpfrInterval operator-(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    if (x.is_empty() || y.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_sub(MpfrAccess::lo(r), x.lo(), y.hi(), MPFR_RNDD);
    mpfr_sub(MpfrAccess::hi(r), x.hi(), y.lo(), MPFR_RNDU);
    r.defined = x.defined && y.defined;
    return r;
}

MpfrInterval operator*(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    if (x.is_empty() || y.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_ptr lo = MpfrAccess::lo(r);
    mpfr_ptr hi = MpfrAccess::hi(r);
    Scratch t(prec);
    const mpfr_srcptr xs[2] = {x.lo(), x.hi()};
    const mpfr_srcptr ys[2] = {y.lo(), y.hi()};
    mpfr_set_inf(lo, 1);
    mpfr_set_inf(hi, -1);
    for (mpfr_srcptr a : xs) {
        for (mpfr_srcptr b : ys) {
            mul_bound(t, a, b, MPFR_RNDD);
            mpfr_min(lo, lo, t, MPFR_RNDD);
            mul_bound(t, a, b, MPFR_RNDU);
            mpfr_max(hi, hi, t, MPFR_RNDU);
        }
    }
    r.defined = x.defined && y.defined;
    return r;
}

MpfrInterval operator/(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    if (x.is_empty() || y.is_empty() || (mpfr_zero_p(y.lo()) && mpfr_zero_p(y.hi()))) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_ptr lo = MpfrAccess::lo(r);
    mpfr_ptr hi = MpfrAccess::hi(r);
    const mpfr_srcptr a = x.lo();
    const mpfr_srcptr b = x.hi();
    const mpfr_srcptr c = y.lo();
    const mpfr_srcptr d = y.hi();
    const bool zero_in_y = nonpos(c) && nonneg(d);
    r.defined = x.defined && y.defined && !zero_in_y;
    // In every quotient below the divisor bound is finite or the dividend bound is finite, so
    // no ∞/∞ occurs; finite/∞ = 0 and ∞/finite = ∞ are the correct limits.
    if (mpfr_sgn(c) > 0) {  // y > 0
        if (nonneg(a)) {
            mpfr_div(lo, a, d, MPFR_RNDD);
            mpfr_div(hi, b, c, MPFR_RNDU);
        } else if (nonpos(b)) {
            mpfr_div(lo, a, c, MPFR_RNDD);
            mpfr_div(hi, b, d, MPFR_RNDU);
        } else {
            mpfr_div(lo, a, c, MPFR_RNDD);
            mpfr_div(hi, b, c, MPFR_RNDU);
        }
        return r;
    }
    if (mpfr_sgn(d) < 0) {  // y < 0
        if (nonneg(a)) {
            mpfr_div(lo, b, d, MPFR_RNDD);
            mpfr_div(hi, a, c, MPFR_RNDU);
        } else if (nonpos(b)) {
            mpfr_div(lo, b, c, MPFR_RNDD);
            mpfr_div(hi, a, d, MPFR_RNDU);
        } else {
            mpfr_div(lo, b, d, MPFR_RNDD);
            mpfr_div(hi, a, d, MPFR_RNDU);
        }
        return r;
    }
    // 0 ∈ y and y ≠ [0, 0].
    if (mpfr_zero_p(a) && mpfr_zero_p(b)) {
        mpfr_set_zero(lo, 1);
        mpfr_set_zero(hi, 1);
        return r;
    }
    mpfr_set_inf(lo, -1);
    mpfr_set_inf(hi, 1);
    if (mpfr_zero_p(c)) {  // y = [0, d], d > 0
        if (nonpos(b)) {
            mpfr_div(hi, b, d, MPFR_RNDU);
        } else if (nonneg(a)) {
            mpfr_div(lo, a, d, MPFR_RNDD);
        }
    } else if (mpfr_zero_p(d)) {  // y = [c, 0], c < 0
        if (nonpos(b)) {
            mpfr_div(lo, b, c, MPFR_RNDD);
        } else if (nonneg(a)) {
            mpfr_div(hi, a, c, MPFR_RNDU);
        }
    }
    return r;
}

MpfrInterval operator-(const MpfrInterval& x) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_neg(MpfrAccess::lo(r), x.hi(), MPFR_RNDD);
    mpfr_neg(MpfrAccess::hi(r), x.lo(), MPFR_RNDU);
    r.defined = x.defined;
    return r;
}

MpfrInterval operator+(const MpfrInterval& x) { return x; }

MpfrInterval& operator+=(MpfrInterval& x, const MpfrInterval& y) { return x = x + y; }
MpfrInterval& operator-=(MpfrInterval& x, const MpfrInterval& y) { return x = x - y; }
MpfrInterval& operator*=(MpfrInterval& x, const MpfrInterval& y) { return x = x * y; }
MpfrInterval& operator/=(MpfrInterval& x, const MpfrInterval& y) { return x = x / y; }

// ---- elementary functions -------------------------------------------------------------------

MpfrInterval abs(const MpfrInterval& x) {
    if (x.is_empty() || nonneg(x.lo())) {
        return x;
    }
    if (nonpos(x.hi())) {
        return -x;
    }
    MpfrInterval r = MpfrAccess::make(x.precision());
    mpfr_set_zero(MpfrAccess::lo(r), 1);
    mpfr_neg(MpfrAccess::hi(r), x.lo(), MPFR_RNDU);
    mpfr_max(MpfrAccess::hi(r), MpfrAccess::hi(r), x.hi(), MPFR_RNDU);
    r.defined = x.defined;
    return r;
}

MpfrInterval square(const MpfrInterval& x) { return pow(x, 2); }

MpfrInterval pow(const MpfrInterval& x, unsigned n) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty()) {
        return empty_at(prec);
    }
    if (n == 0) {
        MpfrInterval r = MpfrAccess::make(prec);
        mpfr_set_ui(MpfrAccess::lo(r), 1, MPFR_RNDD);
        mpfr_set_ui(MpfrAccess::hi(r), 1, MPFR_RNDU);
        r.defined = x.defined;
        return r;
    }
    // Odd n: t ↦ tⁿ is increasing on ℝ. Even n: increasing on |x|.
    const MpfrInterval base = (n % 2 == 1) ? x : abs(x);
    return monotone(base,
                    [n](mpfr_ptr r, mpfr_srcptr v, mpfr_rnd_t rnd) { mpfr_pow_ui(r, v, n, rnd); });
}

MpfrInterval sqrt(const MpfrInterval& x) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty() || mpfr_sgn(x.hi()) < 0) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    if (mpfr_sgn(x.lo()) < 0) {
        mpfr_set_zero(MpfrAccess::lo(r), 1);
    } else {
        mpfr_sqrt(MpfrAccess::lo(r), x.lo(), MPFR_RNDD);
    }
    mpfr_sqrt(MpfrAccess::hi(r), x.hi(), MPFR_RNDU);
    r.defined = x.defined && nonneg(x.lo());
    return r;
}

MpfrInterval exp(const MpfrInterval& x) { return monotone(x, mpfr_exp); }

MpfrInterval log(const MpfrInterval& x) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty() || nonpos(x.hi())) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    const bool positive = mpfr_sgn(x.lo()) > 0;
    if (positive) {
        mpfr_log(MpfrAccess::lo(r), x.lo(), MPFR_RNDD);
    } else {
        mpfr_set_inf(MpfrAccess::lo(r), -1);
    }
    mpfr_log(MpfrAccess::hi(r), x.hi(), MPFR_RNDU);
    r.defined = x.defined && positive;
    return r;
}

MpfrInterval sin(const MpfrInterval& x) { return periodic(x, /*is_sin=*/true); }
MpfrInterval cos(const MpfrInterval& x) { return periodic(x, /*is_sin=*/false); }

MpfrInterval min(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    if (x.is_empty() || y.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_min(MpfrAccess::lo(r), x.lo(), y.lo(), MPFR_RNDD);
    mpfr_min(MpfrAccess::hi(r), x.hi(), y.hi(), MPFR_RNDU);
    r.defined = x.defined && y.defined;
    return r;
}

MpfrInterval max(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    if (x.is_empty() || y.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_max(MpfrAccess::lo(r), x.lo(), y.lo(), MPFR_RNDD);
    mpfr_max(MpfrAccess::hi(r), x.hi(), y.hi(), MPFR_RNDU);
    r.defined = x.defined && y.defined;
    return r;
}

// ---- set operations -------------------------------------------------------------------------

MpfrInterval hull(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    const bool defined = x.defined && y.defined;
    if (x.is_empty() && y.is_empty()) {
        return empty_at(prec);
    }
    if (x.is_empty() || y.is_empty()) {
        const MpfrInterval& v = x.is_empty() ? y : x;
        MpfrInterval r = from_bounds(v.lo(), v.hi(), prec, defined);
        return r;
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_min(MpfrAccess::lo(r), x.lo(), y.lo(), MPFR_RNDD);
    mpfr_max(MpfrAccess::hi(r), x.hi(), y.hi(), MPFR_RNDU);
    r.defined = defined;
    return r;
}

MpfrInterval intersect(const MpfrInterval& x, const MpfrInterval& y) {
    const mpfr_prec_t prec = join_precision(x, y);
    if (x.is_empty() || y.is_empty()) {
        return empty_at(prec);
    }
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_ptr lo = MpfrAccess::lo(r);
    mpfr_ptr hi = MpfrAccess::hi(r);
    mpfr_max(lo, x.lo(), y.lo(), MPFR_RNDD);
    mpfr_min(hi, x.hi(), y.hi(), MPFR_RNDU);
    if (mpfr_greater_p(lo, hi)) {
        return empty_at(prec);
    }
    r.defined = x.defined && y.defined;
    return r;
}

bool contains(const MpfrInterval& x, double v) {
    NearestScope env;
    return !x.is_empty() && std::isfinite(v) && mpfr_cmp_d(x.lo(), v) <= 0 &&
           mpfr_cmp_d(x.hi(), v) >= 0;
}

// ---- Fidget's further ops (issue 14) ---------------------------------------------------------

namespace {

/// [f(a) ↓, f(b) ↑] for f ∈ {floor, ceil, round} (mpfr_rint_*); defined iff both are exact and
/// equal.
template <class F>
MpfrInterval integer_step(const MpfrInterval& x, F f) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty()) return empty_at(prec);
    MpfrInterval r = MpfrAccess::make(prec);
    const int tl = f(MpfrAccess::lo(r), x.lo(), MPFR_RNDD);
    const int th = f(MpfrAccess::hi(r), x.hi(), MPFR_RNDU);
    r.defined =
        x.defined && tl == 0 && th == 0 && mpfr_equal_p(MpfrAccess::lo(r), MpfrAccess::hi(r));
    return r;
}

bool may_be_zero(const MpfrInterval& x) { return nonpos(x.lo()) && nonneg(x.hi()); }
bool is_zero(const MpfrInterval& x) { return mpfr_zero_p(x.lo()) && mpfr_zero_p(x.hi()); }

MpfrInterval with_decoration(MpfrInterval x, bool def) {
    x.defined = def && !x.is_empty();
    return x;
}

/// [lo, hi] from two integers.
MpfrInterval integers(long lo, long hi, mpfr_prec_t prec, bool def) {
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_set_si(MpfrAccess::lo(r), lo, MPFR_RNDD);
    mpfr_set_si(MpfrAccess::hi(r), hi, MPFR_RNDU);
    r.defined = def;
    return r;
}

/// [−π, π] (outward), not defined.
MpfrInterval full_angle(mpfr_prec_t prec) {
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_const_pi(MpfrAccess::hi(r), MPFR_RNDU);
    mpfr_neg(MpfrAccess::lo(r), MpfrAccess::hi(r), MPFR_RNDD);
    r.defined = false;
    return r;
}

/// π as an interval at prec.
MpfrInterval pi_interval(mpfr_prec_t prec) {
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_const_pi(MpfrAccess::lo(r), MPFR_RNDD);
    mpfr_const_pi(MpfrAccess::hi(r), MPFR_RNDU);
    r.defined = true;
    return r;
}

/// The point v (exact) at prec.
MpfrInterval point(mpfr_srcptr v, mpfr_prec_t prec) { return from_bounds(v, v, prec, true); }

}  // namespace

MpfrInterval floor(const MpfrInterval& x) { return integer_step(x, mpfr_rint_floor); }
MpfrInterval ceil(const MpfrInterval& x) { return integer_step(x, mpfr_rint_ceil); }
MpfrInterval round(const MpfrInterval& x) { return integer_step(x, mpfr_rint_round); }

MpfrInterval tan(const MpfrInterval& x) {
    const mpfr_prec_t prec = x.precision();
    if (x.is_empty()) return empty_at(prec);
    MpfrInterval whole = MpfrInterval::entire(Precision{prec});
    whole.defined = false;
    if (!mpfr_number_p(x.lo()) || !mpfr_number_p(x.hi())) return whole;
    // k(t) = (t − π/2)/π: no pole in [a, b] iff one integer n has n < k(a) ≤ k(b) < n + 1. The
    // bounds are rational, the poles not: n = ⌊lower(k(a))⌋ and upper(k(b)) ≤ n + 1 suffice.
    const MpfrInterval pi = pi_interval(prec);
    const MpfrInterval half(0.5, Precision{prec});
    const MpfrInterval ka = point(x.lo(), prec) / pi - half;
    const MpfrInterval kb = point(x.hi(), prec) / pi - half;
    Scratch n(prec);
    mpfr_floor(n, ka.lo());
    mpfr_add_ui(n, n, 1, MPFR_RNDD);  // exact: an integer far below 2^prec
    if (!(mpfr_cmp(kb.hi(), n) <= 0)) return whole;
    return monotone(x, mpfr_tan);
}

MpfrInterval asin(const MpfrInterval& x) {
    const mpfr_prec_t prec = x.precision();
    const MpfrInterval dom(-1.0, 1.0, Precision{prec});
    const MpfrInterval c = intersect(x, dom);
    if (c.is_empty()) return empty_at(prec);
    MpfrInterval r = monotone(c, mpfr_asin);
    r.defined = x.defined && mpfr_cmp_si(x.lo(), -1) >= 0 && mpfr_cmp_si(x.hi(), 1) <= 0;
    return r;
}

MpfrInterval acos(const MpfrInterval& x) {
    const mpfr_prec_t prec = x.precision();
    const MpfrInterval dom(-1.0, 1.0, Precision{prec});
    const MpfrInterval c = intersect(x, dom);
    if (c.is_empty()) return empty_at(prec);
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_acos(MpfrAccess::lo(r), c.hi(), MPFR_RNDD);
    mpfr_acos(MpfrAccess::hi(r), c.lo(), MPFR_RNDU);
    r.defined = x.defined && mpfr_cmp_si(x.lo(), -1) >= 0 && mpfr_cmp_si(x.hi(), 1) <= 0;
    return r;
}

MpfrInterval atan(const MpfrInterval& x) { return monotone(x, mpfr_atan); }

MpfrInterval atan2(const MpfrInterval& y, const MpfrInterval& x) {
    const mpfr_prec_t prec = join_precision(y, x);
    if (y.is_empty() || x.is_empty()) return empty_at(prec);
    if (may_be_zero(y) && may_be_zero(x)) {
        return is_zero(y) && is_zero(x) ? empty_at(prec) : full_angle(prec);
    }
    if (mpfr_sgn(x.lo()) < 0 && mpfr_sgn(y.lo()) < 0 && nonneg(y.hi())) return full_angle(prec);
    MpfrInterval r = MpfrAccess::make(prec);
    mpfr_ptr lo = MpfrAccess::lo(r);
    mpfr_ptr hi = MpfrAccess::hi(r);
    mpfr_set_inf(lo, 1);
    mpfr_set_inf(hi, -1);
    Scratch yc(prec), v(prec);
    for (mpfr_srcptr ys : {y.lo(), y.hi()}) {
        mpfr_set(yc, ys, MPFR_RNDN);                // exact: same or larger precision
        if (mpfr_zero_p(yc)) mpfr_set_zero(yc, 1);  // the real atan2(0, x < 0) is π
        for (mpfr_srcptr xs : {x.lo(), x.hi()}) {
            mpfr_atan2(v, yc, xs, MPFR_RNDD);
            mpfr_min(lo, lo, v, MPFR_RNDD);
            mpfr_atan2(v, yc, xs, MPFR_RNDU);
            mpfr_max(hi, hi, v, MPFR_RNDU);
        }
    }
    r.defined = y.defined && x.defined;
    return r;
}

MpfrInterval compare(const MpfrInterval& a, const MpfrInterval& b) {
    const mpfr_prec_t prec = join_precision(a, b);
    if (a.is_empty() || b.is_empty()) return empty_at(prec);
    const bool lt = mpfr_less_p(a.lo(), b.hi()) != 0, gt = mpfr_greater_p(a.hi(), b.lo()) != 0;
    const bool eq = mpfr_lessequal_p(a.lo(), b.hi()) && mpfr_lessequal_p(b.lo(), a.hi());
    const long lo = lt ? -1 : (eq ? 0 : 1), hi = gt ? 1 : (eq ? 0 : -1);
    return integers(lo, hi, prec, a.defined && b.defined && lo == hi);
}

MpfrInterval mod(const MpfrInterval& a, const MpfrInterval& b) {
    const mpfr_prec_t prec = join_precision(a, b);
    if (a.is_empty() || b.is_empty()) return empty_at(prec);
    const MpfrInterval m = abs(b);
    if (mpfr_zero_p(m.hi())) return empty_at(prec);
    MpfrInterval range = MpfrAccess::make(prec);
    mpfr_set_zero(MpfrAccess::lo(range), 1);
    mpfr_set(MpfrAccess::hi(range), m.hi(), MPFR_RNDU);
    range.defined = false;
    if (mpfr_zero_p(m.lo()) || !mpfr_number_p(a.lo()) || !mpfr_number_p(a.hi())) return range;
    const MpfrInterval q = a / m;
    if (!mpfr_number_p(q.lo()) || !mpfr_number_p(q.hi())) return range;
    Scratch n(prec), n2(prec);
    mpfr_floor(n, q.lo());
    mpfr_floor(n2, q.hi());
    if (!mpfr_equal_p(n, n2)) return range;
    const MpfrInterval r = intersect(a - m * point(n, prec), range);
    return with_decoration(r, a.defined && b.defined);
}

MpfrInterval logic_and(const MpfrInterval& a, const MpfrInterval& b) {
    const mpfr_prec_t prec = join_precision(a, b);
    if (a.is_empty()) return empty_at(prec);
    if (!may_be_zero(a)) return with_decoration(b, a.defined && b.defined);
    if (is_zero(a)) return a;
    const MpfrInterval zero(0.0, Precision{prec});
    return with_decoration(b.is_empty() ? zero : hull(zero, b), false);
}

MpfrInterval logic_or(const MpfrInterval& a, const MpfrInterval& b) {
    const mpfr_prec_t prec = join_precision(a, b);
    if (a.is_empty()) return empty_at(prec);
    if (!may_be_zero(a)) return a;
    if (is_zero(a)) return with_decoration(b, a.defined && b.defined);
    return with_decoration(b.is_empty() ? a : hull(a, b), false);
}

MpfrInterval logic_not(const MpfrInterval& a) {
    const mpfr_prec_t prec = a.precision();
    if (a.is_empty()) return empty_at(prec);
    if (is_zero(a)) return integers(1, 1, prec, a.defined);
    if (!may_be_zero(a)) return integers(0, 0, prec, a.defined);
    return integers(0, 1, prec, false);
}

}  // namespace certray
