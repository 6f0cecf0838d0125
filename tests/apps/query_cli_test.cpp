// tests/apps/query_cli_test.cpp — `certray query` end to end: runs the built binary on a unit
// sphere and checks HITS.csv, STATS.json, the exit codes and that failed runs leave no file behind.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_fixture.h"

namespace {

namespace fs = std::filesystem;

struct HitRow {
    std::string status;
    double t_lo, t_hi, t;
};

double parse_double(const std::string& s) {
    if (s == "nan") return std::nan("");
    double v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    EXPECT_TRUE(ec == std::errc() && ptr == s.data() + s.size()) << "bad number '" << s << "'";
    return v;
}

using certray::testing::slurp;

class QueryCli : public certray::testing::CliFixture {
  protected:
    void SetUp() override {
        CliFixture::SetUp();
        write("sphere.expr", "# the unit sphere\nx^2 + y^2 + z^2 - 1\n");
    }

    std::vector<HitRow> read_hits(const std::string& name) const {
        std::istringstream in(slurp(path(name)));
        std::string line;
        std::getline(in, line);
        EXPECT_EQ(line, "status,t_lo,t_hi,t");
        std::vector<HitRow> rows;
        while (std::getline(in, line)) {
            std::vector<std::string> f;
            std::stringstream ls(line);
            for (std::string cell; std::getline(ls, cell, ',');) f.push_back(cell);
            EXPECT_EQ(f.size(), 4u) << line;
            if (f.size() != 4) continue;
            rows.push_back({f[0], parse_double(f[1]), parse_double(f[2]), parse_double(f[3])});
        }
        return rows;
    }

    /// No file other than the inputs (sphere.expr, the rays, stdout.txt, stderr.txt) is left in the
    /// directory.
    std::vector<std::string> outputs_left(const std::string& rays) const {
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(dir_)) {
            const std::string n = e.path().filename().string();
            if (n != "sphere.expr" && n != rays && n != "stderr.txt" && n != "stdout.txt") {
                left.push_back(n);
            }
        }
        return left;
    }
};

constexpr const char* kHeader = "ox,oy,oz,dx,dy,dz,tmin,tmax\n";

TEST_F(QueryCli, HitsTheSphereAndMissesBesideIt) {
    // Rays from (x, 0, -3) along +z cross the sphere first at t = 3 - sqrt(1 - x²).
    std::string rays = kHeader;
    const std::vector<double> xs = {0.0, 0.25, -0.5, 0.75, 0.9};
    for (double x : xs) rays += std::to_string(x) + ",0,-3,0,0,1,0,10\n";
    rays += "0,5,0,1,0,0,0,10\n";    // along +x at y = 5: misses
    rays += "0,0,-3,0,0,1,0,1.5\n";  // stops short of the sphere: misses
    rays += "0,0,-3,0,0,-1,0,10\n";  // away from the sphere: misses
    write("rays.csv", rays);
    ASSERT_EQ(run("query sphere.expr --rays rays.csv --method certified --out hits.csv"), 0)
        << err_;
    const auto rows = read_hits("hits.csv");
    ASSERT_EQ(rows.size(), xs.size() + 3);
    for (std::size_t i = 0; i < xs.size(); ++i) {
        EXPECT_EQ(rows[i].status, "hit") << "ray " << i;
        const double root = 3 - std::sqrt(1 - xs[i] * xs[i]);
        EXPECT_LE(rows[i].t_lo, root + 1e-12) << "ray " << i;
        EXPECT_GE(rows[i].t_hi, root - 1e-12) << "ray " << i;
        EXPECT_LE(rows[i].t_lo, rows[i].t);
        EXPECT_LE(rows[i].t, rows[i].t_hi);
        EXPECT_LT(rows[i].t_hi - rows[i].t_lo, 1e-6);
    }
    EXPECT_LE(rows[0].t_lo, 2.0);
    EXPECT_GE(rows[0].t_hi, 2.0);
    for (std::size_t i = xs.size(); i < rows.size(); ++i) {
        EXPECT_EQ(rows[i].status, "miss") << "ray " << i;
        EXPECT_TRUE(std::isnan(rows[i].t_lo) && std::isnan(rows[i].t_hi) && std::isnan(rows[i].t));
    }
    EXPECT_EQ(outputs_left("rays.csv"), std::vector<std::string>{"hits.csv"});
}

