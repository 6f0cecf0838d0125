// RapidCheck generators for number-type tests, and a floating-point-environment guard.
//
// The generators aim at the corners where interval code breaks: extreme magnitudes (up to about
// 1e±300), subnormals, signed zeros, infinities, exact small integers and dyadic fractions,
// degenerate, tiny, huge and unbounded boxes. Every value they build is exact (ldexp of an
// integer), so a run does not depend on the rounding mode. Runs are reproducible through
// RapidCheck's own mechanism: RC_PARAMS="seed=N" (the seed of a failure is printed).
#pragma once

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <algorithm>
#include <array>
#include <cfenv>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "interval/interval.h"
#include "solvers/ray.h"
#include "tests/support/fp_env.h"

namespace certray::testing {

namespace detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// ±m · 2^e, exact for the integer ranges used below.
inline double signed_ldexp(std::int64_t m, int e, bool negative) {
    const double v = std::ldexp(static_cast<double>(m), e);
    return negative ? -v : v;
}

/// The finite part of gen_double's mix; `with_inf` adds ±inf with a small weight.
inline rc::Gen<double> gen_double_mix(bool with_inf) {
    namespace gen = rc::gen;
    // Ordinary values: a 53-bit integer scaled so that magnitudes reach about 2^20.
    auto ordinary = gen::apply(signed_ldexp, gen::inRange<std::int64_t>(0, std::int64_t{1} << 53),
                               gen::inRange(-73, -32), gen::arbitrary<bool>());
    // Extreme magnitudes: a normalised 53-bit significand with exponent 2^-996 … 2^997
    // (≈ 1.5e-300 … 1.3e300), plus the ends of the double range.
    auto extreme = gen::weightedOneOf<double>({
        {9, gen::apply(signed_ldexp,
                       gen::inRange<std::int64_t>(std::int64_t{1} << 52, std::int64_t{1} << 53),
                       gen::inRange(-996 - 52, 997 - 52), gen::arbitrary<bool>())},
        {1, gen::element(DBL_MAX, -DBL_MAX, DBL_MIN, -DBL_MIN)},
    });
    auto subnormal = gen::apply(signed_ldexp, gen::inRange<std::int64_t>(1, std::int64_t{1} << 52),
                                gen::just(-1074), gen::arbitrary<bool>());
    auto zero = gen::element(0.0, -0.0);
    auto small_int =
        gen::map(gen::inRange(-100, 101), [](int k) { return static_cast<double>(k); });
    auto dyadic = gen::apply([](int k, int j) { return std::ldexp(static_cast<double>(k), -j); },
                             gen::inRange(-1000, 1001), gen::inRange(1, 21));
    if (with_inf) {
        return gen::weightedOneOf<double>({
            {30, ordinary},
            {12, extreme},
            {6, subnormal},
            {8, zero},
            {15, small_int},
            {15, dyadic},
            {2, gen::element(kInf, -kInf)},
        });
    }
    return gen::weightedOneOf<double>({
        {30, ordinary},
        {12, extreme},
        {6, subnormal},
        {8, zero},
        {15, small_int},
        {15, dyadic},
    });
}

/// Turns (a, b) into a valid nonempty real box: sorted, lo < +inf, hi > −inf.
inline std::pair<double, double> as_bounds(double a, double b) {
    double lo = std::min(a, b);
    double hi = std::max(a, b);
    if (lo == kInf) {
        lo = DBL_MAX;
    }
    if (hi == -kInf) {
        hi = -DBL_MAX;
    }
    return {lo, hi};
}

}  // namespace detail

/// Doubles from a mix of: ordinary values (|x| up to ~2^20), extreme magnitudes (up to 1e±300 and
/// ±DBL_MAX), subnormals, ±0, exact small integers, dyadic fractions k/2^j, and rarely ±inf.
/// Never NaN.
inline rc::Gen<double> gen_double() { return detail::gen_double_mix(/*with_inf=*/true); }

/// As gen_double(), without infinities.
inline rc::Gen<double> gen_finite_double() { return detail::gen_double_mix(/*with_inf=*/false); }

