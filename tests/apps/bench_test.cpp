// tests/apps/bench_test.cpp — the error-against-run-time study (apps/bench.h) on a tiny suite.
//
// On the unit sphere |p| − 1 with a handful of rays whose first roots mathematics gives (from
// (0, 0, −3) along +z the first root is t = 2; from (0.6, 0, −3) it is 3 − 0.8 = 2.2; from
// (0, 2, −3) there is none; from the centre along +x it is 1): the certified method's error is
// within its enclosure width and it has no wrong answer; a sphere tracer whose Lipschitz bound is
// halved (steps twice too long) is caught overshooting; the CSVs and the report are produced with
// their columns; a wrong method presented as certified makes run_bench fail loudly.
#include "apps/bench.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "expr/eval.h"

namespace certray::apps {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (!line.empty() && line.back() == ',') f.emplace_back();
    return f;
}

/// The rows of a CSV file as maps from the header's column names.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p,
                                                         std::vector<std::string>* header) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    *header = split(line);
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        const std::vector<std::string> f = split(line);
        std::map<std::string, std::string> row;
        for (std::size_t k = 0; k < header->size() && k < f.size(); ++k) row[(*header)[k]] = f[k];
        rows.push_back(row);
    }
    return rows;
}

/// Sphere tracing with a Lipschitz bound of 1/2 for |p| − 1 (whose true bound is 1): every step
/// is twice too long, so the tracer jumps over the near side of the sphere.
tracers::RayFunction broken_sphere(const expr::Tape& tape, const tracers::MethodOptions& o) {
    return [&tape, eps = o.epsilon](const Ray& r) {
        RayResult res;
        double t = r.tmin;
        for (int k = 0; k < 1000 && t <= r.tmax; ++k) {
            const std::array<double, 3> p{r.o[0] + t * r.d[0], r.o[1] + t * r.d[1],
                                          r.o[2] + t * r.d[2]};
            const double f = expr::eval(tape, p);
            ++res.evals.value;
            if (std::fabs(f) < eps) {
                res.status = Status::Hit;
                res.t = res.t_lo = res.t_hi = t;
                return res;
            }
            t += std::fabs(f) / 0.5;  // λ halved
        }
        res.status = Status::Miss;
        return res;
    };
}

class BenchTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("certray_bench_test_" +
                std::to_string(::testing::UnitTest::GetInstance()->current_test_info()->line()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        std::ofstream(dir_ / "sphere.expr") << "sqrt(x^2 + y^2 + z^2) - 1\n";
        std::ofstream(dir_ / "rays.csv") << "ox,oy,oz,dx,dy,dz,tmin,tmax\n"
                                            "0,0,-3,0,0,1,0,10\n"
                                            "0.6,0,-3,0,0,1,0,10\n"
                                            "0,2,-3,0,0,1,0,10\n"
                                            "0,0,0,1,0,0,0,10\n";
        opts_.out_dir = (dir_ / "out").string();
        opts_.scenes = {(dir_ / "sphere.expr").string()};
        opts_.rays = (dir_ / "rays.csv").string();
        opts_.stress = "none";
        opts_.methods = {"certified"};
        opts_.plots = false;
        opts_.peers = false;
        opts_.progress = 0;
        opts_.threads = 2;
        opts_.extra_methods = {{"broken-sphere", broken_sphere, false, 1e-9}};
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
    BenchOptions opts_;
};

TEST_F(BenchTest, ProgressLinesWhenStderrIsNotATerminal) {
    opts_.progress = -1;                   // the default: a bar on a terminal, lines elsewhere
    ::testing::internal::CaptureStderr();  // stderr becomes a file
    const int code = run_bench(opts_);
    const std::string err = ::testing::internal::GetCapturedStderr();
    ASSERT_EQ(code, 0) << err;
    // The last ray run prints its line however short the run: percentage, counts, rate, time left.
    EXPECT_NE(err.find("certray bench: 100% ("), std::string::npos) << err;
    EXPECT_NE(err.find(" ray runs, "), std::string::npos) << err;
    EXPECT_NE(err.find(" s left: "), std::string::npos) << err;
    EXPECT_EQ(err.find('\r'), std::string::npos) << err;
}

TEST_F(BenchTest, CertifiedIsExactAndBrokenTracerIsCaught) {
    ASSERT_EQ(run_bench(opts_), 0);
    std::vector<std::string> head;
    const auto rows = read_csv(fs::path(opts_.out_dir) / "measurements.csv", &head);
    const std::vector<std::string> want = {"suite",
                                           "method",
                                           "knob",
                                           "value",
                                           "certified",
                                           "scene",
                                           "ray",
                                           "case",
                                           "expect",
                                           "status",
                                           "t_lo",
                                           "t_hi",
                                           "t",
                                           "truth_lo",
                                           "truth_hi",
                                           "us",
                                           "evals_value",
                                           "evals_interval",
                                           "evals_gradient",
                                           "evals_total",
                                           "class",
                                           "error",
                                           "rel_error"};
    EXPECT_EQ(head, want);
    // 4 budgets of certified + the broken tracer, 4 rays each.
    ASSERT_EQ(rows.size(), 5u * 4u);
    const double roots[] = {2.0, 2.2, NAN, 1.0};
    int broken_wrong = 0, broken_over = 0, certified_hits = 0;
    for (const auto& r : rows) {
        const int ray = std::stoi(r.at("ray"));
        if (r.at("method") == "certified") {
            EXPECT_TRUE(r.at("class") == "correct" || r.at("class") == "unknown")
                << "ray " << ray << " budget " << r.at("value") << ": " << r.at("class");
            if (r.at("status") != "hit") continue;
            ++certified_hits;
            const double lo = std::stod(r.at("t_lo")), hi = std::stod(r.at("t_hi"));
            const double err = std::stod(r.at("error"));
            EXPECT_LE(err, hi - lo) << "ray " << ray;
            // A simple root: the enclosure is a few ulps wide around the mathematical root.
            EXPECT_LE(hi - lo, 8 * std::nextafter(roots[ray], 10.0) - 8 * roots[ray]);
            EXPECT_LE(lo, roots[ray] + 1e-15);
            EXPECT_GE(hi, roots[ray] - 1e-15);
        } else {
            ASSERT_EQ(r.at("method"), "broken-sphere");
            const std::string& c = r.at("class");
            if (c == "missed" || c == "false_hit" || c == "overshoot") ++broken_wrong;
            if (c == "overshoot") ++broken_over;
            if (ray == 0) {  // f = 2 at t = 0, one step of 4 lands on the far side: t = 4
                EXPECT_EQ(c, "overshoot");
                EXPECT_NEAR(std::stod(r.at("error")), 2.0, 1e-9);
            }
        }
    }
    EXPECT_GE(certified_hits, 3);  // budgets 1000 and 20000 prove all three roots
    EXPECT_GE(broken_over, 1);
    EXPECT_GE(broken_wrong, 2);

    const auto sum = read_csv(fs::path(opts_.out_dir) / "summary.csv", &head);
    const std::vector<std::string> want_sum = {
        "suite",       "method",         "knob",           "value",       "certified",
        "scene",       "rays",           "setup_ms",       "mean_us",     "median_us",
        "evals_value", "evals_interval", "evals_gradient", "evals_total", "correct",
        "missed",      "false_hit",      "overshoot",      "unknown",     "ref_unknown",
        "max_error",   "median_error"};
    EXPECT_EQ(head, want_sum);
    EXPECT_EQ(sum.size(), 5u);
    const std::string md = slurp(fs::path(opts_.out_dir) / "report.md");
    EXPECT_NE(md.find("`certified`: **zero wrong answers**"), std::string::npos) << md;
    EXPECT_NE(md.find("## Which method wins where"), std::string::npos);
    EXPECT_NE(md.find("broken-sphere"), std::string::npos);
    EXPECT_EQ(md.find("WRONG ANSWERS"), std::string::npos);
    // The report names what it covers.
    EXPECT_NE(md.find("Covers gallery: 1 scene (sphere.expr), 4 rays; stress suite: not run "
                      "(--stress none)."),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("(gallery only, every setting)"), std::string::npos);
    EXPECT_EQ(md.find("gallery and stress suite"), std::string::npos);
    for (const auto& e : fs::directory_iterator(opts_.out_dir)) {
        EXPECT_NE(e.path().extension(), ".tmp") << e.path();
    }
}

TEST_F(BenchTest, WrongCertifiedMethodIsReportedLoudly) {
    opts_.methods = {};
    opts_.extra_methods = {{"broken-certified", broken_sphere, true, 1e-9}};
    opts_.report = (dir_ / "copy.md").string();
    EXPECT_EQ(run_bench(opts_), 3);
    const std::string md = slurp(dir_ / "copy.md");
    EXPECT_NE(md.find("WRONG ANSWERS"), std::string::npos) << md;
    EXPECT_EQ(md, slurp(fs::path(opts_.out_dir) / "report.md"));
}

TEST_F(BenchTest, StressTableHasAColumnForEveryMethodInTheTotals) {
    // --quick runs the ends of march's step sweep (0.003, 0.1), not its default 0.01: march
    // still gets a column, named by the setting shown.
    std::ofstream(dir_ / "cases.csv")
        << "case,scene,ox,oy,oz,dx,dy,dz,tmin,tmax,expect,root_lo,root_hi,note\n"
           "head-on,sphere.expr,0,0,-3,0,0,1,0,10,hit,0x1p+1,0x1p+1,\n"
           "off-axis,sphere.expr,0.6,0,-3,0,0,1,0,10,hit,0x1.1999999999999p+1,"
           "0x1.199999999999ap+1,\n";
    opts_.stress = (dir_ / "cases.csv").string();
    opts_.quick = true;
    opts_.methods = {"certified", "march"};
    opts_.extra_methods = {};
    ASSERT_EQ(run_bench(opts_), 0);
    const std::string md = slurp(fs::path(opts_.out_dir) / "report.md");
    EXPECT_NE(md.find("Covers gallery: 1 scene (sphere.expr), 4 rays; stress suite: 2 cases in 1 "
                      "scene."),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("(gallery and stress suite, every setting)"), std::string::npos);
    const auto head = md.find("| case | expect");
    ASSERT_NE(head, std::string::npos) << md;
    const std::string header = md.substr(head, md.find('\n', head) - head);
    const auto totals = md.find("Stress totals");
    ASSERT_NE(totals, std::string::npos);
    std::istringstream rows(md.substr(md.find("| --- |", totals)));
    int methods = 0;
    for (std::string line; std::getline(rows, line) && line.rfind("| ", 0) == 0;) {
        if (line.rfind("| ---", 0) == 0) continue;
        const std::string name = line.substr(2, line.find(" |") - 2);
        EXPECT_NE(header.find("| " + name + " "), std::string::npos) << name << ": " << header;
        ++methods;
    }
    EXPECT_EQ(methods, 2);
    EXPECT_NE(header.find("| march step="), std::string::npos) << header;
    EXPECT_NE(header.find("| certified |"), std::string::npos) << header;
}

TEST(BenchClassify, ClassesAgainstTheTruth) {
    const Truth hit{Truth::Hit, 2.0, 2.0};
    const Truth miss{Truth::Miss, 0, 0};
    auto res = [](Status s, double lo, double hi) {
        RayResult r;
        r.status = s;
        r.t_lo = lo;
        r.t_hi = hi;
        r.t = 0.5 * (lo + hi);
        return r;
    };
    // Certified: judged by the enclosure, no tolerance.
    EXPECT_EQ(classify(res(Status::Hit, 1.9, 2.1), hit, true, 0), BenchClass::Correct);
    EXPECT_EQ(classify(res(Status::Hit, 1.9, 1.99), hit, true, 0.5), BenchClass::FalseHit);
    EXPECT_EQ(classify(res(Status::Hit, 2.01, 2.1), hit, true, 0.5), BenchClass::Overshoot);
    EXPECT_EQ(classify(res(Status::Miss, NAN, NAN), hit, true, 0), BenchClass::Missed);
    EXPECT_EQ(classify(res(Status::Unknown, 1.0, 3.0), hit, true, 0), BenchClass::Unknown);
    EXPECT_EQ(classify(res(Status::Unknown, 2.5, 3.0), hit, true, 0), BenchClass::Overshoot);
    EXPECT_EQ(classify(res(Status::Hit, 1, 1), miss, true, 0), BenchClass::FalseHit);
    EXPECT_EQ(classify(res(Status::Miss, NAN, NAN), miss, true, 0), BenchClass::Correct);
    // Approximate: judged by t within the tolerance.
    EXPECT_EQ(classify(res(Status::Hit, 2.001, 2.001), hit, false, 0.01), BenchClass::Correct);
    EXPECT_EQ(classify(res(Status::Hit, 2.1, 2.1), hit, false, 0.01), BenchClass::Overshoot);
    EXPECT_EQ(classify(res(Status::Hit, 1.9, 1.9), hit, false, 0.01), BenchClass::FalseHit);
    EXPECT_DOUBLE_EQ(bench_error(res(Status::Hit, 2.5, 2.5), hit), 0.5);
    EXPECT_DOUBLE_EQ(bench_tolerance(1e-6, 1e6), 1e-3);
    EXPECT_DOUBLE_EQ(bench_tolerance(1e-6, 0.5), 1e-5);
    // Near misses: a hit is wrong, miss and unknown are not.
    const Truth nohit{Truth::NoHit, 0, 0};
    EXPECT_EQ(classify(res(Status::Hit, 3, 3), nohit, false, 0.1), BenchClass::FalseHit);
    EXPECT_EQ(classify(res(Status::Unknown, 3, 3), nohit, true, 0), BenchClass::Unknown);
}

}  // namespace
}  // namespace certray::apps
