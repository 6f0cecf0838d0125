// tests/expr/vm_import_test.cpp — the Fidget .vm importer: the real models (op counts, values
// against closed-form formulas and against an independent line-by-line interpreter) and every
// error path with its location.
#include "expr/vm_import.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "expr/input_error.h"
#include "expr/parser.h"
#include "tests/support/graph_eval.h"

namespace certray::expr {
namespace {

using ::testing::HasSubstr;

const std::filesystem::path kModels = std::filesystem::path(CERTRAY_TEST_DATA) / "models";

std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

double eval(const Graph& g, double x, double y, double z) {
    return testing::eval_graph(g, x, y, z);
}

// An independent route: interpret the .vm text line by line with a map from id to value, without
// the Graph (no deduplication, no simplification).
double interpret_vm(const std::string& text, double x, double y, double z) {
    std::unordered_map<std::string, double> v;
    std::istringstream in(text);
    std::string line;
    double last = 0.0;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string id, op, a, b;
        if (!(ls >> id) || id[0] == '#') continue;
        ls >> op >> a >> b;
        double r = 0.0;
        if (op == "var-x")
            r = x;
        else if (op == "var-y")
            r = y;
        else if (op == "var-z")
            r = z;
        else if (op == "const")
            r = std::stod(a);
        else if (op == "neg")
            r = -v.at(a);
        else if (op == "abs")
            r = std::fabs(v.at(a));
        else if (op == "sqrt")
            r = std::sqrt(v.at(a));
        else if (op == "square")
            r = v.at(a) * v.at(a);
        else if (op == "exp")
            r = std::exp(v.at(a));
        else if (op == "ln")
            r = std::log(v.at(a));
        else if (op == "sin")
            r = std::sin(v.at(a));
        else if (op == "cos")
            r = std::cos(v.at(a));
        else if (op == "add")
            r = v.at(a) + v.at(b);
        else if (op == "sub")
            r = v.at(a) - v.at(b);
        else if (op == "mul")
            r = v.at(a) * v.at(b);
        else if (op == "div")
            r = v.at(a) / v.at(b);
        else if (op == "min")
            r = std::fmin(v.at(a), v.at(b));
        else if (op == "max")
            r = std::fmax(v.at(a), v.at(b));
        else
            ADD_FAILURE() << "test interpreter: unknown op " << op;
        v[id] = r;
        last = r;
    }
    return last;
}

int count_instructions(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string id;
        if (ls >> id && id[0] != '#') ++n;
    }
    return n;
}