/// A nonempty real box {lo, hi}: lo ≤ hi, lo ≠ +inf, hi ≠ −inf, no NaN. Drawn from degenerate
/// points, boxes straddling 0, widths of a few ulps, huge widths, half-unbounded and (rarely)
/// entire boxes, and two sorted gen_double() values.
inline rc::Gen<std::pair<double, double>> gen_bounds() {
    namespace gen = rc::gen;
    using Bounds = std::pair<double, double>;
    using detail::kInf;
    auto point = gen::map(gen_finite_double(), [](double p) { return Bounds{p, p}; });
    auto straddle = gen::apply(
        [](double a, double b) {
            return Bounds{-std::fabs(a), std::fabs(b)};
        },
        gen_finite_double(), gen_finite_double());
    auto tiny = gen::apply(
        [](double p, int ulps) {
            double hi = p;
            for (int i = 0; i < ulps; ++i) {
                hi = std::nextafter(hi, kInf);
            }
            return Bounds{p, hi};
        },
        gen_finite_double(), gen::inRange(1, 5));
    auto huge = gen::apply(
        [](std::int64_t m1, int e1, std::int64_t m2, int e2) {
            return Bounds{-std::ldexp(static_cast<double>(m1), e1),
                          std::ldexp(static_cast<double>(m2), e2)};
        },
        gen::inRange<std::int64_t>(1, std::int64_t{1} << 53), gen::inRange(100, 971),
        gen::inRange<std::int64_t>(1, std::int64_t{1} << 53), gen::inRange(100, 971));
    auto half = gen::apply(
        [](double p, bool upward) {
            return upward ? Bounds{p, kInf} : Bounds{-kInf, p};
        },
        gen_finite_double(), gen::arbitrary<bool>());
    auto any = gen::apply(detail::as_bounds, gen_double(), gen_double());
    return gen::weightedOneOf<Bounds>({
        {10, point},
        {15, straddle},
        {12, tiny},
        {8, huge},
        {5, half},
        {1, gen::just(Bounds{-kInf, kInf})},
        {30, any},
    });
}

/// A finite double in [lo, hi] (requires lo ≤ hi, lo ≠ +inf, hi ≠ −inf). Favours the endpoints,
/// their neighbours and 0 (when inside); an unbounded side contributes finite values on that side
/// (down to ∓DBL_MAX).
inline rc::Gen<double> gen_point_in(double lo, double hi) {
    namespace gen = rc::gen;
    using detail::kInf;
    std::vector<rc::Gen<double>> choices;
    const auto clamp = [lo, hi](double v) {
        v = std::clamp(v, lo, hi);
        return std::clamp(v, -DBL_MAX, DBL_MAX);
    };
    const bool lo_finite = std::isfinite(lo);
    const bool hi_finite = std::isfinite(hi);
    if (lo_finite) {
        choices.push_back(gen::just(lo));
        choices.push_back(gen::just(lo));
        choices.push_back(gen::just(clamp(std::nextafter(lo, kInf))));
    }
    if (hi_finite) {
        choices.push_back(gen::just(hi));
        choices.push_back(gen::just(hi));
        choices.push_back(gen::just(clamp(std::nextafter(hi, -kInf))));
    }
    if (lo <= 0.0 && 0.0 <= hi) {
        choices.push_back(gen::just(0.0));
        choices.push_back(gen::element(0.0, -0.0));
    }
    if (lo_finite && hi_finite) {
        // Uniform-ish: lo·(1 − s) + hi·s cannot overflow for opposite signs; clamped otherwise.
        constexpr std::int64_t kSteps = std::int64_t{1} << 30;
        auto uniform = gen::map(gen::inRange<std::int64_t>(0, kSteps + 1), [=](std::int64_t k) {
            const double s = std::ldexp(static_cast<double>(k), -30);
            return clamp(lo * (1.0 - s) + hi * s);
        });
        choices.push_back(uniform);
        choices.push_back(uniform);
        choices.push_back(uniform);
    } else if (!lo_finite && !hi_finite) {
        choices.push_back(gen_finite_double());
        choices.push_back(gen_finite_double());
        choices.push_back(gen::just(-DBL_MAX));
        choices.push_back(gen::just(DBL_MAX));
    } else {
        // One unbounded side: step away from the finite end by a random magnitude.
        const double sign = lo_finite ? 1.0 : -1.0;
        const double end = lo_finite ? lo : hi;
        auto away = gen::map(gen_finite_double(),
                             [=](double v) { return clamp(end + sign * std::fabs(v)); });
        choices.push_back(away);
        choices.push_back(away);
        choices.push_back(gen::just(sign * DBL_MAX));
    }
    // Values spread over magnitudes, clamped into the box (also lands on the ends).
    choices.push_back(gen::map(gen_finite_double(), clamp));
    choices.push_back(gen::map(gen_finite_double(), clamp));
    const std::size_t n = choices.size();
    return gen::mapcat(gen::inRange<std::size_t>(0, n),
                       [choices = std::move(choices)](std::size_t i) { return choices[i]; });
}

