// solvers/ray.h — the vocabulary of ray queries: a ray, a status, a result with evaluation counts.
//
// Certification semantics (docs/design.md): for g(t) = f(o + t·d) on [tmin, tmax],
//   Hit  [t_lo, t_hi]: g provably has a zero in [t_lo, t_hi] and provably none in [tmin, t_lo);
//   Miss:              g provably has no zero in [tmin, tmax];
//   Unknown [t_lo, t_hi]: no zero in [tmin, t_lo) is proven, a possible zero in [t_lo, t_hi] is
//                      neither proven nor excluded (tangency, undefined points, budget).
// Approximate methods use the same type; their answers are measured, not proven.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string_view>

namespace certray {

/// o + t·d for t in [tmin, tmax]. A zero direction or tmin = tmax is a valid degenerate ray.
struct Ray {
    std::array<double, 3> o{0, 0, 0};
    std::array<double, 3> d{0, 0, 1};
    double tmin = 0;
    double tmax = std::numeric_limits<double>::infinity();
};

enum class Status : std::uint8_t { Hit, Miss, Unknown };

constexpr std::string_view name(Status s) noexcept {
    switch (s) {
        case Status::Hit:
            return "hit";
        case Status::Miss:
            return "miss";
        case Status::Unknown:
            return "unknown";
    }
    return "?";
}

/// Whole-tape evaluations, by kind: a value (double, or a batch lane), an enclosure (interval,
/// affine), a gradient (dual numbers, any base type).
struct EvalCounts {
    std::uint64_t value = 0;
    std::uint64_t interval = 0;
    std::uint64_t gradient = 0;
    std::uint64_t total() const noexcept { return value + interval + gradient; }
    EvalCounts& operator+=(const EvalCounts& o) noexcept {
        value += o.value;
        interval += o.interval;
        gradient += o.gradient;
        return *this;
    }
};

/// The answer for one ray. For Hit and Unknown, [t_lo, t_hi] is the enclosure (Hit) or the
/// candidate interval (Unknown) and t a representative point in it; for Miss all three are NaN.
struct RayResult {
    Status status = Status::Unknown;
    double t_lo = std::numeric_limits<double>::quiet_NaN();
    double t_hi = std::numeric_limits<double>::quiet_NaN();
    double t = std::numeric_limits<double>::quiet_NaN();
    EvalCounts evals;
};

}  // namespace certray
