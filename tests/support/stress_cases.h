// tests/support/stress_cases.h — the stiff-and-extreme suite (scenes/stress/cases.csv) for tests:
// the rays with the answers mathematics gives, and the rule a certified answer must meet.
//
// Format and expectations: scenes/stress/make_stress.py (hit, miss, tangent, hard, nohit; the root
// bracketed by the doubles root_lo ≤ root ≤ root_hi).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "solvers/ray.h"

namespace certray::testing {

struct StressCase {
    std::string label, scene, expect;
    Ray ray;
    double root_lo = 0, root_hi = 0;
};

/// The directory of the suite, ending in '/'.
inline std::string stress_dir() { return std::string(CERTRAY_SOURCE_DIR) + "/scenes/stress/"; }

/// Every case of cases.csv (a malformed line is a test failure).
inline std::vector<StressCase> read_stress_cases() {
    std::ifstream in(stress_dir() + "cases.csv");
    EXPECT_TRUE(in) << "cannot read " << stress_dir() << "cases.csv";
    std::vector<StressCase> cases;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        std::string cell;
        while (std::getline(ss, cell, ',')) f.push_back(cell);
        if (f.size() < 13) {
            ADD_FAILURE() << "bad line in cases.csv: " << line;
            continue;
        }
        StressCase c;
        c.label = f[0];
        c.scene = f[1];
        for (int i = 0; i < 3; ++i) {
            c.ray.o[i] = std::strtod(f[2 + i].c_str(), nullptr);
            c.ray.d[i] = std::strtod(f[5 + i].c_str(), nullptr);
        }
        c.ray.tmin = std::strtod(f[8].c_str(), nullptr);
        c.ray.tmax = std::strtod(f[9].c_str(), nullptr);
        c.expect = f[10];
        c.root_lo = std::strtod(f[11].c_str(), nullptr);
        c.root_hi = std::strtod(f[12].c_str(), nullptr);
        cases.push_back(c);
    }
    return cases;
}

/// Checks a certified answer: never a wrong hit or miss; with `must_prove`, simple roots and
/// misses must be proven (hit / miss, not unknown).
inline void check_stress_case(const StressCase& c, const RayResult& r, bool must_prove) {
    SCOPED_TRACE(c.label + " (" + c.scene + "): got " + std::string(name(r.status)) + " [" +
                 std::to_string(r.t_lo) + ", " + std::to_string(r.t_hi) + "]");
    if (c.expect == "hit" || c.expect == "tangent" || c.expect == "hard") {
        ASSERT_NE(r.status, Status::Miss);
        if (must_prove && c.expect == "hit") {
            EXPECT_EQ(r.status, Status::Hit);
        }
        EXPECT_LE(r.t_lo, c.root_lo);
        if (r.status == Status::Hit) {
            EXPECT_GE(r.t_hi, c.root_hi);
        }
    } else if (c.expect == "miss" || c.expect == "nohit") {
        EXPECT_NE(r.status, Status::Hit);
        if (must_prove && c.expect == "miss") {
            EXPECT_EQ(r.status, Status::Miss);
        }
    } else {
        ADD_FAILURE() << "unknown expectation '" << c.expect << "'";
    }
}

}  // namespace certray::testing
