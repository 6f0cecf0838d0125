// tracers/quad_interval.h — QuadInterval: four UpIntervals evaluated in lock-step (four boxes per
// walk of a tape), for the 2D quadtree's four subtiles.
//
// Contract: lane k of every operation is the UpInterval operation on lane k of the operands — the
// same function, so the same bounds and decoration bit for bit as four separate evaluations —
// and, like UpInterval, valid only inside a live RoundingScope. What it buys: one dispatch of each
// instruction (one switch, one mispredicted branch) for four boxes, which is most of the cost of
// an interval walk (tracers/image2d.cpp; docs/benchmarks.md, "Rendering").
// Lanes are UpIntervals side by side, so lane k of a register file of QuadIntervals is a strided
// array of UpIntervals (`lane_stride`), which expr::prune_ssa reads directly.
#pragma once

#include "interval/interval.h"

namespace certray::tracers {

/// Four UpIntervals, one per lane; each operation acts lane by lane.
struct QuadInterval {
    /// Number of lanes.
    static constexpr int kLanes = 4;
    /// The lanes.
    UpInterval v[kLanes];

    /// All lanes [0, 0] (for register files).
    QuadInterval() = default;
    /// All lanes the point c (a constant of the tape). Implicit, so that `T(c)` works generically.
    QuadInterval(double c) {  // NOLINT: implicit on purpose
        const UpInterval x(c);
        for (UpInterval& l : v) l = x;
    }
};

/// Distance, in UpIntervals, from lane k of one QuadInterval to lane k of the next.
inline constexpr std::size_t lane_stride = sizeof(QuadInterval) / sizeof(UpInterval);
static_assert(sizeof(QuadInterval) == QuadInterval::kLanes * sizeof(UpInterval));

namespace detail {

/// f applied lane by lane.
template <class F>
[[gnu::always_inline]] inline QuadInterval lanes(const QuadInterval& a, F f) {
    QuadInterval r;
    for (int k = 0; k < QuadInterval::kLanes; ++k) r.v[k] = f(a.v[k]);
    return r;
}
/// f applied lane by lane to two operands.
template <class F>
[[gnu::always_inline]] inline QuadInterval lanes(const QuadInterval& a, const QuadInterval& b,
                                                 F f) {
    QuadInterval r;
    for (int k = 0; k < QuadInterval::kLanes; ++k) r.v[k] = f(a.v[k], b.v[k]);
    return r;
}

}  // namespace detail

/// −a lane by lane.
inline QuadInterval operator-(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return -x; });
}
/// |a| lane by lane.
inline QuadInterval abs(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::abs(x); });
}
/// a² lane by lane.
inline QuadInterval square(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::square(x); });
}
/// √a lane by lane.
inline QuadInterval sqrt(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::sqrt(x); });
}
/// eᵃ lane by lane.
inline QuadInterval exp(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::exp(x); });
}
/// ln a lane by lane.
inline QuadInterval log(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::log(x); });
}
/// sin a lane by lane.
inline QuadInterval sin(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::sin(x); });
}
/// cos a lane by lane.
inline QuadInterval cos(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::cos(x); });
}
/// aⁿ lane by lane.
inline QuadInterval pow(const QuadInterval& a, unsigned n) {
    return detail::lanes(a, [n](const UpInterval& x) { return certray::pow(x, n); });
}
/// a + b lane by lane.
inline QuadInterval operator+(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(a, b, [](const UpInterval& x, const UpInterval& y) { return x + y; });
}
/// a − b lane by lane.
inline QuadInterval operator-(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(a, b, [](const UpInterval& x, const UpInterval& y) { return x - y; });
}
/// a · b lane by lane.
inline QuadInterval operator*(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(a, b, [](const UpInterval& x, const UpInterval& y) { return x * y; });
}
/// a / b lane by lane.
inline QuadInterval operator/(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(a, b, [](const UpInterval& x, const UpInterval& y) { return x / y; });
}
/// min(a, b) lane by lane.
inline QuadInterval min(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(
        a, b, [](const UpInterval& x, const UpInterval& y) { return certray::min(x, y); });
}
/// max(a, b) lane by lane.
inline QuadInterval max(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(
        a, b, [](const UpInterval& x, const UpInterval& y) { return certray::max(x, y); });
}

/// floor lane by lane.
inline QuadInterval floor(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::floor(x); });
}
/// ceil lane by lane.
inline QuadInterval ceil(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::ceil(x); });
}
/// round lane by lane.
inline QuadInterval round(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::round(x); });
}
/// tan lane by lane.
inline QuadInterval tan(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::tan(x); });
}
/// asin lane by lane.
inline QuadInterval asin(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::asin(x); });
}
/// acos lane by lane.
inline QuadInterval acos(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::acos(x); });
}
/// atan lane by lane.
inline QuadInterval atan(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::atan(x); });
}
/// logic_not lane by lane.
inline QuadInterval logic_not(const QuadInterval& a) {
    return detail::lanes(a, [](const UpInterval& x) { return certray::logic_not(x); });
}
/// atan2 lane by lane.
inline QuadInterval atan2(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(
        a, b, [](const UpInterval& x, const UpInterval& y) { return certray::atan2(x, y); });
}
/// compare lane by lane.
inline QuadInterval compare(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(
        a, b, [](const UpInterval& x, const UpInterval& y) { return certray::compare(x, y); });
}
/// mod lane by lane.
inline QuadInterval mod(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(
        a, b, [](const UpInterval& x, const UpInterval& y) { return certray::mod(x, y); });
}
/// logic_and lane by lane.
inline QuadInterval logic_and(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(
        a, b, [](const UpInterval& x, const UpInterval& y) { return certray::logic_and(x, y); });
}
/// logic_or lane by lane.
inline QuadInterval logic_or(const QuadInterval& a, const QuadInterval& b) {
    return detail::lanes(
        a, b, [](const UpInterval& x, const UpInterval& y) { return certray::logic_or(x, y); });
}

}  // namespace certray::tracers
