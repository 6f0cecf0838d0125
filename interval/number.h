// interval/number.h — the Number and Enclosure concepts every type the DAG is evaluated over meets.
//
// Generic code (the evaluator, Dual, Affine) calls sqrt(x), square(x), pow(x, n), min(a, b) …
// unqualified inside namespace certray: the std overloads for double are brought in here, and
// each number type provides its own as free functions found by argument-dependent lookup.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>

namespace certray {

using std::abs;
using std::acos;
using std::asin;
using std::atan;
using std::atan2;
using std::ceil;
using std::cos;
using std::exp;
using std::floor;
using std::log;
using std::round;
using std::sin;
using std::sqrt;
using std::tan;

/// min for doubles, propagating NaN: a point where an operand is undefined stays undefined
/// (std::min(x, NaN) would return x and hide it).
inline double min(double a, double b) { return (a < b || std::isnan(a)) ? a : b; }
/// max for doubles, propagating NaN like min.
inline double max(double a, double b) { return (a > b || std::isnan(a)) ? a : b; }
/// x² for doubles (one rounding, like x * x).
inline double square(double x) { return x * x; }
/// xⁿ by binary powering (n a non-negative integer; x⁰ = 1) for a double or a GCC vector of
/// doubles, lane by lane: the same products in the same order (expr/eval_dual_batch.cpp's lanes
/// are pow's bits so).
template <class T>
inline T binary_power(T x, unsigned n) {
    T r = T{} + 1.0;
    while (n) {
        if (n & 1u) r = r * x;
        x = x * x;
        n >>= 1u;
    }
    return r;
}
/// xⁿ for doubles by binary powering (n a non-negative integer; pow(x, 0) = 1).
inline double pow(double x, unsigned n) { return binary_power(x, n); }
/// Fidget's compare: −1 if a < b, 0 if a = b, 1 if a > b, NaN if either is NaN.
inline double compare(double a, double b) {
    return a < b ? -1.0 : (a > b ? 1.0 : (a == b ? 0.0 : std::numeric_limits<double>::quiet_NaN()));
}
/// Euclidean remainder (Rust's rem_euclid, Fidget's mod): r = fmod(a, b) (exact), r + |b| when
/// r < 0 (one rounding); NaN for b = 0.
inline double mod(double a, double b) {
    const double r = std::fmod(a, b);
    return r < 0 ? r + std::fabs(b) : r;
}
/// Fidget's and: a if a = 0, else b (NaN a selects b).
inline double logic_and(double a, double b) { return a == 0 ? a : b; }
/// Fidget's or: a if a ≠ 0 (NaN included), else b.
inline double logic_or(double a, double b) { return a != 0 ? a : b; }
/// Fidget's not: 1 if a = 0, else 0 (NaN gives 0).
inline double logic_not(double a) { return a == 0 ? 1.0 : 0.0; }
inline double lower(double x) { return x; }
inline double upper(double x) { return x; }

/// A type the expression evaluator can run over: closed under the op set, constructible from a
/// double constant.
template <class T>
concept Number = std::copyable<T> && requires(const T& a, const T& b, double c, unsigned n) {
    T(c);
    { a + b } -> std::convertible_to<T>;
    { a - b } -> std::convertible_to<T>;
    { a* b } -> std::convertible_to<T>;
    { a / b } -> std::convertible_to<T>;
    { -a } -> std::convertible_to<T>;
    { abs(a) } -> std::convertible_to<T>;
    { square(a) } -> std::convertible_to<T>;
    { pow(a, n) } -> std::convertible_to<T>;
    { sqrt(a) } -> std::convertible_to<T>;
    { exp(a) } -> std::convertible_to<T>;
    { log(a) } -> std::convertible_to<T>;
    { sin(a) } -> std::convertible_to<T>;
    { cos(a) } -> std::convertible_to<T>;
    { min(a, b) } -> std::convertible_to<T>;
    { max(a, b) } -> std::convertible_to<T>;
    { floor(a) } -> std::convertible_to<T>;
    { ceil(a) } -> std::convertible_to<T>;
    { round(a) } -> std::convertible_to<T>;
    { tan(a) } -> std::convertible_to<T>;
    { asin(a) } -> std::convertible_to<T>;
    { acos(a) } -> std::convertible_to<T>;
    { atan(a) } -> std::convertible_to<T>;
    { logic_not(a) } -> std::convertible_to<T>;
    { atan2(a, b) } -> std::convertible_to<T>;
    { compare(a, b) } -> std::convertible_to<T>;
    { mod(a, b) } -> std::convertible_to<T>;
    { logic_and(a, b) } -> std::convertible_to<T>;
    { logic_or(a, b) } -> std::convertible_to<T>;
};

/// A Number that encloses sets of reals: it has bounds and a decoration saying the function that
/// produced it is defined and continuous on the whole input box.
template <class T>
concept Enclosure = Number<T> && requires(const T& a) {
    { lower(a) } -> std::convertible_to<double>;
    { upper(a) } -> std::convertible_to<double>;
    { is_defined(a) } -> std::convertible_to<bool>;
};

}  // namespace certray
