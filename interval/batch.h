// interval/batch.h — Batch: kBatch doubles evaluated in lock-step (one tape walk, 128 points).
//
// Contract: every operation applies the corresponding double operation of interval/number.h to
// each lane independently, so lane i of a Batch result is bit for bit what the double evaluator
// computes at lane i's inputs (NaN for NaN: min and max propagate it as certray::min does). The
// arithmetic, sqrt, abs, min and max are vectorised by Eigen (IEEE-exact, so vectorising changes no
// bit); exp, log, sin and cos call the libm function per lane, because Eigen's vectorised versions
// are polynomial approximations that differ from libm in the last bits.
// Use: expr::Evaluator<Batch> runs a tape over 128 points per walk, amortising the dispatch of
// each instruction over the lanes (128 rather than 64: 25–45 % less time per point with AVX-512,
// docs/benchmarks.md "Batch code"). It does not go through these operators: its walk is
// expr/eval_batch.cpp, one copy per instruction set (SSE2, AVX2, AVX-512, chosen at run time,
// expr/eval_batch.h) under the same contract; the operators serve generic code (detail::run<Batch>)
// and make Batch a Number. Batch is 64-byte aligned so that no vector load straddles a cache line
// (docs/benchmarks.md, "Expression evaluation").
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <utility>

#include "interval/number.h"

namespace certray {

/// Number of lanes of a Batch.
inline constexpr int kBatch = 128;

/// The result of a lane-by-lane operation, not yet stored: an Eigen expression that assigning to
/// a Batch evaluates straight into its lanes. The evaluator's `r[out] = r[a] + r[b]` thus writes
/// each lane once, with no 1 KiB temporary and copy (coefficient-wise operations are safe
/// when `out` is also an operand). Converts to a Batch wherever a value is needed. Holds
/// references to its operands: store it in a Batch, never in `auto`.
template <class E>
struct BatchExpr {
    E e;
};

/// kBatch doubles; each operation acts lane by lane. A small value type with a public array,
/// aligned to a cache line.
struct alignas(64) Batch {
    using Array = Eigen::Array<double, kBatch, 1>;

    /// The lanes.
    Array v;

    /// All lanes 0 (so that register files of Batch can be resized).
    Batch() : v(Array::Zero()) {}
    /// All lanes c (a constant of the tape). Implicit, so that `T(c)` works generically.
    Batch(double c) : v(Array::Constant(c)) {}  // NOLINT: implicit on purpose
    /// The lanes of an Eigen array expression, evaluated straight into v (no temporary array).
    template <class E>
    explicit Batch(const Eigen::ArrayBase<E>& e) : v(e) {}
    /// The lanes of a pending operation (implicit: a BatchExpr is a Batch not yet stored).
    template <class E>
    Batch(const BatchExpr<E>& x) : v(x.e) {}  // NOLINT: implicit on purpose
    Batch(const Batch&) = default;
    Batch& operator=(const Batch&) = default;
    /// Evaluates a pending operation into these lanes.
    template <class E>
    Batch& operator=(const BatchExpr<E>& x) {
        v = x.e;
        return *this;
    }