TEST_F(QueryCli, StatsJsonCountsEveryRay) {
    std::string rays = kHeader;
    constexpr int kRays = 300;
    for (int i = 0; i < kRays; ++i) {
        rays += std::to_string(-1.5 + 3.0 * i / kRays) + ",0.1,-3,0,0,1,0,10\n";
    }
    write("rays.csv", rays);
    ASSERT_EQ(run("query sphere.expr --rays rays.csv --method certified --out hits.csv "
                  "--stats stats.json --threads 3 --budget 5000"),
              0)
        << err_;
    const nlohmann::json j = nlohmann::json::parse(slurp(path("stats.json")));
    EXPECT_EQ(j.at("method"), "certified");
    EXPECT_EQ(j.at("rays"), kRays);
    EXPECT_EQ(j.at("threads"), 3);
    EXPECT_GE(j.at("seconds").get<double>(), 0.0);
    const auto& s = j.at("status");
    EXPECT_EQ(s.at("hit").get<int>() + s.at("miss").get<int>() + s.at("unknown").get<int>(), kRays);
    EXPECT_GT(s.at("hit").get<int>(), 0);
    EXPECT_GT(s.at("miss").get<int>(), 0);
    const auto& e = j.at("evaluations");
    EXPECT_EQ(e.at("total").get<std::uint64_t>(), e.at("value").get<std::uint64_t>() +
                                                      e.at("interval").get<std::uint64_t>() +
                                                      e.at("gradient").get<std::uint64_t>());
    EXPECT_GT(e.at("total").get<std::uint64_t>(), 0u);
    const auto& per_ray = j.at("evaluations_per_ray");
    EXPECT_LE(per_ray.at("max").get<std::uint64_t>(), 5000u);
    EXPECT_NEAR(per_ray.at("mean").get<double>() * kRays, e.at("total").get<double>(), 1e-6);

    // The answers do not depend on the number of threads.
    ASSERT_EQ(run("query sphere.expr --rays rays.csv --method certified --out one.csv "
                  "--threads 1 --budget 5000"),
              0)
        << err_;
    EXPECT_EQ(slurp(path("one.csv")), slurp(path("hits.csv")));
}

TEST_F(QueryCli, ApproximateMethodsMarkTheirAnswersNotProven) {
    write("rays.csv", std::string(kHeader) + "0,0,-3,0,0,1,0,10\n0,0,-3,0,0,-1,0,10\n");
    ASSERT_EQ(run("query sphere.expr --rays rays.csv --method sphere --out hits.csv"), 0) << err_;
    std::istringstream in(slurp(path("hits.csv")));
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "status,t_lo,t_hi,t,proven");
    // Sphere tracing from (0, 0, -3) along +z stops near the sphere at t = 2, along -z misses.
    ASSERT_TRUE(std::getline(in, line));
    ASSERT_EQ(line.substr(0, 4), "hit,") << line;
    EXPECT_EQ(line.substr(line.size() - 2), ",0") << line;
    const auto first = line.find(',', 4);
    EXPECT_NEAR(parse_double(line.substr(4, first - 4)), 2.0, 1e-6) << line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "miss,nan,nan,nan,0");
    EXPECT_FALSE(std::getline(in, line));
}

