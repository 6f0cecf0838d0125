// tests/tracers/tracers_test.cpp — ray marching, sphere, enhanced and segment tracing against
// roots mathematics gives, the never-past-the-first-root guarantee against the certified solver
// (random sphere unions with the proven λ = 1, random DAGs with λ from the interval gradient), a
// thin shell that marching skips, and a broken λ that makes sphere tracing overshoot.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "expr/derived.h"
#include "expr/graph.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "tests/support/generators.h"
#include "tests/support/random_dag.h"
#include "tracers/march.h"
#include "tracers/methods.h"
#include "tracers/segment_trace.h"
#include "tracers/sphere_trace.h"

namespace certray::tracers {
namespace {

using expr::Tape;
constexpr double kInf = std::numeric_limits<double>::infinity();

Tape tape_of(const std::string& text) { return Tape(expr::parse_expr(text)); }

const char* kSphere = "sqrt(x^2 + y^2 + z^2) - 1";
const char* kTorus = "q = sqrt(x^2 + y^2) - 1\nsqrt(q^2 + z^2) - 0.35";

/// The three Lipschitz tracers with λ = `lambda` (segment ignores it: it derives its own).
std::array<RayResult, 3> lipschitz_tracers(const Tape& t, const Ray& ray, double lambda,
                                           const TraceOptions& o = {}) {
    return {sphere_trace(t, ray, lambda, o), enhanced_trace(t, ray, lambda, o),
            segment_trace(t, ray, o)};
}

/// A hit at most epsilon (scene units; ‖d‖ = 1 here) before `root` and never past it.
void expect_hit_before(const RayResult& r, double root, double eps, const char* what) {
    ASSERT_EQ(r.status, Status::Hit) << what;
    EXPECT_LE(r.t, root) << what;
    EXPECT_GE(r.t, root - eps) << what;
    EXPECT_GT(r.evals.total(), 0u) << what;
}

TEST(Tracers, UnitSphereHitAtTwo) {
    // |p| − 1 from (0, 0, −3) along +z: the first root is t = 2; an SDF is 1-Lipschitz.
    const Tape s = tape_of(kSphere);
    const Ray ray{{0, 0, -3}, {0, 0, 1}, 0, 10};
    const TraceOptions o;
    const auto rs = lipschitz_tracers(s, ray, 1.0, o);
    expect_hit_before(rs[0], 2.0, o.epsilon, "sphere");
    expect_hit_before(rs[1], 2.0, o.epsilon, "enhanced");
    expect_hit_before(rs[2], 2.0, o.epsilon, "segment");
    const RayResult m = march(s, ray, o);
    ASSERT_EQ(m.status, Status::Hit);
    EXPECT_LE(m.t_lo, 2.0);
    EXPECT_GE(m.t_hi, 2.0);
    EXPECT_LE(m.t_hi - m.t_lo, o.epsilon);
}

TEST(Tracers, SphereTracingWithoutAFiniteBoundFallsBackToSegments) {
    // √|z| − ½ has no finite Lipschitz bound on a box holding z = 0 (its derivative is unbounded
    // there): sphere tracing takes segment tracing's local bounds and finds the zero |z| = ¼ from
    // (0, 0, −3) along +z at t = 2.75, instead of stopping with no step.
    const Tape t = tape_of("sqrt(abs(z)) - 0.5");
    const RayFunction sphere = make_method("sphere", t, MethodOptions{});
    const RayResult r = sphere(Ray{{0, 0, -3}, {0, 0, 1}, 0, 6});
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_NEAR(r.t, 2.75, 1e-5);
}

TEST(Tracers, TorusHitAndHoleMiss) {
    // Torus R = 1, r = 0.35 around z: along +x from (−3, 0, 0) the first root is x = −1.35,
    // t = 1.65; along +z through the centre the ring stays at distance 1 − 0.35 > 0: a miss.
    const Tape t = tape_of(kTorus);
    const TraceOptions o;
    const Ray hit{{-3, 0, 0}, {1, 0, 0}, 0, 10};
    const auto rs = lipschitz_tracers(t, hit, 1.0, o);
    expect_hit_before(rs[0], 1.65, o.epsilon, "sphere");
    expect_hit_before(rs[1], 1.65, o.epsilon, "enhanced");
    expect_hit_before(rs[2], 1.65, o.epsilon, "segment");
    const RayResult m = march(t, hit, o);
    ASSERT_EQ(m.status, Status::Hit);
    EXPECT_LE(m.t_lo, 1.65);
    EXPECT_GE(m.t_hi, 1.65);

    const Ray hole{{0, 0, -3}, {0, 0, 1}, 0, 6};
    for (const RayResult& r : lipschitz_tracers(t, hole, 1.0, o)) {
        EXPECT_EQ(r.status, Status::Miss);
    }
    EXPECT_EQ(march(t, hole, o).status, Status::Miss);
}

TEST(Tracers, MissRayAndInfiniteTmax) {
    const Tape s = tape_of(kSphere);
    const TraceOptions o;
    const Ray far{{0, 5, 0}, {1, 0, 0}, -10, 10};
    for (const RayResult& r : lipschitz_tracers(s, far, 1.0, o)) EXPECT_EQ(r.status, Status::Miss);
    EXPECT_EQ(march(s, far, o).status, Status::Miss);
    // To infinity: sphere tracing cannot prove a miss (its steps never reach +inf) and answers
    // Unknown when the budget ends; segment tracing encloses the tail [0, +inf) at once.
    const Ray tail{{0, 5, 0}, {1, 0, 0}, 0, kInf};
    TraceOptions small = o;
    small.budget = 200;
    EXPECT_EQ(sphere_trace(s, tail, 1.0, small).status, Status::Unknown);
    const RayResult seg = segment_trace(s, tail, small);
    EXPECT_EQ(seg.status, Status::Miss);
    EXPECT_LE(seg.evals.total(), 2u);
}

TEST(Tracers, DegenerateRays) {
    const Tape s = tape_of(kSphere);
    const TraceOptions o;
    // Zero direction: g is the constant f(o).
    const Ray out{{0, 0, -3}, {0, 0, 0}, 0, 1};
    const Ray on{{0, 0, 1}, {0, 0, 0}, 0, 1};
    for (const RayResult& r : lipschitz_tracers(s, out, 1.0, o)) EXPECT_EQ(r.status, Status::Miss);
    for (const RayResult& r : lipschitz_tracers(s, on, 1.0, o)) EXPECT_EQ(r.status, Status::Hit);
    EXPECT_EQ(march(s, out, o).status, Status::Miss);
    EXPECT_EQ(march(s, on, o).status, Status::Hit);
    // tmin = tmax.
    const Ray point{{0, 0, -3}, {0, 0, 1}, 1, 1};
    EXPECT_EQ(sphere_trace(s, point, 1.0, o).status, Status::Miss);
    // Unusable λ.
    const Ray ray{{0, 0, -3}, {0, 0, 1}, 0, 10};
    EXPECT_EQ(sphere_trace(s, ray, kInf, o).status, Status::Unknown);
    EXPECT_EQ(enhanced_trace(s, ray, std::nan(""), o).status, Status::Unknown);
}

TEST(Tracers, UndefinedFieldAtTheStartOfTheRay) {
    // sqrt(x) is undefined for x < 0: at the origin of this ray. Sphere tracing and marching stop
    // there; segment tracing skips the segments where g has no value (a zero needs g defined, as
    // for the certified solver) and finds the zero x = 1 at t = 2, never past it.
    const Tape s = tape_of("sqrt(x) - 1");
    const Ray ray{{-1, 0, 0}, {1, 0, 0}, 0, 5};
    EXPECT_EQ(sphere_trace(s, ray, 1.0, {}).status, Status::Unknown);
    EXPECT_EQ(march(s, ray, {}).status, Status::Unknown);
    const RayResult r = segment_trace(s, ray, {});
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, 2.0);
    EXPECT_GE(r.t_hi, 2.0 - 1e-6);
}

TEST(Tracers, ThinShellSkippedByMarchFoundBySphereTracing) {
    // A shell of thickness 1e-3 around the unit sphere: ||p| − 1| − 5e-4, 1-Lipschitz. From
    // (0, 0, −3.005) along +z it occupies t ∈ [2.0045, 2.0055]: between the march samples 2.00 and
    // 2.01 (step 1e-2), where g is positive at both, so march sees no sign change there.
    const Tape s = tape_of("abs(sqrt(x^2 + y^2 + z^2) - 1) - 0.0005");
    const Ray ray{{0, 0, -3.005}, {0, 0, 1}, 0, 2.5};
    TraceOptions o;
    o.step = 1e-2;
    EXPECT_EQ(march(s, ray, o).status, Status::Miss);
    for (const RayResult& r : lipschitz_tracers(s, ray, 1.0, o)) {
        expect_hit_before(r, 2.0045, 1e-5, "lipschitz tracer on the shell");
    }
}

TEST(Tracers, OverRelaxedStepAcrossTheSurfaceIsTakenBack) {
    // Unit sphere, λ = 1, from z = −3 head-on: |f| = 2 at t = 0, so κ = 0.5 jumps to t = 3 (the
    // centre, |f| = 1). The free balls [−5, −1] and [−1, 1] only touch, at the root z = −1, and f
    // changed sign: Keinert's check must step back and find the root t = 2, not answer a miss.
    const Tape s = tape_of(kSphere);
    TraceOptions o;
    o.kappa = 0.5;
    const Ray head_on{{0, 0, -3}, {0, 0, 1}, 0, 10};
    const RayResult r = enhanced_trace(s, head_on, 1.0, o);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t, 2.0);
    EXPECT_GE(r.t, 2.0 - 1e-6);
}

