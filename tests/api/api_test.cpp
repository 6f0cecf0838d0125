// tests/api/api_test.cpp — the public interface (include/certray/certray.h): Scene, query, the
// registry, bad input, threads, progress, cancellation, and hosts with their own floating-point
// state.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "certray/certray.h"
#include "expr/builder.h"
#include "tests/support/fp_env.h"
#include "tests/support/ray_checks.h"
#include "tracers/coherent.h"

namespace certray {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string scene_path(const std::string& name) {
    return std::string(CERTRAY_SOURCE_DIR) + "/scenes/" + name;
}

bool encloses(const RayResult& r, double t) { return r.t_lo <= t && t <= r.t_hi; }

TEST(Api, UnitSphereFromTextHitsAtTwo) {
    // |(0, 0, t - 3)| = 1 at t = 2 and t = 4: the first root is 2.
    const Scene scene = Scene::parse("sqrt(x^2 + y^2 + z^2) - 1");
    const std::vector<Ray> rays = {{{0, 0, -3}, {0, 0, 1}, 0, 10}, {{0, 2, -3}, {0, 0, 1}, 0, 10}};
    const std::vector<RayResult> r = query(scene, rays);
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].status, Status::Hit);
    EXPECT_TRUE(encloses(r[0], 2.0)) << r[0].t_lo << " " << r[0].t_hi;
    EXPECT_EQ(r[1].status, Status::Miss);  // passes at distance 2 from the centre
    EXPECT_FALSE(scene.is_2d());
    EXPECT_TRUE(method_info("certified").certified);
}

TEST(Api, SceneFromTheBuilderOwnsItsGraph) {
    Scene scene = [] {
        expr::Graph g;
        auto [x, y, z] = expr::vars(g);
        g.set_output((x * x + y * y + z * z - 4.0).id);
        return Scene::from_graph(std::move(g));  // the graph is moved in: nothing dangles
    }();
    // x² + y² + z² = 4 along (0, 0, t - 3): t = 1.
    const RayResult r = query_one(scene, {{0, 0, -3}, {0, 0, 1}, 0, 10});
    EXPECT_EQ(r.status, Status::Hit);
    EXPECT_TRUE(encloses(r, 1.0));
    // The printed expression parses back to the same function.
    const RayResult again =
        query_one(Scene::parse(scene.to_expr()), {{0, 0, -3}, {0, 0, 1}, 0, 10});
    EXPECT_EQ(again.t_lo, r.t_lo);
    EXPECT_EQ(again.t_hi, r.t_hi);
}

TEST(Api, LoadsEveryFormatAndCsgBounds) {
    EXPECT_FALSE(Scene::load(scene_path("torus.expr")).is_2d());
    EXPECT_FALSE(Scene::load(scene_path("barth_sextic.vm")).is_2d());
    EXPECT_TRUE(Scene::load(scene_path("prospero.vm")).is_2d());
    EXPECT_FALSE(Scene::load(scene_path("particles.txt")).is_2d());
    const Scene csg = Scene::load(scene_path("molecule.json"));
    ASSERT_TRUE(csg.bounds().has_value());
    EXPECT_LT((*csg.bounds())[0][0], (*csg.bounds())[0][1]);
    EXPECT_THROW(Scene::load(scene_path("missing.expr")), std::exception);
    EXPECT_THROW(Scene::parse("x +* y"), std::exception);
}

