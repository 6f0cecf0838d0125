// tests/expr/scene_import_test.cpp — the particle and Lipschitz-Pruning JSON importers against
// the fields computed by hand here from the same numbers (the blob sum, the smooth-CSG fold of
// the molecule, the rotated sphere minus cylinder of test.json, each primitive and blend of the
// JSON format at points whose values the definitions give, and the branchy box and cone of the
// authors' shader at random points), their input errors, and the published test scene.
#include "expr/scene_import.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <vector>

#include "expr/eval.h"
#include "expr/input_error.h"
#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"

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

/// A one-node tree: the primitive with the given fields and matrix (identity by default).
CsgScene one_primitive(const std::string& fields,
                       const std::string& matrix = "[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]") {
    std::istringstream in(R"({"nodeType": "primitive", "matrix": )" + matrix + ", " + fields + "}");
    return import_csg_json(in, "one.json");
}

double at(const CsgScene& s, const P& p) { return value(s.graph, p); }

TEST(CsgJsonImport, SphereAndTheMatrixMapsWorldToPrimitive) {
    // q = M·p: a translation column (−2, 0, 0) puts the centre at (2, 0, 0).
    const CsgScene s = one_primitive(R"("primitiveType": "sphere", "radius": 1)",
                                     "[1, 0, 0, -2, 0, 1, 0, 0, 0, 0, 1, 0]");
    EXPECT_EQ(at(s, {2, 0, 0}), -1);
    EXPECT_EQ(at(s, {4, 0, 0}), 1);
    EXPECT_EQ(at(s, {0, 0, 0}), 1);
    // A scale of 2 in M shrinks the shape: ‖2p‖ − 1 vanishes at |p| = 1/2.
    const CsgScene k = one_primitive(R"("primitiveType": "sphere", "radius": 1)",
                                     "[2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0]");
    EXPECT_EQ(at(k, {0.5, 0, 0}), 0);
    EXPECT_EQ(at(k, {0, 1, 0}), 1);
}

constexpr const char* kNoRounding = R"("bevel": [0, 0, 0, 0], "round_x": 0, "round_y": 0)";

TEST(CsgJsonImport, BoxIsTheExactBoxDistance) {
    // sides are full lengths: sides (2, 2, 2) is [−1, 1]³. At (2, 0, 0) the distance is 1; at the
    // centre −1; from (2, 2, 2) the nearest point is the corner (1, 1, 1), at √3.
    const CsgScene s =
        one_primitive(std::string(R"("primitiveType": "box", "sides": [2, 2, 2], )") + kNoRounding);
    EXPECT_EQ(at(s, {2, 0, 0}), 1);
    EXPECT_EQ(at(s, {0, 0, 0}), -1);
    EXPECT_EQ(at(s, {0, 0.5, 0}), -0.5);
    EXPECT_DOUBLE_EQ(at(s, {2, 2, 2}), std::sqrt(3.0));
    EXPECT_DOUBLE_EQ(at(s, {-2, 0, 3}), std::sqrt(5.0));  // nearest (−1, 0, 1): (1, 0, 2)
    // sides (2, 4, 6): half sides (1, 2, 3); inside the nearest face is x = ±1.
    const CsgScene r =
        one_primitive(std::string(R"("primitiveType": "box", "sides": [2, 4, 6], )") + kNoRounding);
    EXPECT_EQ(at(r, {0, 0, 0}), -1);
    EXPECT_EQ(at(r, {0, 3, 0}), 1);
    EXPECT_EQ(at(r, {0, 0, 4}), 1);
    EXPECT_EQ(at(r, {0, 0, -2.5}), -0.5);
}

TEST(CsgJsonImport, BoxBevelsRoundEachVerticalEdgeWithHalfTheBevel) {
    // Their shader rounds the corner (x, z) with radius bevel/2: bevel[0] at x > 0, z > 0,
    // [1] x > 0, z ≤ 0, [2] x ≤ 0, z > 0, [3] x ≤ 0, z ≤ 0. At the sharp corner (±1, y, ±1) of
    // [−1, 1]³ a rounded edge of radius r (arc centred r inside each face) is at √2·r − r.
    const CsgScene s = one_primitive(
        R"("primitiveType": "box", "sides": [2, 2, 2], "bevel": [0.4, 0.8, 1.2, 1.6],
           "round_x": 0, "round_y": 0)");
    const double c = std::sqrt(2.0) - 1;
    EXPECT_NEAR(at(s, {1, 0, 1}), c * 0.2, 1e-15);
    EXPECT_NEAR(at(s, {1, 0.5, -1}), c * 0.4, 1e-15);
    EXPECT_NEAR(at(s, {-1, -0.5, 1}), c * 0.6, 1e-15);
    EXPECT_NEAR(at(s, {-1, 0, -1}), c * 0.8, 1e-15);
    // Outside along the diagonal of the first corner: ‖(1.2, 1.2)‖ − 0.2 from the arc's centre.
    EXPECT_NEAR(at(s, {2, 0, 2}), std::hypot(1.2, 1.2) - 0.2, 1e-15);
    // Faces and the centre are unchanged.
    EXPECT_EQ(at(s, {2, 0, 0}), 1);
    EXPECT_EQ(at(s, {0, 0, -2}), 1);
    EXPECT_EQ(at(s, {0, 0, 0}), -1);
}