TEST(Tracers, LooseLambdaIsOutgrownByLocalBounds) {
    // A cube (max of |x|, |y|, |z| − 1) united (min) with a sphere of radius 1 at (3, 0, 0):
    // 1-Lipschitz, first zero from (0, 0, −3) along +z at the cube's face z = −1, t = 2. With a
    // sound but loose λ = 10⁶ the steps |g|/λ are 2·10⁻⁶: the budget ran out after 0.04 of the
    // way (unknown). Local bounds over boxes that double from step to step reach the face.
    const Tape s =
        tape_of("min(max(max(abs(x), abs(y)), abs(z)) - 1, sqrt((x - 3)^2 + y^2 + z^2) - 1)");
    const Ray ray{{0, 0, -3}, {0, 0, 1}, 0, 10};
    TraceOptions o;
    o.seconds = 0;
    for (const RayResult& r : {sphere_trace(s, ray, 1e6, o), enhanced_trace(s, ray, 1e6, o)}) {
        ASSERT_EQ(r.status, Status::Hit);
        EXPECT_LE(r.t, 2.0);
        EXPECT_GE(r.t, 2.0 - 1e-5);
        EXPECT_LT(r.evals.total(), 400u);
    }
}

TEST(Tracers, LocalBoxesAreReusedOnlyWhereTheyHold) {
    // (x² + y² + z²)² − 1 from the origin along +x, first zero at t = 1: ‖∇f‖ = 4|p|³ is tiny
    // near the start and 4 at the zero. A box's λ near the start, reused for points outside that
    // box, would let the free radius jump past the zero; each step must take a box that holds it.
    const Tape s = tape_of("(x^2 + y^2 + z^2)^2 - 1");
    TraceOptions o;
    o.seconds = 0;
    for (const Ray& ray :
         {Ray{{0, 0, 0}, {1, 0, 0}, 0, 3}, Ray{{0.01, 0, 0}, {0.6, 0.8, 0}, 0, 3}}) {
        for (const RayResult& r : {sphere_trace(s, ray, 1e6, o), enhanced_trace(s, ray, 1e6, o)}) {
            ASSERT_EQ(r.status, Status::Hit);
            const double root = ray.o[0] == 0 ? 1.0 : -0.006 + std::sqrt(0.006 * 0.006 + 1 - 1e-4);
            EXPECT_LE(r.t, root + 1e-12);
            EXPECT_GE(r.t, root - 1e-5);
        }
    }
}

