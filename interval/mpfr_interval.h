// MpfrInterval: an interval with MPFR bounds at a chosen precision, the project's reference.
//
// Contract: an MpfrInterval is either empty or a closed set of reals [lo, hi] with
// lo ∈ [-inf, +inf), hi ∈ (-inf, +inf], lo ≤ hi; both bounds carry the same precision. Every
// operation f returns an enclosure: for all x in X (and y in Y) where f is defined, f(x[, y]) lies
// in the result (IEEE 1788 set-based semantics: points outside the domain are dropped). Lower
// bounds are rounded by MPFR with MPFR_RNDD and upper bounds with MPFR_RNDU; the floating-point
// environment (fesetround) is never touched. Binary operations compute at the larger of the two
// operand precisions.
//
// `defined` is a decoration: true means the function is defined and continuous on the whole
// input box (IEEE 1788 "dac" or better). It is the AND of the operands' flags and of the
// operation's own condition; an empty interval always has defined == false.
//
// References: IEEE Std 1788-2015 (set-based flavor, division table 10.5.5); MPFR 4 manual.
#pragma once

#include <mpfr.h>

#include <concepts>

#include "interval/number.h"  // the std overloads for double next to the ones below

namespace certray {

namespace detail {
struct MpfrAccess;
}  // namespace detail

/// A precision in bits (MPFR_PREC_MIN … MPFR_PREC_MAX; values outside are clamped). A distinct
/// type so that a precision is never mistaken for a bound.
struct Precision {
    /// The precision used when none is given.
    static constexpr mpfr_prec_t kDefault = 256;
    constexpr Precision() = default;
    constexpr Precision(mpfr_prec_t b) : bits(b) {}  // NOLINT(google-explicit-constructor)
    mpfr_prec_t bits = kDefault;
};

/// A closed real interval with MPFR bounds (or the empty set). Small value type with free
/// operations found by ADL; RAII over two mpfr_t.
class MpfrInterval {
  public:
    /// The precision in bits used when none is given.
    static constexpr mpfr_prec_t kDefaultPrecision = Precision::kDefault;

    /// The point [0, 0], defined.
    MpfrInterval() : MpfrInterval(0.0) {}
    /// The point [x, x] (exact from 53 bits up, rounded outward below). NaN or ±inf give the
    /// empty set (an interval holds reals only).
    explicit MpfrInterval(double x, Precision prec = Precision{});
    /// [lo, hi] (exact from 53 bits up). Requires lo ≤ hi, lo ≠ +inf, hi ≠ -inf, no NaN;
    /// otherwise the empty set.
    MpfrInterval(double lo, double hi, Precision prec = Precision{});
    /// MpfrInterval(x, 53) would read as both "the point x at 53 bits" and "[x, 53]": write
    /// MpfrInterval(x, Precision{53}) or MpfrInterval(x, 53.0).
    template <std::floating_point F, std::integral I>
    MpfrInterval(F, I) = delete;

    /// The empty set (defined == false).
    static MpfrInterval empty(Precision prec = Precision{});
    /// [-inf, +inf] (defined == true).
    static MpfrInterval entire(Precision prec = Precision{});

    MpfrInterval(const MpfrInterval& other);
    MpfrInterval(MpfrInterval&& other) noexcept;
    MpfrInterval& operator=(const MpfrInterval& other);
    MpfrInterval& operator=(MpfrInterval&& other) noexcept;
    ~MpfrInterval();

    /// The lower bound rounded down to a double (≤ lo); NaN when empty.
    [[nodiscard]] double lower_down() const;
    /// The upper bound rounded up to a double (≥ hi); NaN when empty.
    [[nodiscard]] double upper_up() const;
    /// Generic-code spellings of lower_down() / upper_up() (the enclosure concept).
    [[nodiscard]] double lower() const { return lower_down(); }
    [[nodiscard]] double upper() const { return upper_up(); }
    /// True iff the interval is the empty set.
    [[nodiscard]] bool is_empty() const;
    /// The exact lower bound (NaN when empty).
    [[nodiscard]] mpfr_srcptr lo() const { return lo_; }
    /// The exact upper bound (NaN when empty).
    [[nodiscard]] mpfr_srcptr hi() const { return hi_; }
    /// The precision in bits of both bounds.
    [[nodiscard]] mpfr_prec_t precision() const { return mpfr_get_prec(lo_); }