TEST(CsgJsonImport, BoxRoundXRoundsTheTopEdgesAndRoundYTheBottom) {
    // The cross-section is extruded along y; round_x rounds the edges of y > 0, round_y those of
    // y ≤ 0. The edge (1, ±1, 0) with rounding e is at √2·e − e.
    const CsgScene s = one_primitive(
        R"("primitiveType": "box", "sides": [2, 2, 2], "bevel": [0, 0, 0, 0],
           "round_x": 0.5, "round_y": 0.25, "color": [0.1, 0.2, 0.3])");
    const double c = std::sqrt(2.0) - 1;
    EXPECT_NEAR(at(s, {1, 1, 0}), c * 0.5, 1e-15);
    EXPECT_NEAR(at(s, {0, -1, 1}), c * 0.25, 1e-15);
    EXPECT_EQ(at(s, {0, 2, 0}), 1);   // top face
    EXPECT_EQ(at(s, {0, -3, 0}), 2);  // bottom face
    EXPECT_EQ(at(s, {0, 0, 0}), -1);
}

/// The box of their shader, branch by branch (the corner radius and the extrusion rounding are
/// chosen by the signs of the coordinates), written here from the definition.
double box_by_hand(const P& p, const std::array<double, 3>& sides,
                   const std::array<double, 4>& bevel, double round_x, double round_y) {
    const double r =
        (p[0] > 0 ? (p[2] > 0 ? bevel[0] : bevel[1]) : (p[2] > 0 ? bevel[2] : bevel[3])) / 2;
    auto quadrant = [](double a, double b) {
        return std::min(std::max(a, b), 0.0) + std::hypot(std::max(a, 0.0), std::max(b, 0.0));
    };
    const double d =
        quadrant(std::fabs(p[0]) - sides[0] / 2 + r, std::fabs(p[2]) - sides[2] / 2 + r) - r;
    const double e = p[1] > 0 ? round_x : round_y;
    return quadrant(d + e, std::fabs(p[1]) - sides[1] / 2 + e) - e;
}

