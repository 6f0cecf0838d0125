// tests/support/ray_checks.h — small checks shared by the tests of the ray solvers: a tape from
// text, the width of an enclosure in ulps, "a hit whose enclosure holds this root", and "the
// same answers".
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "expr/parser.h"
#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::testing {

/// The tape of an expression in the .expr language.
inline expr::Tape tape_of(const std::string& text) { return expr::Tape(expr::parse_expr(text)); }

/// Width of [lo, hi] in ulps: the steps from lo up to hi (at most 10⁶ counted).
inline double ulps(double lo, double hi) {
    double n = 0;
    for (double x = lo; x < hi && n < 1e6; x = std::nextafter(x, HUGE_VAL)) ++n;
    return n;
}

/// r is a Hit whose enclosure holds `root` (the value mathematics gives) and is at most
/// `max_ulps` wide.
inline void expect_hit_at(const RayResult& r, double root, double max_ulps) {
    ASSERT_EQ(r.status, Status::Hit) << name(r.status) << " t_lo " << r.t_lo << " t_hi " << r.t_hi;
    EXPECT_LE(r.t_lo, root);
    EXPECT_GE(r.t_hi, root);
    EXPECT_LE(ulps(r.t_lo, r.t_hi), max_ulps) << r.t_lo << " " << r.t_hi;
}

/// got and want are the same answers ray by ray: the same status, and for a Hit the same
/// enclosure, bit for bit. `what` names the case in a failure.
inline void expect_same_answers(const std::vector<RayResult>& got,
                                const std::vector<RayResult>& want, const std::string& what = "") {
    ASSERT_EQ(got.size(), want.size()) << what;
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].status, want[i].status) << what << " ray " << i;
        if (want[i].status == Status::Hit && got[i].status == Status::Hit) {
            EXPECT_EQ(got[i].t_lo, want[i].t_lo) << what << " ray " << i;
            EXPECT_EQ(got[i].t_hi, want[i].t_hi) << what << " ray " << i;
        }
    }
}

}  // namespace certray::testing
