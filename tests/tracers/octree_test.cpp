// tests/tracers/octree_test.cpp — the octree: conservative ray–box segments, cell classification,
// the certified method on it against roots mathematics gives and against the plain certified
// solver (random DAGs and rays), and sphere tracing with local λ never passing the first root.
#include "tracers/octree.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include "expr/eval.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "interval/mpfr_interval.h"
#include "solvers/certified.h"
#include "tests/support/face_cases.h"
#include "tests/support/generators.h"
#include "tests/support/independent_oracle.h"
#include "tests/support/random_dag.h"
#include "tracers/march.h"

namespace certray::tracers {
namespace {

using expr::Tape;
constexpr double kInf = std::numeric_limits<double>::infinity();
const std::array<Interval, 3> kCube{Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};

Tape tape_of(const char* text) { return Tape(expr::parse_expr(text)); }

TEST(RayBox, SegmentsAreConservative) {
    const std::array<Interval, 3> unit{Interval(0, 1), Interval(0, 1), Interval(0, 1)};
    const Interval a = ray_box(Ray{{-1, 0.5, 0.5}, {1, 0, 0}, 0, kInf}, unit);
    EXPECT_LE(a.lower(), 1.0);
    EXPECT_GE(a.upper(), 2.0);
    EXPECT_GE(a.lower(), std::nextafter(1.0, 0.0));  // outward by at most rounding
    // Parallel to a face and outside it: no segment; on the face itself: the whole line.
    EXPECT_TRUE(ray_box(Ray{{-1, 1.5, 0.5}, {1, 0, 0}, 0, kInf}, unit).is_empty());
    const Interval face = ray_box(Ray{{-1, 1, 0.5}, {1, 0, 0}, 0, kInf}, unit);
    EXPECT_LE(face.lower(), 1.0);
    // 0.1 is not a double multiple: the slab bounds are rounded outward, so the exact crossing
    // parameters (1 − o)/d lie inside the segment. Here o = 0.1·k, d = 0.3: t = (1 − 0.1)/0.3 = 3.
    const Interval c = ray_box(Ray{{0.1, 0.5, 0.5}, {0.3, 0, 0}, -kInf, kInf}, unit);
    EXPECT_LE(c.upper() * 0.3 + 0.1, 1.0 + 1e-15);
    EXPECT_GE(c.upper(), 3.0 - 1e-15);
    // A zero direction inside the box: every t.
    const Interval z = ray_box(Ray{{0.5, 0.5, 0.5}, {0, 0, 0}, 0, 1}, unit);
    EXPECT_EQ(z.lower(), -kInf);
    EXPECT_EQ(z.upper(), kInf);
}

TEST(Octree, ClassifiesTheSphere) {
    const Tape s = tape_of("sqrt(x^2 + y^2 + z^2) - 1");
    const Octree tree(s, kCube, {4, 1u << 20});
    const OctreeStats& st = tree.stats();
    EXPECT_GT(st.empty, 0u);
    EXPECT_GT(st.full, 0u);
    EXPECT_GT(st.ambiguous, 0u);
    EXPECT_EQ((st.nodes - 1) % 8, 0u);  // every branch has eight children
    // At depth 4 the cells are 0.25 wide: the shell of ambiguous cells around the unit sphere
    // is far smaller than the 4,096 cells of the full grid.
    EXPECT_LT(st.ambiguous, 1000u);
    // A node budget caps the tree.
    const Octree small(s, kCube, {8, 200});
    EXPECT_LE(small.stats().nodes, 200u);
}

TEST(Octree, CertifiedRootsMathematicsGives) {
    const Tape s = tape_of("sqrt(x^2 + y^2 + z^2) - 1");
    const Octree tree(s, kCube, {5, 1u << 20});
    solvers::CertifiedOptions o;
    RayResult r = tree.certified(Ray{{0, 0, -3}, {0, 0, 1}, 0, kInf}, o);  // starts outside
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, 2.0);
    EXPECT_GE(r.t_hi, 2.0);
    r = tree.certified(Ray{{0, 0, 0}, {1, 0, 0}, 0, 10}, o);  // from inside
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, 1.0);
    EXPECT_GE(r.t_hi, 1.0);
    EXPECT_EQ(tree.certified(Ray{{0, 5, 0}, {1, 0, 0}, -10, 10}, o).status, Status::Miss);
    // A root outside the bounds is still found: a sphere of radius 1 at x = 5.
    const Tape far = tape_of("sqrt((x - 5)^2 + y^2 + z^2) - 1");
    const Octree tf(far, kCube, {4, 1u << 20});
    r = tf.certified(Ray{{0, 0, 0}, {1, 0, 0}, 0, 10}, o);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, 4.0);
    EXPECT_GE(r.t_hi, 4.0);
}