/// Their cone, branch by branch: in (ρ, y), p relative to the rim (R, −H), e = (−R, 2H) from the
/// rim to the apex, q = p − e·clamp(p·e/e·e, 0, 1); outside (q.x > 0 or q.y > 0) ‖q‖, inside
/// −min(‖q‖, p.y).
double cone_by_hand(const P& pt, double height, double radius) {
    const double hh = height / 2;
    const double px = std::hypot(pt[0], pt[2]) - radius, py = pt[1] + hh;
    const double ex = -radius, ey = 2 * hh;
    const double t = std::clamp((px * ex + py * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    const double qx = px - t * ex, qy = py - t * ey;
    const double d = std::hypot(qx, qy);
    return std::max(qx, qy) > 0 ? d : -std::min(d, py);
}

TEST(CsgJsonImport, BoxWithMixedRoundingsAgreesWithTheBranchesEverywhere) {
    const std::array<double, 3> sides{1.5, 2, 1};
    const std::array<double, 4> bevel{0.1, 0.9, 0.5, 0};
    const CsgScene s = one_primitive(
        R"("primitiveType": "box", "sides": [1.5, 2, 1], "bevel": [0.1, 0.9, 0.5, 0],
           "round_x": 0.3, "round_y": 1)");
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> u(-2, 2);
    for (int i = 0; i < 3000; ++i) {
        const P p{u(rng), u(rng), u(rng)};
        ASSERT_NEAR(at(s, p), box_by_hand(p, sides, bevel, 0.3, 1), 1e-12)
            << p[0] << " " << p[1] << " " << p[2];
    }
}

TEST(CsgJsonImport, Cylinder) {
    // Axis y, full height 2, radius 0.5.
    const CsgScene s = one_primitive(R"("primitiveType": "cylinder", "height": 2, "radius": 0.5)");
    EXPECT_EQ(at(s, {0, 0, 0}), -0.5);
    EXPECT_EQ(at(s, {0, 2, 0}), 1);
    EXPECT_EQ(at(s, {1.5, 0, 0}), 1);
    EXPECT_NEAR(at(s, {0, 0.8, 0.1}), -0.2, 1e-15);  // nearer the cap (0.2) than the side (0.4)
    EXPECT_DOUBLE_EQ(at(s, {1.5, 3, 0}), std::sqrt(5.0));  // from the rim (0.5, 1, 0)
}

TEST(CsgJsonImport, Cone) {
    // height 2, radius 1: base disc of radius 1 at y = −1, apex (0, 1, 0); the slanted side lies
    // on 2ρ + y = 1, at distance |2ρ + y − 1|/√5.
    const CsgScene s = one_primitive(R"("primitiveType": "cone", "height": 2, "radius": 1)");
    const double s5 = std::sqrt(5.0);
    EXPECT_EQ(at(s, {0, 1, 0}), 0);                 // the apex
    EXPECT_NEAR(at(s, {0, 3, 0}), 2, 1e-15);        // above the apex: from the apex
    EXPECT_NEAR(at(s, {0, -2, 0}), 1, 1e-15);       // below the base: from the base
    EXPECT_NEAR(at(s, {0, 0, 0}), -1 / s5, 1e-15);  // inside, nearer the side (0.447 < 1)
    EXPECT_NEAR(at(s, {0, -0.9, 0}), -0.1, 1e-15);  // inside, nearer the base
    EXPECT_NEAR(at(s, {1, 0, 0}), 1 / s5, 1e-15);   // outside the side
    EXPECT_NEAR(at(s, {0, 0, -1}), 1 / s5, 1e-15);  // the same, turned about y
    EXPECT_NEAR(at(s, {2, -1, 0}), 1, 1e-15);       // beside the rim (1, −1, 0)
    EXPECT_NEAR(at(s, {1.5, -2, 0}), std::sqrt(1.25), 1e-15);  // below and beside: the rim
    std::mt19937_64 rng(15);
    std::uniform_real_distribution<double> u(-3, 3);
    const CsgScene w = one_primitive(R"("primitiveType": "cone", "height": 0.7, "radius": 1.9)");
    for (int i = 0; i < 3000; ++i) {
        const P p{u(rng), u(rng), u(rng)};
        ASSERT_NEAR(at(s, p), cone_by_hand(p, 2, 1), 1e-12) << p[0] << " " << p[1] << " " << p[2];
        ASSERT_NEAR(at(w, p), cone_by_hand(p, 0.7, 1.9), 1e-12)
            << p[0] << " " << p[1] << " " << p[2];
    }
}

/// Spheres of radius 1 at the origin (left) and at (2.2, 0, 0) (right) under `mode` with `k`.
CsgScene two_spheres(const std::string& mode, double k) {
    std::ostringstream text;
    text << R"({"nodeType": "binaryOperator", "blendMode": ")" << mode << R"(", "blendRadius": )"
         << k << R"(, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0],
        "leftChild": {"nodeType": "primitive", "primitiveType": "sphere", "radius": 1,
                      "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]},
        "rightChild": {"nodeType": "primitive", "primitiveType": "sphere", "radius": 1,
                       "matrix": [1, 0, 0, -2.2, 0, 1, 0, 0, 0, 0, 1, 0]}})";
    std::istringstream in(text.str());
    return import_csg_json(in);
}

TEST(CsgJsonImport, BlendsByHand) {
    // At (1.1, 0, 0) both spheres are at a = b = 0.1. With k = 0.5 the kernel is
    // K(x) = max(k − x, 0)²/(4k): union min(a, b) − K(0) = 0.1 − 0.25/2 = −0.025 (the blend
    // bridges the gap); inter max(a, b) + K(0) = 0.225; sub max(a, −b) + K(|a + b|) =
    // 0.1 + 0.3²/2 = 0.145.
    const P mid{1.1, 0, 0};
    EXPECT_NEAR(at(two_spheres("union", 0.5), mid), -0.025, 1e-15);
    EXPECT_NEAR(at(two_spheres("inter", 0.5), mid), 0.225, 1e-15);
    EXPECT_NEAR(at(two_spheres("sub", 0.5), mid), 0.145, 1e-15);
    // blendRadius 0 is the sharp operator.
    EXPECT_NEAR(at(two_spheres("union", 0), mid), 0.1, 1e-15);
    EXPECT_NEAR(at(two_spheres("inter", 0), mid), 0.1, 1e-15);
    EXPECT_NEAR(at(two_spheres("sub", 0), mid), 0.1, 1e-15);
    // Where |a − b′| ≥ k the blend is off: at (−0.5, 0, 0), a = −0.5 and b = 1.7.
    const P left{-0.5, 0, 0};
    EXPECT_EQ(at(two_spheres("union", 0.5), left), -0.5);
    EXPECT_NEAR(at(two_spheres("inter", 0.5), left), 1.7, 1e-15);
    // sub: b′ = −1.7, |a − b′| = 1.2 ≥ k: max(−0.5, −1.7) = −0.5.
    EXPECT_EQ(at(two_spheres("sub", 0.5), left), -0.5);
    // Inside the right sphere, sub removes it: at (2.2, 0, 0), a = 1.2, b = −1: max(1.2, 1) +
    // K(0.2) = 1.2 + 0.3²/2 = 1.245.
    EXPECT_NEAR(at(two_spheres("sub", 0.5), {2.2, 0, 0}), 1.245, 1e-15);
}

/// The message of the InputError thrown by importing `text`, or "" when none is thrown.
std::string import_error(const std::string& text) {
    std::istringstream in(text);
    try {
        import_csg_json(in, "bad.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

constexpr const char* kId = R"("matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0])";

/// A binary node (union, k = 0) with the two children's texts.
std::string pair(const std::string& left, const std::string& right) {
    return R"({"nodeType": "binaryOperator", "blendMode": "union", "blendRadius": 0, )" +
           std::string(kId) + R"(, "leftChild": )" + left + R"(, "rightChild": )" + right + "}";
}

std::string ball(const std::string& extra = "") {
    return R"({"nodeType": "primitive", "primitiveType": "sphere", "radius": 1, )" +
           std::string(kId) + extra + "}";
}

TEST(CsgJsonImport, ErrorsNameTheNodeAndTheField) {
    auto expect = [](const std::string& text, std::initializer_list<const char*> parts) {
        const std::string what = import_error(text);
        ASSERT_FALSE(what.empty()) << "no error for " << text;
        EXPECT_EQ(what.rfind("bad.json: ", 0), 0u) << what;
        for (const char* part : parts) {
            EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
        }
    };
    // Pre-order: root 0, leftChild 1, leftChild.leftChild 2, leftChild.rightChild 3, rightChild 4.
    const std::string bad_radius =
        R"({"nodeType": "primitive", "primitiveType": "sphere", "radius": -1, )" +
        std::string(kId) + "}";
    expect(pair(pair(ball(), bad_radius), ball()),
           {"node 3 (leftChild.rightChild)", "field 'radius'", "> 0"});
    expect(pair(ball(), ball(R"(, "radiu": 2)")),
           {"node 2 (rightChild)", "field 'radiu'", "unknown field"});
    expect(pair(ball(), ball(R"(, "height": 2)")), {"node 2 (rightChild)", "field 'height'"});
    EXPECT_EQ(import_error(ball(R"(, "aabb_min": [0, 0, 0], "aabb_max": [1, 1, 1])")), "");
    expect(ball(R"(, "aabb_min": [0, 0, 0], "aabb_max": [1, -1, 1])"),
           {"node 0 (root)", "field 'aabb_max'"});
    expect(pair(ball(R"(, "aabb_min": [0, 0, 0])"), ball()),
           {"node 1 (leftChild)", "field 'aabb_min'", "unknown field"});
    // Unknown values.
    expect(R"({"nodeType": "primitive", "primitiveType": "torus", )" + std::string(kId) + "}",
           {"node 0 (root)", "field 'primitiveType'", "'torus'"});
    expect(pair(ball(), R"({"nodeType": "group", )" + std::string(kId) + "}"),
           {"node 2 (rightChild)", "field 'nodeType'", "'group'"});
    std::string xo = pair(ball(), ball());
    xo.replace(xo.find("\"union\""), 7, "\"xor\"");
    expect(xo, {"node 0 (root)", "field 'blendMode'", "'xor'"});
    // Missing and malformed fields.
    expect(R"({"nodeType": "primitive", "primitiveType": "sphere", )" + std::string(kId) + "}",
           {"node 0 (root)", "field 'radius'", "missing"});
    expect(R"({"nodeType": "primitive", "primitiveType": "sphere", "radius": 1})",
           {"field 'matrix'", "missing"});
    expect(ball(R"(, "round_x": "no")"), {"field 'round_x'", "expected a number"});
    expect(R"({"nodeType": "primitive", "primitiveType": "box", "sides": [1, 1], )" +
               std::string(kNoRounding) + ", " + kId + "}",
           {"field 'sides'", "array of 3 numbers"});
    expect(R"({"nodeType": "primitive", "primitiveType": "box", "sides": [1, 1, 2],
               "bevel": [0, 0, 1.5, 0], "round_x": 0, "round_y": 0, )" +
               std::string(kId) + "}",
           {"field 'bevel'", "[0, 1]"});
    expect(R"({"nodeType": "primitive", "primitiveType": "box", "sides": [1, 1, 1],
               "bevel": [0, 0, 0, 0], "round_y": 0, )" +
               std::string(kId) + "}",
           {"field 'round_x'", "missing"});
    expect(R"({"nodeType": "primitive", "primitiveType": "box", "sides": [1, 1, 1],
               "bevel": [0, 0, 0, 0], "round_x": 0, "round_y": 0.6, )" +
               std::string(kId) + "}",
           {"field 'round_y'", "[0, 0.5]"});
    std::string neg = pair(ball(), ball());
    neg.replace(neg.find("\"blendRadius\": 0"), 16, "\"blendRadius\": -0.1");
    expect(neg, {"node 0 (root)", "field 'blendRadius'"});
    expect(pair(ball(), "[1, 2]"), {"node 0 (root)", "field 'rightChild'", "expected an object"});
    expect(R"({"nodeType": "primitive", "primitiveType": "sphere", "radius": 1,
               "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]})",
           {"field 'matrix'", "array of 12 numbers"});
    // A long run of equal steps is written step*n.
    std::string deep = ball(R"(, "oops": 1)");
    for (int i = 0; i < 6; ++i) deep = pair(deep, ball());
    expect(deep, {"node 6 (leftChild*6)", "field 'oops'"});
    std::istringstream broken("{ not json");
    EXPECT_THROW(import_csg_json(broken), InputError);
}

