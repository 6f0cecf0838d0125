// tests/tracers/bounding_test.cpp — bounding volumes (tracers/bounding.h): the structure read
// from f, distance bounds against exact distances to unions of spheres, the tracer against the
// certified solver (never past the first root, never a miss where a root is proven), roots that
// geometry gives on the 10⁴-sphere CSG, and bad input.
#include "tracers/bounding.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "expr/builder.h"
#include "expr/eval.h"
#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/ray_io.h"
#include "tests/support/generators.h"
#include "tests/support/independent_oracle.h"
#include "tests/support/stress_cases.h"
#include "tracers/methods.h"

namespace certray::tracers {
namespace {

using Box = BoundedScene::Box;

Box cube(double lo, double hi) { return {Interval(lo, hi), Interval(lo, hi), Interval(lo, hi)}; }

Box point(const std::array<double, 3>& p) {
    return {Interval(p[0]), Interval(p[1]), Interval(p[2])};
}

struct Sphere {
    std::array<double, 3> c;
    double r;
};

expr::Expr sphere(std::array<expr::Expr, 3> v, const Sphere& s) {
    return sqrt(square(v[0] - s.c[0]) + square(v[1] - s.c[1]) + square(v[2] - s.c[2])) - s.r;
}

/// Union of spheres as a tape (a left-deep chain of min, as files write it).
expr::Tape union_of(const std::vector<Sphere>& spheres) {
    expr::Graph g;
    const auto v = expr::vars(g);
    expr::Expr f = sphere(v, spheres[0]);
    for (std::size_t i = 1; i < spheres.size(); ++i) f = min(f, sphere(v, spheres[i]));
    g.set_output(f.id);
    return expr::Tape(g);
}

/// The exact distance from p to a union of spheres, for p outside all of them.
double distance_outside(const std::vector<Sphere>& spheres, const std::array<double, 3>& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const Sphere& s : spheres) {
        const double dx = p[0] - s.c[0], dy = p[1] - s.c[1], dz = p[2] - s.c[2];
        d = std::min(d, std::sqrt(dx * dx + dy * dy + dz * dz) - s.r);
    }
    return d;
}

rc::Gen<std::vector<Sphere>> gen_spheres() {
    return rc::gen::exec([] {
        std::vector<Sphere> out(*rc::gen::inRange(1, 40));
        for (Sphere& s : out) {
            for (double& c : s.c) c = *rc::gen::inRange(-150, 150) / 100.0;
            s.r = *rc::gen::inRange(1, 40) / 100.0;
        }
        return out;
    });
}

TEST(Bounding, ReadsTheCsgStructureOfTheGalleryScene) {
    // min(max(box, −ball), max(stick, |z| − 1.6)) with box = max(|x| − .8, |y| − .8, |z| − .8):
    // the first max cluster has four operands (three slabs and the complement of the ball), the
    // second two: six leaves; nodes: 6 leaves, 1 complement, 3 + 1 max, 1 min.
    const expr::Tape t(expr::load_graph_file(CERTRAY_SOURCE_DIR "/scenes/csg.expr"));
    const BoundedScene scene(t, cube(-2, 2));
    EXPECT_EQ(scene.leaves(), 6u);
    EXPECT_EQ(scene.nodes(), 12u);
}

TEST(Bounding, FarFromEverySphereTheBoundIsTheDistanceToTheirBox) {
    // Unit spheres at (±3, 0, 0): at the origin the exact distance is 2; the bound must not
    // exceed it, and is the distance to a sphere's box, cut by bisection to within 2⁻¹² of the
    // bounds' side (16) per round.
    const std::vector<Sphere> s{{{3, 0, 0}, 1}, {{-3, 0, 0}, 1}};
    const BoundedScene scene(union_of(s), cube(-8, 8));
    std::uint64_t evals = 0;
    const Interval d = scene.distance(point({0, 0, 0}), evals);
    EXPECT_LE(d.lower(), 2.0);
    EXPECT_GE(d.lower(), 2.0 - 16.0 / 4096);
    // Inside a sphere the sign is negative: the centre is 1 from the boundary.
    const Interval in = scene.distance(point({3, 0, 0}), evals);
    EXPECT_LT(in.upper(), 0);
    EXPECT_GE(in.lower(), -1.0 - 1e-12);
}

RC_GTEST_PROP(BoundingProperty, NeverMoreThanTheExactDistanceToAUnionOfSpheres, ()) {
    const std::vector<Sphere> spheres = *gen_spheres();
    const BoundedScene scene(union_of(spheres), cube(-2, 2));
    for (int k = 0; k < 20; ++k) {
        std::array<double, 3> p;
        for (double& c : p) c = *rc::gen::inRange(-200, 200) / 100.0;
        const double exact = distance_outside(spheres, p);
        std::uint64_t evals = 0;
        const Interval d = scene.distance(point(p), evals, *rc::gen::element(0.0, 0.01, 0.3));
        RC_ASSERT(d.defined);
        if (exact > 1e-9) {
            RC_ASSERT(d.lower() > 0);               // outside: positive
            RC_ASSERT(d.lower() <= exact + 1e-12);  // a lower bound of the distance
        } else if (exact < -1e-9) {
            RC_ASSERT(d.upper() < 0);  // inside some sphere: negative
        }
    }
}

/// f(o + t·d) in double.
double value_at(const expr::Tape& tape, const Ray& ray, double t) {
    return expr::eval<double>(
        tape, {ray.o[0] + t * ray.d[0], ray.o[1] + t * ray.d[1], ray.o[2] + t * ray.d[2]});
}

/// A random CSG of spheres: unions, differences and intersections (max with a complement / a
/// big sphere), as a tape, with its spheres.
struct Csg {
    expr::Tape tape;
    std::vector<Sphere> spheres;
};
rc::Gen<Csg> gen_csg_and_spheres() {
    return rc::gen::exec([] {
        const std::vector<Sphere> spheres = *gen_spheres();
        expr::Graph g;
        const auto v = expr::vars(g);
        expr::Expr f = sphere(v, spheres[0]);
        for (std::size_t i = 1; i < spheres.size(); ++i) {
            const expr::Expr s = sphere(v, spheres[i]);
            switch (*rc::gen::inRange(0, 4)) {
                case 0:
                    f = max(f, -s);  // difference
                    break;
                case 1:
                    f = max(f, s - 0.5);  // intersection with a larger sphere
                    break;
                default:
                    f = min(f, s);
            }
        }
        g.set_output(f.id);
        return Csg{expr::Tape(g), spheres};
    });
}
rc::Gen<expr::Tape> gen_csg() {
    return rc::gen::map(gen_csg_and_spheres(), [](Csg c) { return std::move(c.tape); });
}

RC_GTEST_PROP(BoundingProperty, NeverPastTheCertifiedFirstRootNorMissingAProvenOne, ()) {
    const expr::Tape tape = *gen_csg();
    const BoundedScene scene(tape, cube(-2.5, 2.5));
    TraceOptions opt;
    opt.epsilon = 1e-7;
    for (int k = 0; k < 8; ++k) {
        const Ray ray = *testing::gen_ray();
        const RayResult got = bounded_sphere_trace(scene, ray, opt);
        const RayResult ref = solvers::certified_first_root(tape, ray, {});
        if (ref.status == Status::Hit) {
            // A root is proven at t ≤ ref.t_hi: the tracer stops at or before it, never misses.
            RC_ASSERT(got.status != Status::Miss);
            if (got.status == Status::Hit) RC_ASSERT(got.t <= ref.t_hi);
        }
        if (ref.status == Status::Miss) {
            // No root: a hit is only the classic ε-termination beside the surface (|f|/λ < ε).
            RC_ASSERT(got.status != Status::Hit || std::fabs(value_at(tape, ray, got.t)) < 1e-6);
        }
    }
}

TEST(BoundingProperty, RestrictedCertifiedSurvivesTheIndependentOracle) {
    // certified-bvh answers from a tape with only the leaves each ray meets: every Hit and Miss is
    // judged on the full tape by the independent oracle (tests/support/independent_oracle.h), and
    // must not contradict the certified solver on the full tape either.
    testing::OracleTally tally;
    const bool ok = rc::check("every certified-bvh hit and miss survives the oracle", [&] {
        const Csg csg = *gen_csg_and_spheres();
        const expr::Tape& tape = csg.tape;
        const BoundedScene scene(tape, cube(-2, 2));
        for (int k = 0; k < 8; ++k) {
            Ray ray = *testing::gen_ray();
            if (k % 2 == 1) {
                // Every other ray aimed near a sphere's centre (reached at t = 1), so that rays
                // hit about as often as they miss.
                const Sphere& s = *rc::gen::elementOf(csg.spheres);
                for (int i = 0; i < 3; ++i) {
                    ray.d[i] = s.c[i] + s.r * *rc::gen::inRange(-100, 100) / 100.0 - ray.o[i];
                }
                ray.tmax = 2;
            }
            const RayResult got = bounded_certified(scene, ray, 20000);
            const testing::Judgement j = tally.judge(tape, ray, got);
            RC_LOG() << testing::describe(ray, got) << ": " << j.why << "\n";
            RC_ASSERT(j.verdict != testing::Verdict::Refuted);
            const RayResult ref = solvers::certified_first_root(tape, ray, {});
            if (got.status == Status::Unknown || ref.status == Status::Unknown) continue;
            RC_ASSERT(got.status == ref.status);
            if (got.status == Status::Hit) {
                RC_ASSERT(got.t_lo <= ref.t_hi);
                RC_ASSERT(ref.t_lo <= got.t_hi);
            }
        }
    });
    EXPECT_TRUE(ok);
    std::printf("%s\n", tally.summary("certified-bvh").c_str());
    EXPECT_EQ(tally.refuted, 0u);
    EXPECT_TRUE(tally.unverified_at_most(0.02)) << tally.summary("certified-bvh");
}

TEST(Bounding, RestrictionKeepsOnlyTheLeavesTheSegmentMeets) {
    // Three unit spheres on the x axis; a ray along y through the middle one meets one leaf.
    const std::vector<Sphere> s{{{-3, 0, 0}, 1}, {{0, 0, 0}, 1}, {{3, 0, 0}, 1}};
    const BoundedScene scene(union_of(s), cube(-5, 5));
    Ray ray;
    ray.o = {0, -4, 0};
    ray.d = {0, 1, 0};
    ray.tmin = 0;
    ray.tmax = 8;
    const BoundedScene::Restricted r = scene.restrict_to(ray);
    EXPECT_EQ(r.sign, 0);
    EXPECT_EQ(r.leaves, 1u);
    const RayResult hit = bounded_certified(scene, ray, 20000);
    ASSERT_EQ(hit.status, Status::Hit);
    EXPECT_LE(hit.t_lo, 3.0);  // the root y = −1: t = 3
    EXPECT_GE(hit.t_hi, 3.0);
    // Above all three: no leaf left, f > 0 on the whole segment.
    ray.o = {0, -4, 2.5};
    EXPECT_EQ(scene.restrict_to(ray).sign, +1);
    EXPECT_EQ(bounded_certified(scene, ray, 20000).status, Status::Miss);
}

TEST(Bounding, CertifiedBvhOnTheStressSuite) {
    // Every case of scenes/stress/cases.csv: never a wrong answer (the rules of stress_test.cpp).
    std::map<std::string, std::unique_ptr<expr::Tape>> tapes;
    std::map<std::string, std::unique_ptr<BoundedScene>> scenes;
    for (const testing::StressCase& c : testing::read_stress_cases()) {
        if (!tapes.count(c.scene)) {
            tapes[c.scene] = std::make_unique<expr::Tape>(
                expr::load_graph_file(testing::stress_dir() + c.scene));
            scenes[c.scene] = std::make_unique<BoundedScene>(*tapes[c.scene], cube(-2, 2));
        }
        testing::check_stress_case(c, bounded_certified(*scenes[c.scene], c.ray, 20000), false);
    }
}

TEST(Bounding, FindsTheSpheresOfTheTenThousandSphereCsg) {
    // scenes/stress/deep_csg.expr: spheres of radius 0.004 centred at (0.01 i, 0.01 j, 0).
    const expr::Tape t(expr::load_graph_file(CERTRAY_SOURCE_DIR "/scenes/stress/deep_csg.expr"));
    const BoundedScene scene(t, cube(-2, 2));
    EXPECT_EQ(scene.leaves(), 10000u);
    TraceOptions opt;
    opt.epsilon = 1e-9;
    // Straight down onto the centre (0.5, 0.5, 0) from z = −1: the root is z = −0.004.
    Ray down;
    down.o = {0.5, 0.5, -1};
    down.d = {0, 0, 1};
    down.tmin = 0;
    down.tmax = 2;
    const RayResult hit = bounded_sphere_trace(scene, down, opt);
    ASSERT_EQ(hit.status, Status::Hit);
    EXPECT_NEAR(hit.t, 1 - 0.004, 1e-8);
    EXPECT_LE(hit.t, 1 - 0.004);
    // Between four spheres: 0.005·√2 ≈ 0.00707 from each centre, more than the radius.
    down.o = {0.505, 0.505, -1};
    EXPECT_EQ(bounded_sphere_trace(scene, down, opt).status, Status::Miss);
    // Through the registry, with the default bounds.
    const RayFunction bvh = make_method("bvh", t, MethodOptions{});
    down.o = {0.25, 0.73, -1};
    const RayResult r = bvh(down);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_NEAR(r.t, 1 - 0.004, 1e-5);
    // Certified: the root 1 − 0.004 (z = −0.004 on the sphere at (0.25, 0.73, 0)) enclosed.
    const RayResult c = make_method("certified-bvh", t, MethodOptions{})(down);
    ASSERT_EQ(c.status, Status::Hit);
    EXPECT_LE(c.t_lo, 0.996);
    EXPECT_GE(c.t_hi, 0.996);
    EXPECT_LT(c.t_hi - c.t_lo, 1e-12);
}

TEST(Bounding, CertifiedBvhGivesTheRootsGeometryGivesOnTheDeepCsg) {
    // scenes/stress/deep_csg_rays.csv: 256 rays straight up (+z) from z = −1 at (x, y). The ray
    // meets the sphere of radius r = 0.004 at (0.01 i, 0.01 j, 0) iff its distance δ to that
    // centre in the plane is below r, first at z = −√(r² − δ²): t = 1 − √(r² − δ²).
    const expr::Tape t(expr::load_graph_file(CERTRAY_SOURCE_DIR "/scenes/stress/deep_csg.expr"));
    const RayFunction certified = make_method("certified-bvh", t, MethodOptions{});
    const std::vector<Ray> rays =
        read_rays_csv_file(CERTRAY_SOURCE_DIR "/scenes/stress/deep_csg_rays.csv");
    ASSERT_EQ(rays.size(), 256u);
    int hits = 0;
    for (const Ray& ray : rays) {
        long double delta = 1;
        for (int i = 0; i < 100; ++i) {
            for (int j = 0; j < 100; ++j) {
                const long double dx = ray.o[0] - 0.01L * i, dy = ray.o[1] - 0.01L * j;
                delta = std::min(delta, std::sqrt(dx * dx + dy * dy));
            }
        }
        const long double r = 0.004L;
        if (std::fabs(delta - r) < 1e-9L) continue;  // too close to the silhouette to judge
        const RayResult got = certified(ray);
        SCOPED_TRACE(std::to_string(ray.o[0]) + ", " + std::to_string(ray.o[1]));
        if (delta > r) {
            EXPECT_EQ(got.status, Status::Miss);
            continue;
        }
        ++hits;
        const long double root = 1 - std::sqrt(r * r - delta * delta);
        ASSERT_EQ(got.status, Status::Hit);
        EXPECT_LE(got.t_lo, root + 1e-12L);
        EXPECT_GE(got.t_hi, root - 1e-12L);
        EXPECT_LT(got.t_hi - got.t_lo, 1e-12);
    }
    EXPECT_GT(hits, 50);  // the file is not all misses
}

TEST(Bounding, TheMethodTracesOutsideTheBoundsToo) {
    // A sphere at x = 5, outside the default bounds [−2, 2]³: the part of the ray beyond them is
    // traced with its own segment's bound, so the hit at t = 4 (x = 4) is found.
    expr::Graph g;
    const auto v = expr::vars(g);
    g.set_output(sphere(v, {{5, 0, 0}, 1}).id);
    const expr::Tape t(g);
    const RayFunction bvh = make_method("bvh", t, MethodOptions{});
    Ray ray;
    ray.o = {0, 0, 0};
    ray.d = {1, 0, 0};
    ray.tmin = 0;
    ray.tmax = 10;
    const RayResult r = bvh(ray);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_NEAR(r.t, 4.0, 1e-5);
    EXPECT_LE(r.t, 4.0);
}

TEST(Bounding, RejectsUnboundedBounds) {
    const expr::Tape t = union_of({{{0, 0, 0}, 1}});
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_THROW(BoundedScene(t, {Interval(-inf, 1), Interval(-1, 1), Interval(-1, 1)}),
                 std::invalid_argument);
}

}  // namespace
}  // namespace certray::tracers