TEST(Octree, CertifiedProvesTwoCloseRootsOnACellFace) {
    // x² + y² + z² = 1 along y = 1 − 2⁻⁴⁰, z = 0 (a cell face: the ray is in two cells), roots
    // 3 ∓ √(1 − (1 − 2⁻⁴⁰)²) ≈ 3 ∓ 1.3e-6 on either side of the face x = 0. The plain solver
    // proves the first; the octree must too (its overlapping segments once turned the proof into
    // an unknown), within the budget.
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    const Octree tree(s, kCube, {5, 1u << 20});
    const RayResult r =
        tree.certified(Ray{{-3, 1 - std::ldexp(1.0, -40), 0}, {1, 0, 0}, 0, 10}, {});
    ASSERT_EQ(r.status, Status::Hit);
    const double root_lo = 0x1.7ffff4afb0cccp+1, root_hi = 0x1.7ffff4afb0ccdp+1;  // mpmath
    EXPECT_LE(r.t_lo, root_lo);
    EXPECT_GE(r.t_hi, root_hi);
    EXPECT_LT(r.evals.total(), 20000u);
}

TEST(Octree, CertifiedProvesRootsOnCellFaces) {
    // Boxes with faces at ±0.75, on cell faces at depths ≥ 4: each cell's solve sees half of the
    // sign change (the other half lies in the neighbour's segment, a few ulps on). Before the
    // window across faces, 134 of 138 such rays on the box ended unknown, two ulps wide.
    for (int depth : {4, 5, 6}) {
        for (std::size_t k = 0; k < testing::kFaceScenes.size(); ++k) {
            const Tape t = tape_of(testing::kFaceScenes[k]);
            const Octree tree(t, kCube, {depth, 1u << 20});
            for (const testing::FaceRay& f : testing::face_rays(48, k == 2)) {
                testing::check_face_hit(
                    f, tree.certified(f.ray, {}),
                    "depth " + std::to_string(depth) + ", " + testing::kFaceScenes[k]);
            }
        }
    }
}

TEST(Octree, SphereTracingWithLocalConstants) {
    const Tape s = tape_of("q = sqrt(x^2 + y^2) - 1\nsqrt(q^2 + z^2) - 0.25");
    const Octree tree(s, kCube, {5, 1u << 20});
    TraceOptions opt;
    opt.epsilon = 1e-9;
    opt.budget = 100000;
    const RayResult r = tree.sphere(Ray{{-3, 0, 0}, {1, 0, 0}, 0, 10}, opt);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t, 1.75);  // never past the root 3 − 1.25
    EXPECT_NEAR(r.t, 1.75, 1e-8);
}