TEST(Api, BadInputIsAnExceptionNamingWhat) {
    const Scene scene = Scene::parse("x");
    auto message = [&](const std::vector<Ray>& rays, const QueryOptions& o = {}) -> std::string {
        try {
            query(scene, rays, o);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "no error";
    };
    const Ray ok{{0, 0, 0}, {1, 0, 0}, 0, 1};
    Ray nan_d = ok;
    nan_d.d[0] = kNaN;
    EXPECT_EQ(message({ok, nan_d}), "ray 1: dx is not a finite number");
    Ray inf_o = ok;
    inf_o.o[2] = kInf;
    EXPECT_EQ(message({inf_o}), "ray 0: oz is not a finite number");
    Ray reversed = ok;
    reversed.tmin = 2;
    EXPECT_EQ(message({reversed}), "ray 0: tmin > tmax");
    QueryOptions unknown;
    unknown.method = "magic";
    EXPECT_NE(message({ok}, unknown).find("unknown method 'magic'; available methods: certified"),
              std::string::npos);
    QueryOptions unread;
    unread.method = "certified";
    unread.knobs.values = {{"samples", 8}};
    EXPECT_EQ(message({ok}, unread),
              "method 'certified' does not read 'samples'; its knobs: budget, tighten");
    QueryOptions out_of_range;
    out_of_range.method = "hermite";
    out_of_range.knobs.values = {{"samples", 0.5}};
    EXPECT_NE(message({ok}, out_of_range).find("knob 'samples'"), std::string::npos);
    // A zero direction and tmin = tmax are valid degenerate rays (g is constant: x = 0 → a hit).
    const RayResult degenerate = query_one(scene, {{0, 0, 0}, {0, 0, 0}, 1, 1});
    EXPECT_EQ(degenerate.status, Status::Hit);
}

TEST(Api, ThreadsGiveTheSameAnswersAndReportProgress) {
    const Scene scene = Scene::load(scene_path("torus.expr"));
    std::vector<Ray> rays;
    for (int i = 0; i < 500; ++i) {
        const double a = 0.0125 * i;
        rays.push_back(
            {{3 * std::cos(a), 3 * std::sin(a), 0.3}, {-std::cos(a), -std::sin(a), 0}, 0, 6});
    }
    QueryOptions one;
    one.threads = 1;
    QueryOptions two;
    two.threads = 2;
    std::size_t last_done = 0, calls = 0;
    two.progress = [&](std::size_t done, std::size_t n) {
        EXPECT_EQ(n, rays.size());
        EXPECT_GE(done, last_done);
        last_done = done;
        ++calls;
    };
    const std::vector<RayResult> a = query(scene, rays, one);
    const std::vector<RayResult> b = query(scene, rays, two);
    testing::expect_same_answers(b, a);
    EXPECT_GE(calls, 1u);
    EXPECT_EQ(last_done, rays.size());
}

/// Rays like a camera's: from `eye` towards the points of a grid on the square of side 2·half
/// centred at the origin in the plane z = 0 (n × n of them).
std::vector<Ray> camera_rays(std::array<double, 3> eye, int n, double half, double tmax) {
    std::vector<Ray> rays;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double x = -half + 2 * half * (i + 0.5) / n, y = -half + 2 * half * (j + 0.5) / n;
            rays.push_back({eye, {x - eye[0], y - eye[1], -eye[2]}, 0, tmax});
        }
    }
    return rays;
}

