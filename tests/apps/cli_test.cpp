// tests/apps/cli_test.cpp — the `certray` command line as a whole: each exit code of
// apps/cli_errors.h with its message, --version, an unknown command, and one --bounds syntax
// (LO HI or LO,HI) in inspect, query and render; and apps::run_guarded's mapping of exceptions to
// exit codes, the internal error (4) included, which no input reaches.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "apps/cli_errors.h"
#include "expr/input_error.h"
#include "tests/support/cli_fixture.h"

namespace {

class Cli : public certray::testing::CliFixture {
  protected:
    void SetUp() override {
        CliFixture::SetUp();
        write("sphere.expr", "x^2 + y^2 + z^2 - 1\n");
        write("wave.expr", "sin(x) + y + z\n");
        write("rays.csv", "ox,oy,oz,dx,dy,dz,tmin,tmax\n0,0,-3,0,0,1,0,10\n");
    }
    /// `certray query sphere.expr …` with the required options and `extra`.
    int query(const std::string& extra) {
        return run("query sphere.expr --rays rays.csv --method certified --out hits.csv " + extra);
    }
    bool err_has(const std::string& text) const { return err_.find(text) != std::string::npos; }
};

TEST_F(Cli, VersionAndHelpExitZeroOnStdout) {
    ASSERT_EQ(run("--version"), 0) << err_;
    EXPECT_EQ(out_.rfind("certray ", 0), 0u) << out_;
    const std::string v = out_.substr(8, out_.find_first_of("\r\n") - 8);
    EXPECT_EQ(std::count(v.begin(), v.end(), '.'), 2) << out_;  // X.Y.Z
    EXPECT_TRUE(err_.empty()) << err_;
    for (const char* args : {"--help", "query --help", "render --help", "inspect --help"}) {
        ASSERT_EQ(run(args), 0) << args;
        EXPECT_NE(out_.find("--help"), std::string::npos) << args;
        EXPECT_TRUE(err_.empty()) << args << ": " << err_;
    }
    ASSERT_EQ(run("--help"), 0);
    EXPECT_NE(out_.find("--version"), std::string::npos) << out_;
}

TEST_F(Cli, ExitOkOnSuccess) {
    EXPECT_EQ(query(""), 0) << err_;
    EXPECT_EQ(run("methods"), 0) << err_;
    EXPECT_EQ(run("inspect sphere.expr --levels 1"), 0) << err_;
}

TEST_F(Cli, UnknownOrMissingCommandIsUsage) {
    EXPECT_EQ(run("frob"), 2);
    EXPECT_EQ(err_,
              "certray: unknown command 'frob'; commands: inspect, query, methods, render, "
              "bench\n");
    EXPECT_EQ(run("--frob"), 2);
    EXPECT_TRUE(
        err_has("certray: unknown option '--frob'; options: --help, --version; commands: "
                "inspect, query"))
        << err_;
    EXPECT_EQ(run(""), 2);
    EXPECT_TRUE(err_has("certray: a command is required")) << err_;
}

TEST_F(Cli, ParseErrorsAreUsageWithReadableMessages) {
    EXPECT_EQ(query("--threads -1"), 2);
    EXPECT_TRUE(err_has("certray query: --threads: expected a non-negative integer, got '-1'"))
        << err_;
    EXPECT_EQ(query("--budget abc"), 2);
    EXPECT_TRUE(err_has("certray query: --budget: expected a positive integer, got 'abc'")) << err_;
    EXPECT_EQ(query("--budget 0"), 2);
    EXPECT_TRUE(err_has("--budget: expected a positive integer, got '0'")) << err_;
    EXPECT_EQ(query("--kappa 2"), 2);
    EXPECT_TRUE(err_has("--kappa: expected a number from 0 to 1, got '2'")) << err_;
    EXPECT_EQ(query("--epsilon -1"), 2);
    EXPECT_TRUE(err_has("--epsilon: expected a positive number, got '-1'")) << err_;
    EXPECT_EQ(run("inspect sphere.expr --levels 9"), 2);
    EXPECT_TRUE(err_has("certray inspect: --levels: expected an integer from 0 to 8, got '9'"))
        << err_;
    EXPECT_EQ(run("render sphere.expr -o x.png --threads many"), 2);
    EXPECT_TRUE(err_has("certray render: --threads: expected a non-negative integer, got 'many'"))
        << err_;
    EXPECT_EQ(query("--frob"), 2);
    EXPECT_TRUE(err_has("certray query: unknown option '--frob'")) << err_;
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method certified"), 2);
    EXPECT_TRUE(err_has("certray query: --out is required")) << err_;
    EXPECT_EQ(run("render"), 2);
    EXPECT_TRUE(err_has("certray render: ")) << err_;
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method nosuch --out hits.csv"), 2);
    EXPECT_TRUE(err_has("unknown method 'nosuch'")) << err_;
    EXPECT_EQ(err_.find("Run with --help"), std::string::npos) << err_;  // one line of ours
}

TEST_F(Cli, InputErrorsExitOne) {
    write("bad.expr", "x + * y\n");
    EXPECT_EQ(run("inspect bad.expr"), 1);
    EXPECT_TRUE(err_has("certray: bad.expr:1:")) << err_;
    write("bad.csv", "ox,oy\n");
    EXPECT_EQ(run("query sphere.expr --rays bad.csv --method certified --out hits.csv"), 1);
    EXPECT_TRUE(err_has("bad.csv:1:")) << err_;
    // A method that does not apply to the scene.
    EXPECT_EQ(run("query wave.expr --rays rays.csv --method analytic --out hits.csv"), 1);
    EXPECT_TRUE(err_has("does not apply")) << err_;
    EXPECT_FALSE(std::filesystem::exists(path("hits.csv")));
}

TEST_F(Cli, IoErrorsExitThree) {
    EXPECT_EQ(run("inspect missing.expr"), 3);
    EXPECT_TRUE(err_has("missing.expr")) << err_;
    EXPECT_EQ(run("query sphere.expr --rays missing.csv --method certified --out hits.csv"), 3);
    EXPECT_TRUE(err_has("missing.csv")) << err_;
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method certified --out no_dir/hits.csv"), 3);
    EXPECT_TRUE(err_has("cannot write")) << err_;
    EXPECT_EQ(run("render sphere.expr -o no_dir/x.png --size 8x8"), 3);
    EXPECT_TRUE(err_has("cannot write")) << err_;
}

TEST_F(Cli, KnobsTheMethodDoesNotReadAreUsageErrors) {
    // The registry (tracers/methods.h): certified reads only --budget; hermite only --samples.
    EXPECT_EQ(query("--bounds -1 1"), 2);
    EXPECT_TRUE(err_has("method 'certified' does not read 'bounds'; its knobs: budget, tighten"))
        << err_;
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method hermite --out h.csv --budget 5"), 2);
    EXPECT_TRUE(err_has("method 'hermite' does not read 'budget'; its knobs: samples")) << err_;
    EXPECT_EQ(run("query sphere.expr --rays rays.csv --method hermite --out h.csv --samples 8"), 0)
        << err_;
    EXPECT_EQ(query("--depth 3"), 2);
    EXPECT_TRUE(err_has("does not read 'depth'")) << err_;
}

TEST_F(Cli, BoundsSyntaxIsTheSameEverywhere) {
    for (const char* b : {"-1 1", "-1,1", "=-1,1"}) {
        const std::string opt = std::string(b[0] == '=' ? "--bounds" : "--bounds ") + b;
        EXPECT_EQ(run("inspect sphere.expr --levels 1 " + opt), 0) << opt << ": " << err_;
        EXPECT_NE(out_.find("over [-1, 1]^3"), std::string::npos) << opt << ": " << out_;
        EXPECT_EQ(
            run("query sphere.expr --rays rays.csv --method certified-octree --out h.csv " + opt),
            0)
            << opt << ": " << err_;
        EXPECT_EQ(run("render sphere.expr -o x.png --size 8x8 " + opt), 0) << opt << ": " << err_;
    }
    for (const char* cmd : {"inspect sphere.expr", "render sphere.expr -o x.png",
                            "query sphere.expr --rays rays.csv --method certified --out h.csv"}) {
        const std::string c = cmd;
        const std::string who = "certray " + c.substr(0, c.find(' ')) + ": --bounds: ";
        EXPECT_EQ(run(c + " --bounds 1"), 2) << cmd;
        EXPECT_TRUE(err_has(who + "expected two numbers, as 'LO HI' or 'LO,HI', got '1'")) << err_;
        EXPECT_EQ(run(c + " --bounds -1,x"), 2) << cmd;
        EXPECT_TRUE(err_has(who + "expected two numbers")) << err_;
        EXPECT_EQ(run(c + " --bounds 1,-1"), 2) << cmd;
        EXPECT_TRUE(err_has(who + "expected two finite numbers LO < HI")) << err_;
        ASSERT_EQ(run(c.substr(0, c.find(' ')) + " --help"), 0);
        EXPECT_NE(out_.find("--bounds LO HI "), std::string::npos) << out_;
        EXPECT_EQ(out_.find("[FLOAT,FLOAT]"), std::string::npos) << out_;
    }
}

TEST(RunGuarded, MapsExceptionsToExitCodes) {
    using certray::apps::run_guarded;
    EXPECT_EQ(run_guarded([] { return 0; }), 0);
    EXPECT_EQ(run_guarded([] { return 2; }), 2);
    EXPECT_EQ(run_guarded([]() -> int { throw certray::InputError("f.expr", 3, 4, "bad"); }), 1);
    EXPECT_EQ(run_guarded([]() -> int { throw std::invalid_argument("does not apply"); }), 1);
    EXPECT_EQ(
        run_guarded([]() -> int { throw certray::InputError("f.expr", 0, 0, "cannot open file"); }),
        3);
    EXPECT_EQ(run_guarded([]() -> int { throw std::runtime_error("cannot write 'x': full"); }), 3);
    EXPECT_EQ(run_guarded([]() -> int { throw std::runtime_error("something else"); }), 4);
    EXPECT_EQ(run_guarded([]() -> int { throw std::logic_error("a bug"); }), 4);
    EXPECT_EQ(run_guarded([]() -> int { throw 42; }), 4);
}

TEST_F(Cli, InspectDefaultBoundsMatchRender) {
    write("disk.expr", "x^2 + y^2 - 0.5\n");
    ASSERT_EQ(run("inspect disk.expr --levels 1"), 0) << err_;
    EXPECT_NE(out_.find("2D over [-1, 1]^2"), std::string::npos) << out_;
    ASSERT_EQ(run("inspect sphere.expr --levels 1"), 0) << err_;
    EXPECT_NE(out_.find("3D over [-2, 2]^3"), std::string::npos) << out_;
    // A file's own bounds, as render frames it: a .vm's view (Fidget's [-1, 1]^3 when its header
    // says nothing), a CSG tree's aabb per axis; --bounds overrides them.
    write("ball.vm",
          "_0 var-x\n_1 var-y\n_2 var-z\n_3 square _0\n_4 square _1\n_5 square _2\n"
          "_6 add _3 _4\n_7 add _6 _5\n_8 const 0.25\n_9 sub _7 _8\n");
    ASSERT_EQ(run("inspect ball.vm --levels 1"), 0) << err_;
    EXPECT_NE(out_.find("3D over [-1, 1]^3 (the file's bounds)"), std::string::npos) << out_;
    // f = x² + y² + z² − 1/4 over [-1, 1]^3: [−0.25, 2.75].
    EXPECT_NE(out_.find("f over the bounds: [-0.25, 2.75]"), std::string::npos) << out_;
    write("box.json", R"({"aabb_min": [-1, -1, -1.5], "aabb_max": [1, 1, 1.5],
        "nodeType": "primitive", "primitiveType": "sphere", "radius": 0.5, "round_x": 0.0,
        "round_y": 0.0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]})");
    ASSERT_EQ(run("inspect box.json --levels 1"), 0) << err_;
    EXPECT_NE(out_.find("3D over [-1, 1] x [-1, 1] x [-1.5, 1.5] (the file's bounds)"),
              std::string::npos)
        << out_;
    ASSERT_EQ(run("inspect ball.vm --levels 1 --bounds -2 2"), 0) << err_;
    EXPECT_NE(out_.find("3D over [-2, 2]^3\n"), std::string::npos) << out_;
}

}  // namespace
