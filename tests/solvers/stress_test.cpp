// tests/solvers/stress_test.cpp — the stiff-and-extreme suite (scenes/stress/cases.csv): steep,
// tiny, subnormal, far, thin, tangent, touching, grazing, domain edges, overflow, clustered roots,
// a huge Lipschitz constant, undefined expressions and a 10⁴-primitive CSG, each ray with the
// answer mathematics gives (scenes/stress/make_stress.py). The certified solver and its MPFR
// reference must give zero wrong answers; the certified solver must prove every simple root.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/analytic.h"
#include "solvers/certified.h"
#include "solvers/exact.h"
#include "solvers/ray.h"
#include "tests/support/fp_env.h"
#include "tests/support/stress_cases.h"

namespace certray::solvers {
namespace {

using testing::read_stress_cases;
using testing::stress_dir;
using Case = testing::StressCase;

void check(const Case& c, const RayResult& r, bool must_prove) {
    testing::check_stress_case(c, r, must_prove);
}

class Stress : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        cases_ = new std::vector<Case>(read_stress_cases());
        tapes_ = new std::map<std::string, expr::Tape>;
        for (const Case& c : *cases_) {
            if (!tapes_->count(c.scene)) {
                tapes_->emplace(
                    c.scene, testing::as_host([&] {
                        return expr::Tape(expr::load_graph_file(stress_dir() + c.scene));
                    }));
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
        check(c, testing::as_host([&] { return certified_first_root(tapes_->at(c.scene), c.ray); }),
              true);
    }
}

TEST_F(Stress, CertifiedAffineIsNeverWrong) {
    CertifiedOptions o;
    o.affine = true;
    for (const Case& c : *cases_)
        check(c,
              testing::as_host([&] { return certified_first_root(tapes_->at(c.scene), c.ray, o); }),
              true);
}

TEST_F(Stress, MpfrReferenceIsNeverWrong) {
    for (const Case& c : *cases_) {
        if (c.scene == "deep_csg.expr") continue;  // 10⁴ primitives in MPFR: seconds, not needed
        check(c, testing::as_host([&] {
                  return certified_first_root_reference(tapes_->at(c.scene), c.ray);
              }),
              true);
    }
}

// The exact oracle on the polynomial scenes decides every case: tangents and near misses too.
TEST_F(Stress, ExactDecidesEveryPolynomialCase) {
    int polynomial = 0;
    for (const Case& c : *cases_) {
        const expr::Tape& tape = tapes_->at(c.scene);
        if (!is_polynomial(tape)) continue;
        ++polynomial;
        const RayResult r = testing::as_host([&] { return exact_first_root(tape, c.ray); });
        check(c, r, true);
        SCOPED_TRACE(c.label);
        if (c.expect == "miss" || c.expect == "nohit") {
            EXPECT_EQ(r.status, Status::Miss);
        } else {
            ASSERT_EQ(r.status, Status::Hit);
            EXPECT_LE(r.t_hi, std::nextafter(r.t_lo, std::numeric_limits<double>::infinity()));
        }
    }
    EXPECT_GE(polynomial, 6);  // quadric, touch, subnormal, cluster10
}

TEST_F(Stress, CertifiedAndBernsteinDecideEveryPolynomialCaseWithinFourUlps) {
    // The goal: no unknown on polynomial scenes, every hit at most 4 ulps wide — for the
    // certified solver and the Bernstein method, through their exact fallback.
    AnalyticOptions bernstein;
    bernstein.mode = AnalyticOptions::Mode::Bernstein;
    for (const Case& c : *cases_) {
        const expr::Tape& tape = tapes_->at(c.scene);
        if (!is_polynomial(tape)) continue;
        SCOPED_TRACE(c.label);
        for (const RayResult& r :
             {testing::as_host([&] { return certified_first_root(tape, c.ray); }),
              testing::as_host([&] { return analytic_first_root(tape, c.ray, bernstein); })}) {
            check(c, r, true);
            ASSERT_NE(r.status, Status::Unknown);
            if (r.status != Status::Hit) continue;
            // 4 ulps at the enclosure's magnitude: at most 4·ulp(max(|t_lo|, |t_hi|)) wide.
            const double scale = std::max(std::fabs(r.t_lo), std::fabs(r.t_hi));
            double four_ulps = scale;
            for (int i = 0; i < 4; ++i) four_ulps = std::nextafter(four_ulps, HUGE_VAL);
            EXPECT_LE(r.t_hi - r.t_lo, four_ulps - scale) << r.t_lo << " " << r.t_hi;
        }
    }
}

TEST_F(Stress, SmallBudgetsStayHonest) {
    CertifiedOptions o;
    o.budget = 8;
    for (const Case& c : *cases_) {
        const RayResult r =
            testing::as_host([&] { return certified_first_root(tapes_->at(c.scene), c.ray, o); });
        check(c, r, false);
        EXPECT_LE(r.evals.total(), o.budget + 16) << c.label;
    }
}

}  // namespace
}  // namespace certray::solvers
