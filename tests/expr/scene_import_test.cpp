// tests/expr/scene_import_test.cpp — the particle and Lipschitz-Pruning JSON importers against
// the fields computed by hand here from the same numbers (the blob sum, the smooth-CSG fold of
// the molecule, the rotated sphere minus cylinder of test.json), and their input errors.
#include "expr/scene_import.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "expr/eval.h"
#include "expr/input_error.h"
#include "expr/load.h"
#include "expr/tape.h"

namespace certray::expr {
namespace {

namespace fs = std::filesystem;
using P = std::array<double, 3>;

double value(const Graph& g, const P& p) { return eval<double>(Tape(g), p); }

/// The first existing path among the candidates, or "" (the test is then skipped).
std::string find_file(std::initializer_list<fs::path> candidates) {
    for (const fs::path& p : candidates) {
        if (fs::exists(p)) return p.string();
    }
    return "";
}

double blob_by_hand(const std::vector<P>& centres, const P& p) {
    double s = 0;
    for (const P& c : centres) {
        const double d2 = (p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                          (p[2] - c[2]) * (p[2] - c[2]);
        const double k = std::max(1 - d2 / (2.25 * 2.25), 0.0);
        s += k * k * k;
    }
    return 0.5 - s;
}

TEST(ParticleImport, TwoBlobsByHand) {
    std::istringstream in("# two blobs\n0 0 0\n\n1.5 -0.5 2\n");
    const Graph g = import_particles(in);
    const std::vector<P> c = {P{0, 0, 0}, P{1.5, -0.5, 2}};
    for (const P& p : {P{0, 0, 0}, P{1, 0, 1}, P{0.3, -2, 0.7}, P{5, 5, 5}, P{1.5, -0.5, 2}}) {
        EXPECT_NEAR(value(g, p), blob_by_hand(c, p), 1e-14) << p[0] << " " << p[1] << " " << p[2];
    }
    // At a centre with no other blob within R: f = 0.5 − 1 = −0.5 (inside); far away f = 0.5.
    std::istringstream one("3 3 3\n");
    const Graph g1 = import_particles(one);
    EXPECT_EQ(value(g1, {3, 3, 3}), -0.5);
    EXPECT_EQ(value(g1, {10, 3, 3}), 0.5);
}

TEST(ParticleImport, ParametersAndErrors) {
    std::istringstream in("0 0 0\n");
    const Graph g = import_particles(in, ParticleParams{1.0, 2.0, 0.25});
    // |p| = 0.5: 0.25 − 2·(1 − 0.25)³ = 0.25 − 0.84375.
    EXPECT_DOUBLE_EQ(value(g, {0.5, 0, 0}), 0.25 - 0.84375);
    std::istringstream bad("0 0 0\n1 2\n");
    try {
        import_particles(bad, {}, "bad.txt");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "bad.txt");
        EXPECT_EQ(e.line(), 2);
    }
    std::istringstream extra("0 0 0 4\n");
    EXPECT_THROW(import_particles(extra), InputError);
    std::istringstream empty("# nothing\n");
    EXPECT_THROW(import_particles(empty), InputError);
}

TEST(ParticleImport, ReferenceSceneFile) {
    const std::string path =
        find_file({fs::path(CERTRAY_TEST_DATA) / "models" / "particles.txt",
                   fs::path(CERTRAY_TEST_DATA) / ".." / ".." / "scenes" / "particles.txt"});
    if (path.empty()) GTEST_SKIP() << "particles.txt not found";
    std::vector<P> c;
    std::ifstream in(path);
    for (P p; in >> p[0] >> p[1] >> p[2];) c.push_back(p);
    ASSERT_GE(c.size(), 1000u);  // 1,000 lines, the last one without a newline
    const Graph g = load_graph_file(path);
    const Tape t(g);
    for (const P& p : {P{0, 0, 0}, c[1], P{2, -3, 1}, P{0, -80, 0}, P{1, 1, -4}}) {
        EXPECT_NEAR(eval<double>(t, p), blob_by_hand(c, p), 1e-11);
    }
}

TEST(CsgJsonImport, MoleculeIsTheSmoothUnionFold) {
    const std::string path =
        find_file({fs::path(CERTRAY_TEST_DATA) / ".." / ".." / "scenes" / "molecule.json"});
    if (path.empty()) GTEST_SKIP() << "molecule.json not found";
    // By hand: the tree is a left comb of unions with identity matrices; collect the spheres in
    // left-to-right order and fold the smooth union. A matrix maps world to primitive space
    // (q = M·p, the authors' loader), so a sphere's centre is minus the translation column.
    std::ifstream in(path);
    const nlohmann::json doc = nlohmann::json::parse(in);
    std::vector<const nlohmann::json*> rights;
    const nlohmann::json* n = &doc;
    double k = -1;
    while (n->at("nodeType") == "binaryOperator") {
        ASSERT_EQ(n->at("blendMode"), "union");
        k = n->at("blendRadius").get<double>();
        rights.push_back(&n->at("rightChild"));
        n = &n->at("leftChild");
    }
    std::vector<std::array<double, 4>> spheres;  // cx cy cz r, left to right
    auto add = [&](const nlohmann::json& s) {
        const auto& m = s.at("matrix");
        spheres.push_back({-m[3].get<double>(), -m[7].get<double>(), -m[11].get<double>(),
                           s.at("radius").get<double>()});
    };
    add(*n);
    for (auto it = rights.rbegin(); it != rights.rend(); ++it) add(**it);
    ASSERT_EQ(spheres.size(), 1001u);
    auto by_hand = [&](const P& p) {
        double acc = 0, plain = 0;
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            const auto& s = spheres[i];
            const double d =
                std::sqrt((p[0] - s[0]) * (p[0] - s[0]) + (p[1] - s[1]) * (p[1] - s[1]) +
                          (p[2] - s[2]) * (p[2] - s[2])) -
                s[3];
            if (i == 0) {
                acc = plain = d;
                continue;
            }
            const double h = std::max(k - std::fabs(acc - d), 0.0);
            acc = std::min(acc, d) - h * h / (4 * k);
            plain = std::min(plain, d);
        }
        return std::array<double, 2>{acc, plain};
    };
    const CsgScene scene = import_csg_json_file(path);
    ASSERT_TRUE(scene.has_bounds);
    EXPECT_EQ(scene.bounds_min[2], -1.1);
    EXPECT_EQ(scene.bounds_max[0], 1.0);
    const Tape t(scene.graph);
    const auto& s0 = spheres[0];
    for (const P& p :
         {P{0, 0, 0}, P{0.5, -0.2, 0.3}, P{s0[0], s0[1], s0[2]}, P{2, 2, 2}, P{-0.7, 0.1, 1.0}}) {
        const auto [smooth, plain] = by_hand(p);
        const double f = eval<double>(t, p);
        EXPECT_NEAR(f, smooth, 1e-12);
        EXPECT_LE(f, plain + 1e-12);  // a smooth union never exceeds the hard one
    }
}

constexpr const char* kTestJson = R"({
  "aabb_min": [-2,-2,-2], "aabb_max": [2,2,2],
  "nodeType": "binaryOperator", "blendMode": "sub", "blendRadius": 0.1,
  "matrix": [1, 0, 0, 0, 0, 0.866, 0.5, 0, 0, -0.5, 0.866, 0],
  "leftChild": {"nodeType": "primitive", "primitiveType": "sphere", "radius": 1,
                "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]},
  "rightChild": {"nodeType": "primitive", "primitiveType": "cylinder", "height": 2,
                 "radius": 0.5, "matrix": [1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0]}})";

