// tests/solvers/stress_test.cpp — the stiff-and-extreme suite (scenes/stress/cases.csv): steep,
// tiny, subnormal, far, thin, tangent, touching, grazing, domain edges, overflow, clustered roots,
// a huge Lipschitz constant, undefined expressions and a 10⁴-primitive CSG, each ray with the
// answer mathematics gives (scenes/stress/make_stress.py). The certified solver and its MPFR
// reference must give zero wrong answers; the certified solver must prove every simple root.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/ray.h"

namespace certray::solvers {
namespace {

struct Case {
    std::string label, scene, expect, note;
    Ray ray;
    double root_lo = 0, root_hi = 0;
};

std::string stress_dir() { return std::string(CERTRAY_SOURCE_DIR) + "/scenes/stress/"; }

std::vector<Case> read_cases() {
    std::ifstream in(stress_dir() + "cases.csv");
    EXPECT_TRUE(in) << "cannot read " << stress_dir() << "cases.csv";
    std::vector<Case> cases;
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
        Case c;
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

/// Checks one certified answer against the case; `must_prove` demands a Hit for simple roots.
void check(const Case& c, const RayResult& r, bool must_prove) {
    SCOPED_TRACE(c.label + " (" + c.scene + "): got " + std::string(name(r.status)) + " [" +
                 std::to_string(r.t_lo) + ", " + std::to_string(r.t_hi) + "]");
    if (c.expect == "hit") {
        ASSERT_NE(r.status, Status::Miss);
        if (must_prove) EXPECT_EQ(r.status, Status::Hit);
        EXPECT_LE(r.t_lo, c.root_lo);
        if (r.status == Status::Hit) EXPECT_GE(r.t_hi, c.root_hi);
    } else if (c.expect == "miss") {
        EXPECT_NE(r.status, Status::Hit);
        if (must_prove) EXPECT_EQ(r.status, Status::Miss);
    } else if (c.expect == "tangent" || c.expect == "hard") {
        ASSERT_NE(r.status, Status::Miss);
        EXPECT_LE(r.t_lo, c.root_lo);
        if (r.status == Status::Hit) EXPECT_GE(r.t_hi, c.root_hi);
    } else if (c.expect == "nohit") {
        EXPECT_NE(r.status, Status::Hit);
    } else {
        ADD_FAILURE() << "unknown expectation '" << c.expect << "'";
    }
}

class Stress : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        cases_ = new std::vector<Case>(read_cases());
        tapes_ = new std::map<std::string, expr::Tape>;
        for (const Case& c : *cases_) {
            if (!tapes_->count(c.scene)) {
                tapes_->emplace(c.scene, expr::Tape(expr::load_graph_file(stress_dir() + c.scene)));
            }
        }
    }
    static void TearDownTestSuite() {
        delete cases_;
        delete tapes_;
    }
    static std::vector<Case>* cases_;
    static std::map<std::string, expr::Tape>* tapes_;
};
std::vector<Case>* Stress::cases_ = nullptr;
std::map<std::string, expr::Tape>* Stress::tapes_ = nullptr;

TEST_F(Stress, SuiteIsComplete) { EXPECT_GE(cases_->size(), 25u); }

TEST_F(Stress, CertifiedIsNeverWrongAndProvesSimpleRoots) {
    for (const Case& c : *cases_) {
        check(c, certified_first_root(tapes_->at(c.scene), c.ray), true);
    }
}

TEST_F(Stress, CertifiedAffineIsNeverWrong) {
    CertifiedOptions o;
    o.affine = true;
    for (const Case& c : *cases_)
        check(c, certified_first_root(tapes_->at(c.scene), c.ray, o), true);
}

TEST_F(Stress, MpfrReferenceIsNeverWrong) {
    for (const Case& c : *cases_) {
        if (c.scene == "deep_csg.expr") continue;  // 10⁴ primitives in MPFR: seconds, not needed
        check(c, certified_first_root_reference(tapes_->at(c.scene), c.ray), true);
    }
}

TEST_F(Stress, SmallBudgetsStayHonest) {
    CertifiedOptions o;
    o.budget = 8;
    for (const Case& c : *cases_) {
        const RayResult r = certified_first_root(tapes_->at(c.scene), c.ray, o);
        check(c, r, false);
        EXPECT_LE(r.evals.total(), o.budget + 16) << c.label;
    }
}

}  // namespace
}  // namespace certray::solvers