TEST(Tracers, BrokenLambdaOvershoots) {
    // λ/2 = 0.5 on the unit sphere from (0, 0, −3.5): the first step is 2·2.5 = 5 > 2.5, the
    // first root — sphere tracing jumps past the sphere and reports a miss. The never-past-the-
    // root property checked below fails for it; with the proven λ = 1 it holds.
    const Tape s = tape_of(kSphere);
    const Ray ray{{0, 0, -3.5}, {0, 0, 1}, 0, 8};
    const RayResult broken = sphere_trace(s, ray, 0.5, {});
    const bool respects = broken.status == Status::Hit && broken.t <= 2.5;
    EXPECT_FALSE(respects) << "status " << name(broken.status) << " t " << broken.t;
    const RayResult good = sphere_trace(s, ray, 1.0, {});
    EXPECT_TRUE(good.status == Status::Hit && good.t <= 2.5);
}

/// The guarantee against the certified solver: a traced hit is never past the certified first
/// root's enclosure, and a traced miss never contradicts a certified hit.
void check_against_certified(const Tape& t, const Ray& ray, const RayResult& traced) {
    const RayResult c = solvers::certified_first_root(t, ray);
    if (c.status == Status::Hit) {
        RC_ASSERT(traced.status != Status::Miss);
        if (traced.status == Status::Hit) RC_ASSERT(traced.t <= c.t_hi);
    }
    if (traced.status == Status::Miss) RC_ASSERT(c.status != Status::Hit);
}