TEST_F(QueryCli, ProgressLinesWhenStderrIsAFile) {
    std::string rays = kHeader;
    for (int i = 0; i < 50; ++i) rays += "0,0,-3,0,0,1,0,10\n";
    write("rays.csv", rays);
    // Shorter than the threshold (2 s): nothing on stderr.
    ASSERT_EQ(run("query sphere.expr --rays rays.csv --method certified --out hits.csv"), 0);
    EXPECT_TRUE(err_.empty()) << err_;
    // Threshold 0: lines, not a bar, ending with every ray done.
    setenv("CERTRAY_PROGRESS_SECONDS", "0", 1);
    const int code = run("query sphere.expr --rays rays.csv --method certified --out hits.csv");
    const std::string with_lines = err_;
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method certified --out hits.csv --quiet"),
              0);
    const std::string quiet = err_;
    unsetenv("CERTRAY_PROGRESS_SECONDS");
    ASSERT_EQ(code, 0) << with_lines;
    EXPECT_NE(with_lines.find("certray query: 50 / 50 rays (100%)"), std::string::npos)
        << with_lines;
    EXPECT_EQ(with_lines.find('\r'), std::string::npos) << with_lines;
    EXPECT_TRUE(quiet.empty()) << quiet;
}

TEST_F(QueryCli, EmptyRayFileGivesHeaderOnly) {
    write("rays.csv", kHeader);
    ASSERT_EQ(run("query sphere.expr --rays rays.csv --method certified --out hits.csv "
                  "--stats stats.json"),
              0)
        << err_;
    EXPECT_EQ(slurp(path("hits.csv")), "status,t_lo,t_hi,t\n");
    EXPECT_EQ(nlohmann::json::parse(slurp(path("stats.json"))).at("rays"), 0);
}

TEST_F(QueryCli, MalformedRaysFailWithTheLineAndLeaveNoFile) {
    write("rays.csv", std::string(kHeader) + "0,0,-3,0,0,1,0,10\n0,0,-3,0,0,1,5,1\n");
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method certified --out hits.csv "
                  "--stats stats.json"),
              1);
    EXPECT_NE(err_.find("rays.csv:3:14: field 'tmin'"), std::string::npos) << err_;
    EXPECT_TRUE(outputs_left("rays.csv").empty());

    write("rays.csv", std::string(kHeader) + "0,0,-3,0,0,1,0\n");
    EXPECT_NE(run("query sphere.expr --rays rays.csv --method certified --out hits.csv"), 0);
    EXPECT_NE(err_.find("rays.csv:2:"), std::string::npos) << err_;
    EXPECT_TRUE(outputs_left("rays.csv").empty());
}

TEST_F(QueryCli, UnknownMethodExitsTwoAndListsTheMethods) {
    write("rays.csv", std::string(kHeader) + "0,0,-3,0,0,1,0,10\n");
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method bogus --out hits.csv"), 2);
    EXPECT_NE(err_.find("unknown method 'bogus'"), std::string::npos) << err_;
    EXPECT_NE(err_.find("certified"), std::string::npos) << err_;
    EXPECT_TRUE(outputs_left("rays.csv").empty());
}

TEST_F(QueryCli, MissingInputsAndUnwritableOutputsFail) {  // exit 3: I/O errors
    write("rays.csv", std::string(kHeader) + "0,0,-3,0,0,1,0,10\n");
    EXPECT_EQ(run("query missing.expr --rays rays.csv --method certified --out hits.csv"), 3);
    EXPECT_NE(err_.find("missing.expr"), std::string::npos) << err_;
    EXPECT_EQ(run("query sphere.expr --rays missing.csv --method certified --out hits.csv"), 3);
    EXPECT_NE(err_.find("missing.csv"), std::string::npos) << err_;
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method certified --out no/such/hits.csv"),
              3);
    EXPECT_NE(err_.find("no/such/hits.csv"), std::string::npos) << err_;
    // The stats file cannot be written: the hits file must not be left behind either.
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method certified --out hits.csv "
                  "--stats no/such/stats.json"),
              3);
    EXPECT_TRUE(outputs_left("rays.csv").empty());
    // The output path is a directory: the rename fails and the temporary file is removed.
    fs::create_directory(path("outdir"));
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method certified --out outdir"), 3);
    EXPECT_EQ(outputs_left("rays.csv"), std::vector<std::string>{"outdir"});
}

}  // namespace
