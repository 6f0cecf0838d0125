// tests/tracers/approx_test.cpp — per-cell Taylor models on the octree: the certified `approx`
// agrees with the certified solver (overlapping hits, never a hit against a miss) on the gallery
// scenes and on random DAGs, gives zero wrong answers on the stress suite, and the plain variant's
// errors and the costs of both are measured and printed (not asserted).
#include "tracers/approx.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "expr/load.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/ray_io.h"
#include "tests/support/face_cases.h"
#include "tests/support/generators.h"
#include "tests/support/independent_oracle.h"
#include "tests/support/random_dag.h"
#include "tests/support/ray_checks.h"
#include "tests/support/stress_cases.h"
#include "tracers/octree.h"

namespace certray::tracers {
namespace {

using expr::Tape;

const std::array<Interval, 3> kCube{Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};

std::string scene(const std::string& name) {
    return std::string(CERTRAY_SOURCE_DIR) + "/scenes/" + name;
}

/// Both answers are certified: they may differ in precision or in Unknown, never contradict.
void expect_consistent(const RayResult& a, const RayResult& b, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_FALSE(a.status == Status::Hit && b.status == Status::Miss);
    EXPECT_FALSE(a.status == Status::Miss && b.status == Status::Hit);
    if (a.status == Status::Hit && b.status == Status::Hit) {
        EXPECT_LE(std::max(a.t_lo, b.t_lo), std::min(a.t_hi, b.t_hi));
    }
}

TEST(Approx, SphereRootsMathematicsGives) {
    const Tape s(expr::parse_expr("x*x + y*y + z*z - 1"));
    const Approx approx(s, kCube, {{5, 1u << 20}});
    // From z = −5 towards +z: the sphere at t = 4 (exact).
    const RayResult r = approx.certified(Ray{{0, 0, -5}, {0, 0, 1}, 0, 10}, {});
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, 4.0);
    EXPECT_GE(r.t_hi, 4.0);
    EXPECT_LT(r.t_hi - r.t_lo, 1e-12);
    // Off-centre: x = 0.6, root at z = −0.8, t = 4.2.
    const RayResult r2 = approx.certified(Ray{{0.6, 0, -5}, {0, 0, 1}, 0, 10}, {});
    ASSERT_EQ(r2.status, Status::Hit);
    EXPECT_LE(r2.t_lo, 4.2);
    EXPECT_GE(r2.t_hi, 4.2);
    EXPECT_EQ(approx.certified(Ray{{1.5, 0, -5}, {0, 0, 1}, 0, 10}, {}).status, Status::Miss);
    // A sphere is exact at degree 2: its models have R = [0, 0] up to rounding, so the model
    // proves the root itself.
    const ApproxStats st = approx.stats();
    EXPECT_GT(st.proven, 0u);
    EXPECT_LE(st.fallback, st.proven);  // a root on a cell face is left to the solver
    const RayResult p = approx.plain(Ray{{0.6, 0, -5}, {0, 0, 1}, 0, 10});
    ASSERT_EQ(p.status, Status::Hit);
    EXPECT_NEAR(p.t, 4.2, 1e-9);
}

TEST(Approx, ProvesRootsOnCellFaces) {
    // Boxes with faces at ±0.75, on cell faces at depths ≥ 4: each cell's candidate holds half of
    // the sign change; the window across the face decides it (134 of 138 such rays on the box
    // ended unknown before it).
    for (int depth : {4, 5}) {
        for (std::size_t k = 0; k < testing::kFaceScenes.size(); ++k) {
            const Tape t(expr::parse_expr(testing::kFaceScenes[k]));
            const Approx approx(t, kCube, {{depth, 1u << 20}});
            for (const testing::FaceRay& f : testing::face_rays(48, k == 2)) {
                testing::check_face_hit(
                    f, approx.certified(f.ray, {}),
                    "depth " + std::to_string(depth) + ", " + testing::kFaceScenes[k]);
            }
        }
    }
}

// Models are built lazily by whichever thread meets a cell first: answers do not depend on it.
TEST(Approx, ThreadsBuildTheSameModels) {
    const Tape tape(expr::load_graph_file(scene("blobs.expr")));
    const std::vector<Ray> rays = read_rays_csv_file(scene("rays.csv"));
    const Approx serial(tape, kCube);
    std::vector<RayResult> expect;
    for (const Ray& r : rays) expect.push_back(serial.certified(r, {}));
    const Approx shared(tape, kCube);
    std::vector<RayResult> got(rays.size());
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.emplace_back([&, k] {
            for (std::size_t i = k; i < rays.size(); i += 4) got[i] = shared.certified(rays[i], {});
        });
    for (std::thread& t : threads) t.join();
    testing::expect_same_answers(got, expect);
    EXPECT_EQ(shared.stats().models_built, serial.stats().models_built);
}

struct Measure {
    double seconds = 0;
    std::uint64_t evals = 0;
    int hits = 0, misses = 0, unknown = 0;
    void add(const RayResult& r, double s) {
        seconds += s;
        evals += r.evals.total();
        (r.status == Status::Hit ? hits : r.status == Status::Miss ? misses : unknown)++;
    }
};

template <class F>
RayResult timed(F f, Measure& m) {
    const auto t0 = std::chrono::steady_clock::now();
    const RayResult r = f();
    m.add(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return r;
}

/// The gallery over scenes/rays.csv: consistency with the certified solver, plain-variant errors,
/// costs, remainder widths per level and model memory (printed).
void gallery_scene(const std::string& name) {
    const Tape tape(expr::load_graph_file(scene(name)));
    const std::vector<Ray> rays = read_rays_csv_file(scene("rays.csv"));
    solvers::CertifiedOptions opt;
    const auto b0 = std::chrono::steady_clock::now();
    const Approx approx(tape, kCube);
    approx.build_all();
    const double build =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - b0).count();
    const Octree& tree = approx.octree();
    Measure mc, mo, ma, mp;
    int plain_wrong_status = 0, plain_compared = 0;
    double plain_err_max = 0, plain_err_sum = 0;
    for (const Ray& ray : rays) {
        const RayResult c =
            timed([&] { return solvers::certified_first_root(tape, ray, opt); }, mc);
        const RayResult o = timed([&] { return tree.certified(ray, opt); }, mo);
        const RayResult a = timed([&] { return approx.certified(ray, opt); }, ma);
        const RayResult p = timed([&] { return approx.plain(ray); }, mp);
        expect_consistent(a, c, name + " approx vs certified");
        expect_consistent(a, o, name + " approx vs certified-octree");
        if (c.status == Status::Unknown) continue;
        ++plain_compared;
        if ((p.status == Status::Hit) != (c.status == Status::Hit)) {
            ++plain_wrong_status;
        } else if (c.status == Status::Hit) {
            const double e = std::max({0.0, c.t_lo - p.t, p.t - c.t_hi});
            plain_err_max = std::max(plain_err_max, e);
            plain_err_sum += e;
        }
    }
    const double n = static_cast<double>(rays.size());
    auto line = [&](const char* m, const Measure& x) {
        std::printf("  %-17s %6.1f us/ray %8.1f evals/ray  hit %d miss %d unknown %d\n", m,
                    1e6 * x.seconds / n, x.evals / n, x.hits, x.misses, x.unknown);
    };
    const ApproxStats st = approx.stats();
    std::printf(
        "%s: %zu rays; octree %zu ambiguous leaves; models %llu (deg1 %llu deg2 %llu "
        "deg3 %llu), %.1f KiB, built in %.3f s\n",
        name.c_str(), rays.size(), tree.stats().ambiguous, (unsigned long long)st.models_built,
        (unsigned long long)st.by_degree[1], (unsigned long long)st.by_degree[2],
        (unsigned long long)st.by_degree[3], st.model_bytes / 1024.0, build);
    line("certified", mc);
    line("certified-octree", mo);
    line("approx", ma);
    line("approx-plain", mp);
    std::printf(
        "  approx segments %llu: excluded by model %llu, candidates proven by model %llu, "
        "fallback %llu; full-tape pieces %llu; model ranges %llu\n",
        (unsigned long long)st.segments, (unsigned long long)st.excluded,
        (unsigned long long)st.proven, (unsigned long long)st.fallback,
        (unsigned long long)st.full_tape, (unsigned long long)st.model_ranges);
    std::printf("  approx-plain vs certified: %d/%d wrong hit/miss, |t error| max %.3g mean %.3g\n",
                plain_wrong_status, plain_compared, plain_err_max,
                plain_err_sum / std::max(1, plain_compared - plain_wrong_status));
    // Remainder width / cell size per level: min, median, max.
    std::map<int, std::vector<double>> by_level;
    for (const auto& [node, m] : approx.built_models())
        by_level[m->level].push_back(width(m->r) / m->size);
    for (auto& [level, w] : by_level) {
        std::sort(w.begin(), w.end());
        std::printf("  level %d: %zu models, width(R)/h min %.2e median %.2e max %.2e\n", level,
                    w.size(), w.front(), w[w.size() / 2], w.back());
    }
}

TEST(ApproxGallery, Sphere) { gallery_scene("sphere.expr"); }
TEST(ApproxGallery, Torus) { gallery_scene("torus.expr"); }
TEST(ApproxGallery, Blobs) { gallery_scene("blobs.expr"); }
TEST(ApproxGallery, Csg) { gallery_scene("csg.expr"); }
TEST(ApproxGallery, Gyroid) { gallery_scene("gyroid.expr"); }

// ---- the stress suite (format and rules of tests/solvers/stress_test.cpp) ---------------------

using Case = testing::StressCase;

TEST(ApproxStress, NeverWrong) {
    const std::vector<Case> cases = testing::read_stress_cases();
    ASSERT_GE(cases.size(), 25u);
    std::map<std::string, std::unique_ptr<Tape>> tapes;
    std::map<std::string, std::unique_ptr<Approx>> approx;
    int hits = 0, certified_hits = 0, plain_wrong = 0;
    for (const Case& c : cases) {
        if (!tapes.count(c.scene)) {
            tapes[c.scene] =
                std::make_unique<Tape>(expr::load_graph_file(scene("stress/" + c.scene)));
            // The 10⁴-primitive CSG: a shallower tree (building depth 5 over 50,000 instructions
            // takes seconds; the answers' correctness does not depend on the depth).
            ApproxOptions o;
            if (c.scene == "deep_csg.expr") o.octree.max_depth = 3;
            approx[c.scene] = std::make_unique<Approx>(*tapes[c.scene], kCube, o);
        }
        const RayResult r = approx[c.scene]->certified(c.ray, {});
        testing::check_stress_case(c, r, false);
        hits += r.status == Status::Hit;
        certified_hits +=
            solvers::certified_first_root(*tapes[c.scene], c.ray).status == Status::Hit;
        const RayResult p = approx[c.scene]->plain(c.ray);
        const bool truth_hit = c.expect == "hit";
        const bool plain_ok =
            truth_hit
                ? p.status == Status::Hit && p.t >= c.root_lo - 1e-6 * std::abs(c.root_lo) - 1e-9 &&
                      p.t <= c.root_hi + 1e-6 * std::abs(c.root_hi) + 1e-9
            : (c.expect == "miss" || c.expect == "nohit") ? p.status != Status::Hit
                                                          : true;
        plain_wrong += !plain_ok;
    }
    std::printf(
        "stress: %zu cases; approx proves %d hits (certified solver %d); approx-plain wrong "
        "on %d (outside [-2,2]^3 it sees nothing)\n",
        cases.size(), hits, certified_hits, plain_wrong);
}

// ---- random DAGs ------------------------------------------------------------------------------

// Every Hit and Miss of Approx::certified (certified-taylor) on random DAGs is judged by the
// independent oracle (tests/support/independent_oracle.h); the answers must also agree with the
// certified solver (overlapping hits, never a hit against a miss).
TEST(ApproxProperty, CertifiedSurvivesTheIndependentOracle) {
    testing::OracleTally tally;
    const bool ok = rc::check("every certified-taylor hit and miss survives the oracle", [&] {
        expr::Graph g = *testing::gen_dag(12);
        const Ray first = *testing::gen_ray(100, 50);
        testing::maybe_through_the_ray(g, first);
        const Tape t(g);
        const Approx approx(t, kCube, {{3, 4096}});
        solvers::CertifiedOptions o;
        o.budget = 4000;
        int agree = 0;
        for (int k = 0; k < 4; ++k) {
            const Ray ray = k == 0 ? first : *testing::gen_ray(100, 50);
            const RayResult a = approx.certified(ray, o);
            const testing::Judgement j = tally.judge(t, ray, a);
            RC_LOG() << testing::describe(ray, a) << ": " << j.why << "\n";
            RC_ASSERT(j.verdict != testing::Verdict::Refuted);
            const RayResult b = solvers::certified_first_root(t, ray, o);
            agree += a.status == b.status;
            if (a.status == Status::Hit && b.status == Status::Hit)
                RC_ASSERT(std::max(a.t_lo, b.t_lo) <= std::min(a.t_hi, b.t_hi));
            RC_ASSERT(!(a.status == Status::Hit && b.status == Status::Miss));
            RC_ASSERT(!(a.status == Status::Miss && b.status == Status::Hit));
        }
        RC_TAG(agree, "of 4 statuses equal");
    });
    EXPECT_TRUE(ok);
    std::printf("%s\n", tally.summary("certified-taylor (random DAGs)").c_str());
    EXPECT_EQ(tally.refuted, 0u);
    EXPECT_TRUE(tally.unverified_at_most(0.02)) << tally.summary("certified-taylor");
}

/// Random smooth blobs (a sphere with a sinusoidal bump), rays aimed near the centre: most rays
/// hit, so the model's proofs and candidates are exercised; each Hit and Miss judged by the
/// independent oracle and compared with the certified solver.
TEST(ApproxProperty, SmoothScenesSurviveTheIndependentOracle) {
    testing::OracleTally tally;
    const bool ok = rc::check("certified-taylor on smooth blobs survives the oracle", [&] {
        auto frac = [](int lo, int hi, double s) { return *rc::gen::inRange(lo, hi) / s; };
        const double cx = frac(-50, 50, 100), cy = frac(-50, 50, 100), cz = frac(-50, 50, 100);
        const double r = frac(20, 120, 100), e = frac(0, 30, 100), k = frac(1, 60, 10);
        const std::string text = "(x - " + std::to_string(cx) + ")^2 + (y - " + std::to_string(cy) +
                                 ")^2 + (z - " + std::to_string(cz) + ")^2 - " +
                                 std::to_string(r * r) + " + " + std::to_string(e) + " * sin(" +
                                 std::to_string(k) + " * x) * cos(" + std::to_string(k) + " * y)";
        const Tape t(expr::parse_expr(text));
        const Approx approx(t, kCube, {{4, 1u << 16}});
        int hits = 0;
        for (int n = 0; n < 4; ++n) {
            Ray ray;
            ray.o = {frac(-400, 400, 100), frac(-400, 400, 100), -5.0};
            ray.d = {cx + r * frac(-70, 70, 100) - ray.o[0], cy + r * frac(-70, 70, 100) - ray.o[1],
                     cz - ray.o[2]};
            ray.tmin = 0;
            ray.tmax = 2;
            const RayResult a = approx.certified(ray, {});
            const testing::Judgement j = tally.judge(t, ray, a);
            RC_LOG() << testing::describe(ray, a) << ": " << j.why << "\n";
            RC_ASSERT(j.verdict != testing::Verdict::Refuted);
            const RayResult b = solvers::certified_first_root(t, ray, {});
            hits += a.status == Status::Hit;
            if (a.status == Status::Hit && b.status == Status::Hit)
                RC_ASSERT(std::max(a.t_lo, b.t_lo) <= std::min(a.t_hi, b.t_hi));
            RC_ASSERT(!(a.status == Status::Hit && b.status == Status::Miss));
            RC_ASSERT(!(a.status == Status::Miss && b.status == Status::Hit));
        }
        const ApproxStats st = approx.stats();
        RC_TAG(hits, "hits of 4", st.proven > 0 ? "model proved a root" : "no model proof");
    });
    EXPECT_TRUE(ok);
    std::printf("%s\n", tally.summary("certified-taylor (smooth blobs)").c_str());
    EXPECT_EQ(tally.refuted, 0u);
    EXPECT_TRUE(tally.unverified_at_most(0.02)) << tally.summary("certified-taylor");
}

}  // namespace
}  // namespace certray::tracers