    /// The function that produced this interval is defined and continuous on the whole input box.
    bool defined = true;

  private:
    friend struct detail::MpfrAccess;
    struct Uninit {};
    // Both bounds initialised to NaN at `prec`, defined = false; the caller fills them.
    MpfrInterval(Uninit, Precision prec);

    mpfr_t lo_;
    mpfr_t hi_;
};

// Arithmetic. Case tables: `e` = empty, `E` = entire, bounds written [a, b] and [c, d].

/// x + y ⊇ {a + b}. e → e.  [a,b]+[c,d] = [a+c ↓, b+d ↑].
MpfrInterval operator+(const MpfrInterval& x, const MpfrInterval& y);
/// x − y ⊇ {a − b}. e → e.  [a,b]−[c,d] = [a−d ↓, b−c ↑].
MpfrInterval operator-(const MpfrInterval& x, const MpfrInterval& y);
/// x × y ⊇ {a·b}. e → e.  min/max of the four corner products, with 0·∞ = 0 (a bound at ∞ is
/// a limit, the set holds only reals) so [0,0]×E = [0,0].
MpfrInterval operator*(const MpfrInterval& x, const MpfrInterval& y);
/// x ÷ y ⊇ {a/b : b ≠ 0} (IEEE 1788 set-based). y = [0,0] → e;  x = [0,0] → [0,0];
/// 0 ∉ y → corner quotients;  y = [0,d]: x ≤ 0 → [-∞, b/d], x ≥ 0 → [a/d, +∞], else E;
/// y = [c,0]: x ≤ 0 → [b/c, +∞], x ≥ 0 → [-∞, a/c], else E;  c < 0 < d → E.
/// defined is false whenever 0 ∈ y.
MpfrInterval operator/(const MpfrInterval& x, const MpfrInterval& y);
/// −x = [−b, −a] (exact). e → e.
MpfrInterval operator-(const MpfrInterval& x);
/// +x = x.
MpfrInterval operator+(const MpfrInterval& x);

MpfrInterval& operator+=(MpfrInterval& x, const MpfrInterval& y);
MpfrInterval& operator-=(MpfrInterval& x, const MpfrInterval& y);
MpfrInterval& operator*=(MpfrInterval& x, const MpfrInterval& y);
MpfrInterval& operator/=(MpfrInterval& x, const MpfrInterval& y);

// Elementary functions.

/// ⌊x⌋, ⌈x⌉, x rounded half away from 0: [f(a) ↓, f(b) ↑]; defined iff f(a) = f(b) (constant).
MpfrInterval floor(const MpfrInterval& x);
MpfrInterval ceil(const MpfrInterval& x);
MpfrInterval round(const MpfrInterval& x);
/// tan x: [tan a ↓, tan b ↑] when no pole π/2 + nπ lies in [a, b]; else E, not defined.
MpfrInterval tan(const MpfrInterval& x);
/// asin, acos on x ∩ [−1, 1] (e if disjoint); defined iff x ⊆ [−1, 1].
MpfrInterval asin(const MpfrInterval& x);
MpfrInterval acos(const MpfrInterval& x);
/// atan x (increasing).
MpfrInterval atan(const MpfrInterval& x);
/// atan2(y, x) ∈ (−π, π]: e for {(0,0)}; [−π, π] not defined when the box holds the origin or
/// meets the negative x axis with y < 0 points; else the hull of the corner angles.
MpfrInterval atan2(const MpfrInterval& y, const MpfrInterval& x);
/// −1, 0, 1 as a < b, a = b, a > b: the hull of the possible values; defined iff one value.
MpfrInterval compare(const MpfrInterval& a, const MpfrInterval& b);
/// a − |b|·⌊a/|b|⌋: exact formula where ⌊a/|b|⌋ is constant on the box (defined), else
/// [0, max |b|] not defined; e when b ≡ 0.
MpfrInterval mod(const MpfrInterval& a, const MpfrInterval& b);
/// a if a = 0 else b; a if a ≠ 0 else b; 1 if a = 0 else 0 (see interval/interval_ext.h).
MpfrInterval logic_and(const MpfrInterval& a, const MpfrInterval& b);
MpfrInterval logic_or(const MpfrInterval& a, const MpfrInterval& b);
MpfrInterval logic_not(const MpfrInterval& a);

/// |x| ⊇ {|a|}. a ≥ 0 → x;  b ≤ 0 → −x;  a < 0 < b → [0, max(−a, b)].
MpfrInterval abs(const MpfrInterval& x);
/// x² ⊇ {a²} (tighter than x·x). a ≥ 0 → [a², b²];  b ≤ 0 → [b², a²];  else [0, max(a², b²)].
MpfrInterval square(const MpfrInterval& x);
/// xⁿ ⊇ {aⁿ}, n ≥ 0. n = 0 → [1,1];  n odd → [aⁿ ↓, bⁿ ↑];  n even → |x|ⁿ.
MpfrInterval pow(const MpfrInterval& x, unsigned n);
/// √x ⊇ {√a : a ≥ 0}. b < 0 → e;  a < 0 ≤ b → [0, √b] and defined = false;  else [√a ↓, √b ↑].
MpfrInterval sqrt(const MpfrInterval& x);
/// exp x = [exp a ↓, exp b ↑] (monotone; exp(−∞) = 0).
MpfrInterval exp(const MpfrInterval& x);
/// log x ⊇ {log a : a > 0}. b ≤ 0 → e;  a ≤ 0 < b → [−∞, log b] and defined = false;
/// else [log a ↓, log b ↑].
MpfrInterval log(const MpfrInterval& x);
/// sin x ⊇ {sin a}. Bounds from the endpoints, widened to ±1 whenever the box may contain a
/// maximum π/2 + 2kπ or a minimum −π/2 + 2kπ (decided with an enclosure of π; when unsure the
/// extremum is included). Infinite bound → [−1, 1].
MpfrInterval sin(const MpfrInterval& x);
/// cos x ⊇ {cos a}. As sin, with maxima 2kπ and minima (2k+1)π.
MpfrInterval cos(const MpfrInterval& x);
/// min(x, y) = [min(a, c), min(b, d)] (exact). e → e.
MpfrInterval min(const MpfrInterval& x, const MpfrInterval& y);
/// max(x, y) = [max(a, c), max(b, d)] (exact). e → e.
MpfrInterval max(const MpfrInterval& x, const MpfrInterval& y);

// Set operations.

/// The smallest interval holding x ∪ y (empty is the identity); defined = x.defined ∧ y.defined.
MpfrInterval hull(const MpfrInterval& x, const MpfrInterval& y);
/// x ∩ y; defined = x.defined ∧ y.defined (false when the result is empty).
MpfrInterval intersect(const MpfrInterval& x, const MpfrInterval& y);
/// True iff the real v lies in x (never for NaN or ±inf, never for empty x).
bool contains(const MpfrInterval& x, double v);

// The Enclosure concept (interval/number.h) spelled as free functions.

/// x.lower_down(): the lower bound rounded down to a double.
inline double lower(const MpfrInterval& x) { return x.lower_down(); }
/// x.upper_up(): the upper bound rounded up to a double.
inline double upper(const MpfrInterval& x) { return x.upper_up(); }
/// x.defined: the function is defined and continuous on the whole input box.
inline bool is_defined(const MpfrInterval& x) { return x.defined; }
/// x.is_empty().
inline bool is_empty(const MpfrInterval& x) { return x.is_empty(); }

}  // namespace certray