// Camera-like rays are answered together by the coherent walk: the same answers as one by one
// (same status, hits enclosing the same first root within 4 ulps), on a surface with a known
// first root: the unit sphere seen from (0, 0, 3) towards z = 0 and parallel rays along −z.
TEST(Api, CameraLikeRaysAreAnsweredTogetherWithTheSameMeaning) {
    for (const char* text : {"x^2 + y^2 + z^2 - 1", "max(max(abs(x), abs(y)), abs(z)) - 0.75"}) {
        const Scene scene = Scene::parse(text);
        std::vector<Ray> rays = camera_rays({0, 0, 3}, 24, 1.2, 1.5);  // t = 1: the plane z = 0
        for (const Ray& r : camera_rays({0, 0, 3}, 20, 1.2, 1.5)) {
            rays.push_back(r);
        }
        std::vector<Ray> parallel;
        for (const Ray& r : camera_rays({0, 0, 3}, 20, 1.2, 1.5)) {
            parallel.push_back({{r.o[0] + r.d[0], r.o[1] + r.d[1], 3}, {0, 0, -1}, 0, 4});
        }
        for (const std::vector<Ray>* set : {&rays, &parallel}) {
            ASSERT_TRUE(tracers::bundle_rays(*set).has_value());
            QueryOptions one_by_one;
            one_by_one.coherent = false;
            const std::vector<RayResult> a = query(scene, *set);
            const std::vector<RayResult> b = query(scene, *set, one_by_one);
            ASSERT_EQ(a.size(), set->size());
            unsigned hits = 0;
            for (std::size_t k = 0; k < a.size(); ++k) {
                ASSERT_EQ(a[k].status, b[k].status) << text << " ray " << k;
                if (a[k].status != Status::Hit) continue;
                ++hits;
                EXPECT_LE(std::max(a[k].t_lo, b[k].t_lo), std::min(a[k].t_hi, b[k].t_hi)) << k;
                // Narrowed to 4 ulps as one by one (the `tighten` knob's default for queries).
                double lim = a[k].t_lo;
                for (int u = 0; u < 4; ++u) lim = std::nextafter(lim, kInf);
                EXPECT_LE(a[k].t_hi, lim) << k;
                if (std::string(text).front() == 'x') {  // the sphere: |o + t·d|² = 1
                    const Ray& r = (*set)[k];
                    const double qa = r.d[0] * r.d[0] + r.d[1] * r.d[1] + r.d[2] * r.d[2];
                    const double qb = 2 * (r.o[0] * r.d[0] + r.o[1] * r.d[1] + r.o[2] * r.d[2]);
                    const double qc = r.o[0] * r.o[0] + r.o[1] * r.o[1] + r.o[2] * r.o[2] - 1;
                    const double t = (-qb - std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
                    EXPECT_LE(a[k].t_lo, t + 1e-12) << k;
                    EXPECT_GE(a[k].t_hi, t - 1e-12) << k;
                }
            }
            EXPECT_GT(hits, 50u) << text;
        }
    }
    // Rays that share neither origin nor direction, or too few: one by one.
    std::vector<Ray> scattered = camera_rays({0, 0, 3}, 20, 1.2, 1.5);
    for (std::size_t k = 0; k < scattered.size(); ++k) scattered[k].o[0] += 1e-3 * k;
    EXPECT_FALSE(tracers::bundle_rays(scattered).has_value());
    EXPECT_FALSE(tracers::bundle_rays(camera_rays({0, 0, 3}, 10, 1.2, 1.5)).has_value());
}

TEST(Api, CancelledQueriesThrow) {
    const Scene scene = Scene::parse("x");
    const std::vector<Ray> rays(10000, Ray{{-1, 0, 0}, {1, 0, 0}, 0, 2});
    std::atomic<bool> cancel{true};
    QueryOptions o;
    o.cancel = &cancel;
    EXPECT_THROW(query(scene, rays, o), Cancelled);
}

TEST(Api, SolidSurfaceSkipsRegionsWhereFIsZero) {
    // Along (t − 3, 0, 0): f = min(max(x, 0), (x − 2)² + y² + z² − 1/4) is ≡ 0 for x ≤ 0 (t ≤ 3),
    // positive for 0 < x < 1.5 and negative inside the ball from x = 1.5 (t = 4.5).
    const Scene scene = Scene::parse("min(max(x, 0), (x - 2)^2 + y^2 + z^2 - 0.25)");
    const Ray ray{{-3, 0, 0}, {1, 0, 0}, 0, 10};
    QueryOptions solid;
    solid.surface = Surface::Solid;
    for (const char* method : {"certified", "certified-octree", "reference"}) {
        solid.method = method;
        const RayResult r = query_one(scene, ray, solid);
        EXPECT_EQ(r.status, Status::Hit) << method;
        EXPECT_TRUE(encloses(r, 4.5)) << method << " " << r.t_lo << " " << r.t_hi;
    }
    // The zero surface: f = 0 already at t = 0.
    const RayResult z = query_one(scene, ray);
    EXPECT_EQ(z.status, Status::Hit);
    EXPECT_EQ(z.t_lo, 0.0);
    // A ray through the f ≡ 0 region only: no entry into the solid.
    const RayResult slab = query_one(scene, {{-3, 5, 0}, {1, 0, 0}, 0, 2}, solid);
    EXPECT_EQ(slab.status, Status::Miss);
    EXPECT_EQ(Scene::load(scene_path("test.json")).default_surface(), Surface::Solid);
    EXPECT_EQ(Scene::load(scene_path("torus.expr")).default_surface(), Surface::Zero);
}

TEST(Api, RegistrySaysWhichMethodsAreProven) {
    int certified = 0, approximate = 0;
    for (const MethodInfo& m : methods()) (m.certified ? certified : approximate)++;
    EXPECT_GE(certified, 6);
    EXPECT_GE(approximate, 6);
    EXPECT_FALSE(method_info("sphere").certified);
    EXPECT_FALSE(method_info("taylor-plain").certified);
    EXPECT_TRUE(method_info("certified-taylor").certified);
    // The old names still work, as the new ones.
    EXPECT_EQ(method_info("approx").name, "certified-taylor");
    EXPECT_EQ(method_info("approx-plain").name, "taylor-plain");
    EXPECT_THROW(method_info("nope"), std::invalid_argument);
}

TEST(Api, HostsWithFlushToZeroOrAnotherRoundingGetTheSameAnswers) {
    // (x − 1/2)·2^-1070: every value near the root is subnormal; the root is 1/2.
    const Scene scene = Scene::load(scene_path("stress/subnormal.expr"));
    const std::vector<Ray> rays = {{{0, 0, 0}, {1, 0, 0}, 0, 1}, {{0.75, 0, 0}, {1, 0, 0}, 0, 1}};
    const std::vector<RayResult> reference = query(scene, rays);
    ASSERT_EQ(reference[0].status, Status::Hit);
    EXPECT_TRUE(encloses(reference[0], 0.5));
    EXPECT_EQ(reference[1].status, Status::Miss);
    for (const char* state : {"ftz-daz", "upward", "downward", "toward-zero"}) {
        testing::HostFpEnv host(state);
        const testing::FpWords words = testing::read_fp_words();
        const std::vector<RayResult> r = query(scene, rays);
        EXPECT_TRUE(testing::same_control(testing::read_fp_words(), words)) << state;
        testing::expect_same_answers(r, reference, state);
    }
}

}  // namespace
}  // namespace certray