TEST(CsgJsonImport, SphereMinusCylinderByHand) {
    std::istringstream in(kTestJson);
    const CsgScene scene = import_csg_json(in);
    const Tape t(scene.graph);
    auto by_hand = [](const P& p) {
        // World to primitive: q = R·(M_prim·p), R the root rotation about x.
        const double ry = 0.866 * p[1] + 0.5 * p[2], rz = -0.5 * p[1] + 0.866 * p[2];
        const double sphere = std::sqrt(p[0] * p[0] + ry * ry + rz * rz) - 1;
        const double cx = p[0] + 1, cy = ry, cz = rz;  // the cylinder's translation by (1, 0, 0)
        const double dx = std::sqrt(cx * cx + cz * cz) - 0.5, dy = std::fabs(cy) - 1;
        const double cyl =
            std::min(std::max(dx, dy), 0.0) + std::sqrt(std::max(dx, 0.0) * std::max(dx, 0.0) +
                                                        std::max(dy, 0.0) * std::max(dy, 0.0));
        const double h = std::max(0.1 - std::fabs(sphere + cyl), 0.0);
        return std::max(sphere, -cyl) + h * h / 0.4;
    };
    for (const P& p : {P{0, 0, 0}, P{-1, 0, 0}, P{0.9, 0.1, -0.2}, P{-0.6, 0.3, 0.3},
                       P{-1.05, 0.2, 0.1}, P{3, -1, 2}}) {
        EXPECT_NEAR(eval<double>(t, p), by_hand(p), 1e-14) << p[0] << " " << p[1] << " " << p[2];
    }
    // The cylinder (axis along rotated y through x = −1) removes the sphere around (−1, 0, 0):
    // that point is outside; the opposite side (0.9, 0, 0) stays inside.
    EXPECT_GT(eval<double>(t, {-0.95, 0, 0}), 0);
    EXPECT_LT(eval<double>(t, {0.9, 0, 0}), 0);
}

TEST(CsgJsonImport, UnknownNodesAreNamed) {
    std::istringstream box(R"({"nodeType": "primitive", "primitiveType": "box",
        "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]})");
    try {
        import_csg_json(box, "box.json");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("box"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("box.json"), std::string::npos) << e.what();
    }
    std::istringstream op(R"({"nodeType": "binaryOperator", "blendMode": "xor", "blendRadius": 0,
        "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0],
        "leftChild": {"nodeType": "primitive", "primitiveType": "sphere", "radius": 1,
                      "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]},
        "rightChild": {"nodeType": "group", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]}})");
    try {
        import_csg_json(op);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("group"), std::string::npos) << e.what();
    }
    std::istringstream broken("{ not json");
    EXPECT_THROW(import_csg_json(broken), InputError);
}

}  // namespace
}  // namespace certray::expr