TEST(Octree, SphereTracingGoesOnBySegmentsWhereACellHasNoFiniteBound) {
    // A box (max of planes) united with 1 + exp(−1/x²) ≥ 1, undefined at x = 0 only: the cells
    // holding x = 0 have no finite λ. From (−3, 0, 0) along +x the first zero is the box's face
    // x = 1.5, t = 4.5. Sphere tracing stopped unknown at the first such cell; segment tracing
    // now takes it over there, and the ray reaches the face, never past it.
    const Tape s = tape_of(
        "min(max(max(1.5 - x, x - 2.5), max(abs(y) - 1, abs(z) - 1)), 1 + exp(-1 / (x * x)))");
    const Octree tree(s, kCube, {5, 1u << 20});
    TraceOptions opt;
    opt.seconds = 0;
    const RayResult r = tree.sphere(Ray{{-3, 0, 0}, {1, 0, 0}, 0, 10}, opt);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t, 4.5);
    EXPECT_GE(r.t, 4.5 - 1e-5);
}

TEST(Octree, SphereTracingEndsARunAwayRayAtItsDeadline) {
    // z − 1e-7 + (x − x)·sin(10⁶x) is −1e-7 on the plane z = 0, but (x − x)·sin(10⁶x) keeps 0 in
    // every enclosure over a piece of the ray longer than about 1e-7, and its derivative's
    // enclosure is about ±10⁶ × the piece's length: sphere tracing (64 steps per cell) and then
    // segment tracing crawl in steps below 1e-6 (2·10⁶ evaluations, 3 s, cross a quarter of the
    // cube). With a budget that never stops it, the ray's time does: unknown after about
    // `seconds`; without the deadline it ran for tens of seconds.
    const Tape s = tape_of("z - 1e-7 + (x - x) * sin(1000000 * x)");
    const Octree tree(s, kCube, {5, 1u << 20});
    TraceOptions opt;
    opt.epsilon = 1e-9;
    opt.budget = std::uint64_t{1} << 62;
    opt.seconds = 0.05;
    const auto start = std::chrono::steady_clock::now();
    const RayResult r = tree.sphere(Ray{{-3, 0, 0}, {1, 0, 0}, 0, 10}, opt);
    const double took =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.status, Status::Unknown);
    EXPECT_GE(r.t_lo, 1.0);  // the ray enters the cube at t = 1; nothing is known past t_lo
    EXPECT_LT(took, 1.0);
}

// Every cell the octree marks empty (f > 0) or full (f < 0) keeps that sign at random points,
// in MPFR; every ambiguous leaf's pruned tape equals the full tape at random points of its cell
// (bit for bit in double: pruning drops only branches that lose and folds exact constants).
RC_GTEST_PROP(OctreeProperty, CellsAreClassifiedSoundlyAndPrunedTapesAgree, ()) {
    const Tape t(*testing::gen_dag(10));
    const Octree tree(t, kCube, {3, 4096});
    int checked = 0;
    for (std::uint32_t n = 0; n < tree.node_count() && checked < 40; ++n) {
        const Octree::State st = tree.state(n);
        if (st == Octree::State::Branch) continue;
        if (*rc::gen::inRange(0, 4) != 0) continue;  // a sample of the cells
        ++checked;
        const std::array<Interval, 3>& box = tree.box(n);
        std::array<double, 3> p;
        for (int i = 0; i < 3; ++i) {
            const double u = *rc::gen::inRange(0, 1001) / 1000.0;
            p[i] = box[i].lower() + u * (box[i].upper() - box[i].lower());
            p[i] = std::clamp(p[i], box[i].lower(), box[i].upper());
        }
        if (st == Octree::State::Ambiguous) {
            const double full = expr::eval<double>(t, p);
            const double pruned = expr::eval<double>(tree.leaf_tape(n), p);
            RC_ASSERT((std::isnan(full) && std::isnan(pruned)) || full == pruned);
            continue;
        }
        const MpfrInterval v = expr::eval<MpfrInterval>(
            t, {MpfrInterval(p[0]), MpfrInterval(p[1]), MpfrInterval(p[2])});
        if (v.is_empty()) continue;  // f undefined there: no root either
        if (st == Octree::State::Empty) RC_ASSERT(v.lower() > 0);
        if (st == Octree::State::Full) RC_ASSERT(v.upper() < 0);
    }
}