RC_GTEST_PROP(TracersProperty, SphereUnionsNeverPastFirstRoot, ()) {
    // min over spheres of (|p − c| − r): 1-Lipschitz everywhere, so λ = 1 is proven.
    const int n = *rc::gen::inRange(1, 5);
    std::string text;
    for (int k = 0; k < n; ++k) {
        const double cx = *rc::gen::inRange(-20, 20) / 10.0, cy = *rc::gen::inRange(-20, 20) / 10.0,
                     cz = *rc::gen::inRange(-20, 20) / 10.0, r = *rc::gen::inRange(1, 15) / 10.0;
        const std::string s = "(sqrt((x - " + std::to_string(cx) + ")^2 + (y - " +
                              std::to_string(cy) + ")^2 + (z - " + std::to_string(cz) + ")^2) - " +
                              std::to_string(r) + ")";
        text = k == 0 ? s : "min(" + text + ", " + s + ")";
    }
    const Tape t = tape_of(text);
    const Ray ray = *testing::gen_ray(100, 80);
    TraceOptions o;
    o.budget = 2000;
    for (const RayResult& r : lipschitz_tracers(t, ray, 1.0, o)) check_against_certified(t, ray, r);
}

RC_GTEST_PROP(TracersProperty, LocalBoundsNeverPastFirstRoot, ()) {
    // Blobby unions of spheres (squared distances, 2r-Lipschitz near each) with a sound but
    // loose λ = 10⁴: the local bounds over boxes around the points do the work, each box reused
    // while the next point's box fits inside it (sphere_trace.cpp, local_bound).
    const int n = *rc::gen::inRange(1, 5);
    std::string text;
    for (int k = 0; k < n; ++k) {
        const double cx = *rc::gen::inRange(-20, 20) / 10.0, cy = *rc::gen::inRange(-20, 20) / 10.0,
                     cz = *rc::gen::inRange(-20, 20) / 10.0, r = *rc::gen::inRange(1, 15) / 10.0;
        const std::string s = "((x - " + std::to_string(cx) + ")^2 + (y - " + std::to_string(cy) +
                              ")^2 + (z - " + std::to_string(cz) + ")^2 - " +
                              std::to_string(r * r) + ")";
        text = k == 0 ? s : "min(" + text + ", " + s + ")";
    }
    const Tape t = tape_of(text);
    const Ray ray = *testing::gen_ray(100, 80);
    TraceOptions o;
    o.budget = 3000;
    o.seconds = 0;
    for (const RayResult& r : lipschitz_tracers(t, ray, 1e4, o)) check_against_certified(t, ray, r);
}

RC_GTEST_PROP(TracersProperty, RandomDagsNeverPastFirstRoot, ()) {
    const expr::Graph g = *testing::gen_dag(12);
    const Tape t(g);
    const Ray ray = *testing::gen_ray(100, 80);
    std::array<double, 3> p, q;
    for (int i = 0; i < 3; ++i) {
        p[i] = ray.o[i] + ray.tmin * ray.d[i];
        q[i] = ray.o[i] + ray.tmax * ray.d[i];
    }
    // The segment's bounding box, widened so that rounding of p and q cannot leave it.
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) {
        box[i] = Interval(std::nextafter(std::min(p[i], q[i]), -kInf) - 1e-9,
                          std::nextafter(std::max(p[i], q[i]), kInf) + 1e-9);
    }
    const double lambda = global_lipschitz(t, box);
    TraceOptions o;
    o.budget = 500;
    for (const RayResult& r : lipschitz_tracers(t, ray, lambda, o)) {
        check_against_certified(t, ray, r);
    }
}

}  // namespace
}  // namespace certray::tracers