/// A ray for property tests: origin on the grid 0.01·[−300, 300]³, direction 1/`d_den`·[−100,
/// 100]³ (possibly zero: a degenerate ray), t ∈ [0, tmax] with tmax = 0.1·[1, `tmax_tenths`].
/// Dyadic-free decimal grids, so rays rarely sit exactly on cell faces — but sometimes do.
inline rc::Gen<Ray> gen_ray(int d_den = 50, int tmax_tenths = 50) {
    return rc::gen::exec([d_den, tmax_tenths] {
        Ray ray;
        for (int i = 0; i < 3; ++i) {
            ray.o[i] = *rc::gen::inRange(-300, 300) / 100.0;
            ray.d[i] = *rc::gen::inRange(-100, 100) / static_cast<double>(d_den);
        }
        ray.tmin = 0;
        ray.tmax = *rc::gen::inRange(1, tmax_tenths) / 10.0;
        return ray;
    });
}

/// A segment {o + t·u : t ∈ [t0, t1]} on a dyadic grid with few bits — o in [−2, 2]³ and u in
/// [−1, 1]³ by 64ths, t0 in [−1, 1] and t1 − t0 in (0, 1] by 64ths — so that o + t·u is an exact
/// double at t0, t1, their middle and eighths between them (the mean value form tests take f
/// there by MPFR).
struct DyadicSegment {
    std::array<double, 3> o, u;
    double t0, t1;
};
inline rc::Gen<DyadicSegment> gen_dyadic_segment() {
    return rc::gen::exec([] {
        DyadicSegment s;
        for (int c = 0; c < 3; ++c) {
            s.o[c] = *rc::gen::inRange(-128, 129) / 64.0;
            s.u[c] = *rc::gen::inRange(-64, 65) / 64.0;
        }
        s.t0 = *rc::gen::inRange(-64, 65) / 64.0;
        s.t1 = s.t0 + *rc::gen::inRange(1, 65) / 64.0;
        return s;
    });
}

/// Π (x − rᵢ) as .expr text, with the roots: 1 to max_factors dyadic roots rᵢ = kᵢ/64 in [−4, 4]
/// (exact doubles, so the polynomial's real roots are known exactly; repeats give multiple roots).
struct RootProduct {
    std::string text;
    std::vector<double> roots;
};
inline rc::Gen<RootProduct> gen_root_product(int max_factors) {
    return rc::gen::exec([max_factors] {
        RootProduct p;
        const int n = *rc::gen::inRange(1, max_factors + 1);
        for (int i = 0; i < n; ++i) {
            const double r = *rc::gen::inRange(-256, 256) / 64.0;
            p.roots.push_back(r);
            char buf[64];
            std::snprintf(buf, sizeof buf, "%s(x - %.17g)", i ? " * " : "", r);
            p.text += buf;
        }
        return p;
    });
}

/// RAII check that no code leaks a change of the floating-point control state: records the raw
/// MXCSR and x87 control words on construction (fp_env.h); on destruction, if they differ,
/// restores them and records a test failure (ADD_FAILURE).
struct FpEnvGuard {
    FpEnvGuard() : words(read_fp_words()) {}
    FpEnvGuard(const FpEnvGuard&) = delete;
    FpEnvGuard& operator=(const FpEnvGuard&) = delete;
    ~FpEnvGuard() {
        const FpWords now = read_fp_words();
        if (!same_control(now, words)) {
            write_fp_words(words);
            ADD_FAILURE() << "floating-point control words leaked: were " << describe(words)
                          << ", found " << describe(now) << " (restored)";
        }
    }

    /// The control words on entry.
    const FpWords words;
};

}  // namespace certray::testing