    /// Lane i.
    double operator[](int i) const { return v[i]; }
    /// Lane i.
    double& operator[](int i) { return v[i]; }
};

namespace detail {

/// f applied to each lane with the scalar (libm) function, for bit-exact transcendentals.
template <class F>
Batch lanewise(const Batch& x, F f) {
    Batch r(x);  // a copy, not a zero fill: every lane is overwritten
    for (int i = 0; i < kBatch; ++i) r.v[i] = f(r.v[i]);
    return r;
}

}  // namespace detail

namespace detail {
template <class E>
BatchExpr<E> lazy(E&& e) {
    return BatchExpr<E>{std::forward<E>(e)};
}
}  // namespace detail

/// a + b lane by lane (one rounding per lane, as in double).
inline auto operator+(const Batch& a, const Batch& b) { return detail::lazy(a.v + b.v); }
/// a − b lane by lane.
inline auto operator-(const Batch& a, const Batch& b) { return detail::lazy(a.v - b.v); }
/// a · b lane by lane.
inline auto operator*(const Batch& a, const Batch& b) { return detail::lazy(a.v * b.v); }
/// a / b lane by lane.
inline auto operator/(const Batch& a, const Batch& b) { return detail::lazy(a.v / b.v); }
/// −a lane by lane (exact: flips the sign bit).
inline auto operator-(const Batch& a) { return detail::lazy(-a.v); }

/// |a| lane by lane (exact).
inline auto abs(const Batch& a) { return detail::lazy(a.v.abs()); }
/// a² lane by lane as a · a (one rounding, like square(double)).
inline auto square(const Batch& a) { return detail::lazy(a.v * a.v); }
/// aⁿ lane by lane by binary powering — the same product sequence as pow(double, unsigned), so the
/// same roundings.
inline Batch pow(Batch x, unsigned n) {
    Batch r(1.0);
    while (n) {
        if (n & 1u) r.v *= x.v;
        x.v *= x.v;
        n >>= 1u;
    }
    return r;
}
/// √a lane by lane (IEEE correctly rounded in both the vector and the scalar instruction; NaN
/// for a < 0).
inline auto sqrt(const Batch& a) { return detail::lazy(a.v.sqrt()); }
/// eᵃ lane by lane with libm's exp.
inline Batch exp(const Batch& a) {
    return detail::lanewise(a, [](double x) { return std::exp(x); });
}
/// ln a lane by lane with libm's log (NaN for a < 0, −inf at 0).
inline Batch log(const Batch& a) {
    return detail::lanewise(a, [](double x) { return std::log(x); });
}
/// sin a lane by lane with libm's sin.
inline Batch sin(const Batch& a) {
    return detail::lanewise(a, [](double x) { return std::sin(x); });
}
/// cos a lane by lane with libm's cos.
inline Batch cos(const Batch& a) {
    return detail::lanewise(a, [](double x) { return std::cos(x); });
}

/// min lane by lane, propagating NaN. Written as certray::min(double, double)'s own rule,
/// (a < b or a is NaN) ? a : b, as a vector compare and blend: Eigen's
/// `min<PropagateNaN>` propagates NaN too but breaks the tie min(−0, +0) the other way
/// (it returns a, certray::min returns b), which would change the sign of a zero result.
inline auto min(const Batch& a, const Batch& b) {
    return detail::lazy(((a.v < b.v) || a.v.isNaN()).select(a.v, b.v));
}
/// max lane by lane, propagating NaN: (a > b or a is NaN) ? a : b, like certray::max.
inline auto max(const Batch& a, const Batch& b) {
    return detail::lazy(((a.v > b.v) || a.v.isNaN()).select(a.v, b.v));
}

// ---- Fidget's further ops (issue 14): lane by lane with the scalar functions run<double> calls.
/// floor lane by lane (the scalar double function).
inline Batch floor(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::floor(x); });
}
/// ceil lane by lane (the scalar double function).
inline Batch ceil(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::ceil(x); });
}
/// round lane by lane (the scalar double function).
inline Batch round(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::round(x); });
}
/// tan lane by lane (the scalar double function).
inline Batch tan(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::tan(x); });
}
/// asin lane by lane (the scalar double function).
inline Batch asin(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::asin(x); });
}
/// acos lane by lane (the scalar double function).
inline Batch acos(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::acos(x); });
}
/// atan lane by lane (the scalar double function).
inline Batch atan(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::atan(x); });
}
/// logic_not lane by lane (the scalar double function).
inline Batch logic_not(const Batch& a) {
    return detail::lanewise(a, [](double x) { return certray::logic_not(x); });
}

namespace detail {
/// f lane by lane over two operands.
template <class F>
Batch lanewise2(const Batch& a, const Batch& b, F f) {
    Batch r(a);  // every lane is overwritten
    for (int k = 0; k < kBatch; ++k) r.v[k] = f(a.v[k], b.v[k]);
    return r;
}
}  // namespace detail
/// atan2 lane by lane (the scalar double function).
inline Batch atan2(const Batch& a, const Batch& b) {
    return detail::lanewise2(a, b, [](double x, double y) { return certray::atan2(x, y); });
}
/// compare lane by lane (the scalar double function).
inline Batch compare(const Batch& a, const Batch& b) {
    return detail::lanewise2(a, b, [](double x, double y) { return certray::compare(x, y); });
}
/// mod lane by lane (the scalar double function).
inline Batch mod(const Batch& a, const Batch& b) {
    return detail::lanewise2(a, b, [](double x, double y) { return certray::mod(x, y); });
}
/// logic_and lane by lane (the scalar double function).
inline Batch logic_and(const Batch& a, const Batch& b) {
    return detail::lanewise2(a, b, [](double x, double y) { return certray::logic_and(x, y); });
}
/// logic_or lane by lane (the scalar double function).
inline Batch logic_or(const Batch& a, const Batch& b) {
    return detail::lanewise2(a, b, [](double x, double y) { return certray::logic_or(x, y); });
}

static_assert(Number<Batch>, "Batch must be usable by the expression evaluator");

}  // namespace certray