TEST(CsgJsonImport, FieldsWithoutGeometryAreIgnored) {
    // color anywhere on a primitive, round_x and round_y on a non-box: the field is unchanged.
    const CsgScene plain = one_primitive(R"("primitiveType": "cone", "height": 2, "radius": 1)");
    const CsgScene extra = one_primitive(
        R"("primitiveType": "cone", "height": 2, "radius": 1, "color": [1, 0, 0],
           "round_x": 0.3, "round_y": 0.2)");
    for (const P& p : {P{0, 0, 0}, P{1, 0.5, -0.3}, P{0, 3, 0}})
        EXPECT_EQ(at(plain, p), at(extra, p));
}

TEST(CsgJsonImport, PublishedTestSceneLoadsAndIsHit) {
    // scenes/test.json is their scenes/test.json: the sphere minus the cylinder of kTestJson,
    // with colours and roundings (ignored on these primitives).
    const std::string path = std::string(CERTRAY_SOURCE_DIR) + "/scenes/test.json";
    const CsgScene scene = import_csg_json_file(path);
    ASSERT_TRUE(scene.has_bounds);
    EXPECT_EQ(scene.bounds_min[0], -2);
    EXPECT_EQ(scene.bounds_max[2], 2);
    std::istringstream in(kTestJson);
    const CsgScene same = import_csg_json(in);
    for (const P& p : {P{0, 0, 0}, P{-1, 0.2, 0.1}, P{0.9, 0.1, -0.2}, P{3, -1, 2}}) {
        EXPECT_EQ(at(scene, p), at(same, p));
    }
    // A ray along z through the centre meets the sphere's surface where ‖R·p‖ = 1, R the root
    // matrix (rows (0, 0.866, 0.5), (0, −0.5, 0.866): not quite a rotation, 0.866² + 0.5² ≠ 1):
    // z = −1/√(0.5² + 0.866²), t = 3 + z. There the cylinder (axis through x = −1, radius 0.5)
    // is about 0.82 away, beyond the blend radius 0.1, so the subtraction leaves the sphere.
    const expr::Tape tape(scene.graph);
    const RayResult r = solvers::certified_first_root(tape, Ray{{0, 0, -3}, {0, 0, 1}, 0, 6});
    const double t = 3 - 1 / std::sqrt(0.5 * 0.5 + 0.866 * 0.866);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, t + 1e-12);
    EXPECT_GE(r.t_hi, t - 1e-12);
    EXPECT_LT(r.t_hi - r.t_lo, 1e-9);
    // Through the hole: the ray along z through (−1, 0, ·) crosses the carved-out region first.
    const RayResult h = solvers::certified_first_root(tape, Ray{{-1, 0, -3}, {0, 0, 1}, 0, 6});
    EXPECT_NE(h.status, Status::Unknown);
}
}  // namespace
}  // namespace certray::expr