// Every Hit and Miss of the certified octree (certified-octree) is judged by the independent
// oracle (tests/support/independent_oracle.h), which shares no root logic with the solvers; the
// answers must also agree with the plain solver (overlapping hits, never a hit against a miss).
TEST(OctreeProperty, CertifiedSurvivesTheIndependentOracle) {
    testing::OracleTally tally;
    const bool ok = rc::check("every certified-octree hit and miss survives the oracle", [&] {
        expr::Graph g = *testing::gen_dag(12);
        const Ray first = *testing::gen_ray();
        testing::maybe_through_the_ray(g, first);
        const Tape t(g);
        const Octree tree(t, kCube, {3, 4096});
        solvers::CertifiedOptions o;
        o.budget = 4000;
        for (int k = 0; k < 4; ++k) {
            const Ray ray = k == 0 ? first : *testing::gen_ray();
            const RayResult a = tree.certified(ray, o);
            const testing::Judgement j = tally.judge(t, ray, a);
            RC_LOG() << testing::describe(ray, a) << ": " << j.why << "\n";
            RC_ASSERT(j.verdict != testing::Verdict::Refuted);
            const RayResult b = solvers::certified_first_root(t, ray, o);
            if (a.status == Status::Hit && b.status == Status::Hit) {
                RC_ASSERT(std::max(a.t_lo, b.t_lo) <= std::min(a.t_hi, b.t_hi));
            }
            RC_ASSERT(!(a.status == Status::Hit && b.status == Status::Miss));
            RC_ASSERT(!(a.status == Status::Miss && b.status == Status::Hit));
        }
    });
    EXPECT_TRUE(ok);
    std::printf("%s\n", tally.summary("certified-octree").c_str());
    EXPECT_EQ(tally.refuted, 0u);
    EXPECT_TRUE(tally.unverified_at_most(0.02)) << tally.summary("certified-octree");
}

// Sphere tracing with the cells' λ never reports a hit past the first root inside the bounds.
RC_GTEST_PROP(OctreeProperty, SphereTracingNeverPassesTheFirstRoot, ()) {
    const Tape t(*testing::gen_dag(12));
    const Octree tree(t, kCube, {3, 4096});
    for (int k = 0; k < 4; ++k) {
        Ray ray = *testing::gen_ray();
        // Keep the ray inside the bounds, where the octree sees the scene.
        const Interval in = ray_box(ray, kCube);
        if (in.is_empty()) continue;
        ray.tmin = std::max(ray.tmin, in.upper() < 0 ? 0.0 : std::max(0.0, in.lower()));
        ray.tmax = std::min(ray.tmax, in.upper());
        if (!(ray.tmin < ray.tmax)) continue;
        TraceOptions opt;
        opt.epsilon = 1e-7;
        opt.seconds = 0;
        const RayResult s = tree.sphere(ray, opt);
        const RayResult c = solvers::certified_first_root(t, ray, {20000});
        RC_LOG() << "ray o (" << ray.o[0] << ", " << ray.o[1] << ", " << ray.o[2] << ") d ("
                 << ray.d[0] << ", " << ray.d[1] << ", " << ray.d[2] << ") t [" << ray.tmin << ", "
                 << ray.tmax << "]: sphere " << name(s.status) << " " << s.t << ", certified "
                 << name(c.status) << " [" << c.t_lo << ", " << c.t_hi << "]\n";
        // (A hit where the certified solver proves a miss is sphere tracing's ε-hit: |f|/λ ≤ ε
        // near the surface, or where λ is loose. Past a proven first root, it is a bug.)
        if (s.status == Status::Hit && c.status == Status::Hit) RC_ASSERT(s.t <= c.t_hi);
    }
}

}  // namespace
}  // namespace certray::tracers