std::string error_of(const std::string& text) {
    try {
        import_vm(text, "t.vm");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(VmImport, ProsperoHasItsPublishedSize) {
    const std::string text = slurp(kModels / "prospero.vm");
    EXPECT_EQ(count_instructions(text), 7866);  // the README: 7,866 SSA ops
    const Graph g = import_vm(text, "prospero.vm");
    EXPECT_LE(g.size(), 7866u);
    EXPECT_LE(g.topological_order().size(), g.size());
    EXPECT_GT(g.topological_order().size(), 1000u);
    EXPECT_TRUE(g.uses_var(0));
    EXPECT_TRUE(g.uses_var(1));
    EXPECT_FALSE(g.uses_var(2));  // a 2D model
}

TEST(VmImport, EveryModelMatchesAnIndependentInterpreter) {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    int models = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(kModels)) {
        if (entry.path().extension() != ".vm") continue;
        SCOPED_TRACE(entry.path().string());
        ++models;
        const std::string text = slurp(entry.path());
        const Graph g = import_vm_file(entry.path());
        EXPECT_LE(g.size(), static_cast<std::size_t>(count_instructions(text)));
        for (int k = 0; k < 50; ++k) {
            const double x = u(rng), y = u(rng), z = u(rng);
            const double want = interpret_vm(text, x, y, z);
            const double got = eval(g, x, y, z);
            if (std::isnan(want)) {
                EXPECT_TRUE(std::isnan(got));
            } else {
                EXPECT_EQ(got, want) << "at " << x << ", " << y << ", " << z;
            }
        }
    }
    EXPECT_EQ(models, 11);
}

struct ClosedForm {
    const char* file;
    double (*f)(double, double, double);
};

double barth(double x, double y, double z) {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;  // the golden ratio
    const double p2 = p * p;
    const double x2 = x * x, y2 = y * y, z2 = z * z;
    const double s = x2 + y2 + z2 - 1.0;
    return 4.0 * (p2 * x2 - y2) * (p2 * y2 - z2) * (p2 * z2 - x2) - (1.0 + 2.0 * p) * s * s;
}
double tanglecube(double x, double y, double z) {
    return std::pow(x, 4) - 5 * x * x + std::pow(y, 4) - 5 * y * y + std::pow(z, 4) - 5 * z * z +
           10;
}
double tangle_knoll(double x, double y, double z) { return tanglecube(x, y, z) + 1.8; }
double steiner(double x, double y, double z) {
    return x * x * y * y + y * y * z * z + z * z * x * x - x * y * z;
}
double mitchell(double x, double y, double z) {
    const double x2 = x * x, r = y * y + z * z;
    return 4 * (x2 * x2 + r * r) + 17 * x2 * r - 20 * (x2 + r) + 17;
}
double chebyshev6(double t) { return 32 * std::pow(t, 6) - 48 * std::pow(t, 4) + 18 * t * t - 1; }
double chmutov(double x, double y, double z) {
    return chebyshev6(x) + chebyshev6(y) + chebyshev6(z);
}
double clebsch(double x, double y, double z) {
    const double x2 = x * x, y2 = y * y, z2 = z * z;
    return 81 * (x2 * x + y2 * y + z2 * z) -
           189 * (x2 * y + x2 * z + y2 * x + y2 * z + z2 * x + z2 * y) + 54 * x * y * z +
           126 * (x * y + x * z + y * z) - 9 * (x2 + y2 + z2) - 9 * (x + y + z) + 1;
}
double quarter(double x, double y, double) {
    return std::fmax(std::fmax(x, y), x * x + y * y - 0.5);
}

TEST(VmImport, ModelsMatchTheirClosedFormFormulas) {
    const ClosedForm forms[] = {
        {"algebraic/barth_sextic.vm", barth},        {"tanglecube.vm", tanglecube},
        {"algebraic/tangle_knoll.vm", tangle_knoll}, {"algebraic/steiner_roman.vm", steiner},
        {"algebraic/mitchell.vm", mitchell},         {"algebraic/chmutov6.vm", chmutov},
        {"algebraic/clebsch_cubic.vm", clebsch},     {"quarter.vm", quarter},
    };
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (const ClosedForm& form : forms) {
        SCOPED_TRACE(form.file);
        const Graph g = import_vm_file(kModels / form.file);
        for (int k = 0; k < 100; ++k) {
            const double x = u(rng), y = u(rng), z = u(rng);
            const double want = form.f(x, y, z);
            EXPECT_NEAR(eval(g, x, y, z), want, 1e-9 * (1.0 + std::fabs(want)))
                << "at " << x << ", " << y << ", " << z;
        }
    }
    // A point on the Barth sextic's real surface: the origin gives −(1 + 2φ)·1 = −(2 + √5).
    const Graph b = import_vm_file(kModels / "algebraic/barth_sextic.vm");
    EXPECT_NEAR(eval(b, 0, 0, 0), -(2.0 + std::sqrt(5.0)), 1e-12);
}

TEST(VmImport, CommentsBlankLinesAndSharing) {
    const Graph g = import_vm(
        "# header\n"
        "\n"
        "   a var-x   # trailing comment\n"
        "b var-x\n"  // the same node as a
        "c const -2.5\n"
        "d mul a c\n"
        "e mul c b\n"  // the same node as d (commutative)
        "f sub d e\n",
        "t.vm");
    const Node& f = g.node(g.output());
    EXPECT_EQ(f.op, Op::Sub);
    EXPECT_EQ(f.a, f.b);
    EXPECT_EQ(g.size(), 4u);  // x, −2.5, mul, sub
    EXPECT_EQ(g.node(g.node(f.a).b).op == Op::Const ? g.node(g.node(f.a).b).constant
                                                    : g.node(g.node(f.a).a).constant,
              -2.5);
}

TEST(VmImport, ErrorsNameLineColumnAndCause) {
    EXPECT_EQ(error_of("_0 var-x\n_1 rand _0\n"), "t.vm:2:4: unsupported opcode 'rand'");
    EXPECT_EQ(error_of("_0 var-x\n_1 mix _0 _0\n"), "t.vm:2:4: unsupported opcode 'mix'");
    EXPECT_EQ(error_of("_0 var-x\n_1 floor _0 _0\n"), "t.vm:2:13: 'floor' takes 1 argument, got 2");
    EXPECT_EQ(error_of("_0 var-x\n_1 frob _0\n"), "t.vm:2:4: unknown opcode 'frob'");
    EXPECT_EQ(error_of("_0 var-x\n_1 add _0 _2\n"),
              "t.vm:2:11: undefined id '_2' (arguments must name ids defined on earlier lines)");
    EXPECT_EQ(error_of("_0 var-x\n_1 add _0 _2\n_2 const 1\n"),  // a forward reference
              "t.vm:2:11: undefined id '_2' (arguments must name ids defined on earlier lines)");
    EXPECT_EQ(error_of("_0 add _1 _1\n_1 add _0 _0\n"),  // a cycle
              "t.vm:1:8: undefined id '_1' (arguments must name ids defined on earlier lines)");
    EXPECT_EQ(error_of("_0 var-x\n_0 var-y\n"),
              "t.vm:2:1: duplicate id '_0' (first defined at line 1)");
    EXPECT_EQ(error_of("_0 var-x\n_1 add _0\n"), "t.vm:2:4: 'add' takes 2 arguments, got 1");
    EXPECT_EQ(error_of("_0 var-x 3\n"), "t.vm:1:10: 'var-x' takes 0 arguments, got 1");
    EXPECT_EQ(error_of("_0 var-x\n_1 neg _0 _0\n"), "t.vm:2:11: 'neg' takes 1 argument, got 2");
    EXPECT_EQ(error_of("_0 const\n"), "t.vm:1:4: 'const' takes 1 argument, got 0");
    EXPECT_EQ(error_of("_0 const abc\n"), "t.vm:1:10: malformed number 'abc'");
    EXPECT_EQ(error_of("_0 const nan\n"), "t.vm:1:10: malformed number 'nan'");
    EXPECT_EQ(error_of("_0 const inf\n"), "t.vm:1:10: malformed number 'inf'");
    EXPECT_EQ(error_of("_0 const 0x10\n"), "t.vm:1:10: malformed number '0x10'");
    EXPECT_EQ(error_of("_0 const 1.5.2\n"), "t.vm:1:10: malformed number '1.5.2'");
    EXPECT_EQ(error_of("_0 const 1e999\n"),
              "t.vm:1:10: number '1e999' is out of the range of double");
    EXPECT_EQ(error_of("_0\n"), "t.vm:1:3: expected an opcode after id '_0'");
    EXPECT_EQ(error_of("# nothing\n\n"),
              "t.vm: no instructions: expected '<id> <opcode> [args]' lines");
    EXPECT_THAT(error_of("_0 var-x\n_1 const 1\n_2 compare _0\n"),
                HasSubstr("t.vm:3:4: 'compare' takes 2 arguments, got 1"));
}

TEST(VmImport, ConstantsAreTheNearestDoubles) {
    EXPECT_EQ(import_vm("a const 0.1").node(NodeId{0}).constant, 0.1);
    EXPECT_EQ(import_vm("a const -2.5e-3").node(NodeId{0}).constant, -0.0025);
    EXPECT_EQ(import_vm("a const +7").node(NodeId{0}).constant, 7.0);
    EXPECT_EQ(import_vm("a const 1").node(NodeId{0}).constant, 1.0);
}

TEST(VmImport, MissingFileIsAnInputError) {
    EXPECT_THROW(import_vm_file(kModels / "no-such-model.vm"), InputError);
}

}  // namespace
}  // namespace certray::expr
