// tests/tracers/segment_trace_test.cpp — segment tracing (tracers/segment_trace.h): the ray jet's
// enclosures against 256-bit MPFR evaluations of g and g′ at points of the segment (value,
// derivative, and the second-order Taylor enclosure wherever the jet claims g′ smooth), the kink
// rules on the blob falloff, the never-past-the-first-root guarantee against the certified solver
// on random DAGs (every variant), a step-doubling mutant that the same checks catch, a smooth thin
// shell, and rays of the Segment Tracing particle scene against the certified first root.
#include "tracers/segment_trace.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>

#include "expr/eval.h"
#include "expr/parser.h"
#include "expr/scene_import.h"
#include "expr/tape.h"
#include "interval/dual.h"
#include "interval/mpfr_interval.h"
#include "solvers/certified.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"
#include "tests/support/random_dag.h"
#include "tracers/camera.h"
#include "tracers/region_tapes.h"

namespace certray::tracers {
namespace {

using expr::Tape;
using M1 = Dual<MpfrInterval, 1>;
constexpr double kInf = std::numeric_limits<double>::infinity();

Tape tape_of(const std::string& text) { return Tape(expr::parse_expr(text)); }

/// printf into a std::string (and no "literal" + std::string&&, on which g++ 12 warns falsely).
template <class... A>
std::string fmt(const char* f, A... a) {
    char buf[512];
    std::snprintf(buf, sizeof buf, f, a...);
    return buf;
}

/// " - max(1 - |p - c|²/2.25², 0)³": one blob of the particle scene's falloff.
std::string minus_blob(double cx, double cy, double cz) {
    return fmt(" - max(1 - ((x - %.17g)^2 + (y - %.17g)^2 + (z - %.17g)^2) / 5.0625, 0)^3", cx, cy,
               cz);
}

/// g(u) and g′(u) at the point o + u·d, computed exactly (2,200 bits hold any sum of products of
/// doubles), then in intervals of that precision.
M1 exact_jet(const Tape& t, const Ray& ray, double u) {
    const Precision exact{2200};
    std::array<M1, 3> p;
    for (int i = 0; i < 3; ++i) {
        const MpfrInterval x =
            MpfrInterval(ray.o[i], exact) + MpfrInterval(u, exact) * MpfrInterval(ray.d[i], exact);
        p[i] = M1(x, {MpfrInterval(ray.d[i])});
    }
    return expr::eval<M1>(t, p);
}

bool usable(const MpfrInterval& x) {
    return !x.is_empty() && x.defined && std::isfinite(x.lower()) && std::isfinite(x.upper());
}

/// The true derivative lies in the oracle's enclosure `exact`; where that is (nearly) a point, it
/// must lie in [lo, hi]. Where it is wide — Dual<MpfrInterval> joins both branches of a min/max
/// whose operands it cannot order through their double-rounded bounds — [lo, hi] must meet it.
bool derivative_ok(const Interval& ours, const MpfrInterval& exact) {
    const double w = exact.upper() - exact.lower();
    if (w <= 1e-9 * std::max(std::fabs(exact.lower()), std::fabs(exact.upper()))) {
        return testing::encloses(ours.lower(), ours.upper(), exact);
    }
    return ours.lower() <= exact.upper() && exact.lower() <= ours.upper();
}

// ---- the jet against MPFR ------------------------------------------------------------------

RC_GTEST_PROP(SegmentModel, EnclosesValueDerivativeAndTaylorForm, ()) {
    const Tape t(*testing::gen_dag(16));
    Ray ray = *testing::gen_ray(100, 80);
    const double t0 = *testing::gen_point_in(ray.tmin, ray.tmax);
    const double len = *rc::gen::element(1e-6, 1e-3, 0.05, 0.5, 2.0, 8.0);
    const double t1 = t0 + len;
    const SegmentModel m = segment_model(t, ray, t0, t1);
    // At t: g(t) ∈ g0 and, where g is differentiable, g′(t) ∈ g1.
    const M1 at = exact_jet(t, ray, t0);
    if (usable(at.a)) {
        RC_ASSERT(testing::encloses(m.g0.lower(), m.g0.upper(), at.a));
        if (usable(at.v[0])) RC_ASSERT(derivative_ok(m.g1, at.v[0]));
    }
    for (int k = 0; k < 4; ++k) {
        const double u = *testing::gen_point_in(t0, t1);
        const M1 e = exact_jet(t, ray, u);
        if (!usable(e.a)) continue;
        RC_ASSERT(testing::encloses(m.g.lower(), m.g.upper(), e.a));
        if (u > t0 && u < t1 && usable(e.v[0])) {
            RC_ASSERT(derivative_ok(m.dg, e.v[0]));
        }
        if (m.smooth && m.g.defined && !m.g.is_empty()) {
            // g(t + τ) ∈ g(t) + τ·g′(t) + τ²/2·G″ for τ = u − t.
            const Interval tau = Interval(u) - Interval(t0);
            const Interval taylor = m.g0 + tau * m.g1 + square(tau) * m.ddg / Interval(2.0);
            RC_LOG() << fmt("u %.17g taylor [%.17g, %.17g]\n", u, taylor.lower(), taylor.upper())
                     << testing::describe(e.a) << "\n";
            RC_ASSERT(testing::encloses(taylor.lower(), taylor.upper(), e.a));
        }
    }
}

/// Checks the model of `t` on [t0, t0 + len] against MPFR at `samples` points: value always,
/// the Taylor form where the model claims smoothness.
void check_model(const Tape& t, const Ray& ray, double t0, double len, int samples) {
    const double t1 = t0 + len;
    const SegmentModel m = segment_model(t, ray, t0, t1);
    for (int k = 0; k < samples; ++k) {
        const double u = *testing::gen_point_in(t0, t1);
        const M1 e = exact_jet(t, ray, u);
        if (!usable(e.a)) continue;
        RC_ASSERT(testing::encloses(m.g.lower(), m.g.upper(), e.a));
        if (m.smooth && m.g.defined && !m.g.is_empty()) {
            const Interval tau = Interval(u) - Interval(t0);
            const Interval taylor = m.g0 + tau * m.g1 + square(tau) * m.ddg / Interval(2.0);
            RC_ASSERT(testing::encloses(taylor.lower(), taylor.upper(), e.a));
        }
    }
}

RC_GTEST_PROP(SegmentModel, KinkRulesOnRampPowers, ()) {
    // Σ wₖ·op(max(qₖ, 0))ⁿ with qₖ a random quadratic and n ∈ 1..3, op ∈ {id, abs-shifted, min
    // with a plane}: kinks that a power ≥ 2 of a zero-valued ramp kills, and kinks that survive.
    const int terms = *rc::gen::inRange(1, 4);
    auto c = [] { return *rc::gen::inRange(-8, 9) / 4.0; };
    std::string text = fmt("%g", *rc::gen::inRange(-4, 5) / 4.0);
    for (int k = 0; k < terms; ++k) {
        const std::string q =
            fmt("(%g + %g*x + %g*y + %g*z - %g*(x^2 + y^2 + z^2))", c(), c(), c(), c(), c());
        std::string ramp;
        switch (*rc::gen::inRange(0, 4)) {
            case 0:
                ramp = fmt("max(%s, 0)", q.c_str());
                break;
            case 1:
                ramp = fmt("max(0, %s)", q.c_str());
                break;
            case 2:
                ramp = fmt("abs(%s)", q.c_str());
                break;
            default:
                ramp = fmt("min(%s, %g + x)", q.c_str(), c());
                break;
        }
        text += fmt(" + %g * %s^%d", c(), ramp.c_str(), *rc::gen::inRange(1, 4));
    }
    RC_LOG() << text << "\n";
    const Tape t = tape_of(text);
    const Ray ray = *testing::gen_ray(100, 80);
    const double t0 = *testing::gen_point_in(ray.tmin, ray.tmax);
    check_model(t, ray, t0, *rc::gen::element(1e-3, 0.1, 0.5, 2.0), 6);
}

TEST(SegmentModel, BlobFalloffIsSmoothAcrossItsSupport) {
    // 0.5 − max(1 − r²/R², 0)³: the kink of max at r = R is multiplied by 3·0² = 0 in the
    // derivative of the cube, so g is C¹ (C² even) on a segment crossing r = R; with the first
    // power it is not (g′ jumps by 2r·d/R² there).
    const Ray ray{{-4, 0.3, 0}, {1, 0, 0}, 0, 8};
    const Tape cube = tape_of("0.5 - max(1 - (x^2 + y^2 + z^2) / 5.0625, 0)^3");
    const Tape first = tape_of("0.5 - max(1 - (x^2 + y^2 + z^2) / 5.0625, 0)");
    // x from −3 to −1: r crosses R = 2.25 near x = −2.23.
    EXPECT_TRUE(segment_model(cube, ray, 1, 3).smooth);
    EXPECT_FALSE(segment_model(first, ray, 1, 3).smooth);
    // Away from the boundary (x ∈ [−1, 1], inside the support) both are smooth.
    EXPECT_TRUE(segment_model(first, ray, 3, 5).smooth);
    // A kink of the output itself stays a kink: 0.5 − max(x, 0) at x = 0.
    const Tape ramp = tape_of("0.5 - max(x, 0)");
    EXPECT_FALSE(segment_model(ramp, ray, 3, 5).smooth);
    // Squared, the ramp's kink is killed only if its value is 0 there: max(x, 0)² is C¹,
    // (0.5 − max(x, 0))² is not (its derivative jumps by 2·0.5·1 at x = 0).
    EXPECT_TRUE(segment_model(tape_of("max(x, 0)^2 - 0.25"), ray, 3, 5).smooth);
    EXPECT_FALSE(segment_model(tape_of("(0.5 - max(x, 0))^2"), ray, 3, 5).smooth);
}

// ---- the tracer against the certified solver ------------------------------------------------

/// Every named variant (tracers/segment_trace.h): each must keep the guarantee.
std::vector<SegmentOptions> variants() { return segment_presets(); }

/// The presets, and the default with `regions` and a short first segment, as the registry runs it.
std::vector<SegmentOptions> variants_and(const RegionTapes* regions) {
    std::vector<SegmentOptions> all = variants();
    all.push_back({});
    all.back().name = "regions";
    all.back().regions = regions;
    all.back().first_length = 0.1;  // the registry's: a first segment of a cell's size
    return all;
}

/// Region tapes of t over the ray's segment box widened by 1 (SegmentOptions::regions).
std::unique_ptr<RegionTapes> regions_along(const Tape& t, const Ray& ray) {
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) {
        const double a = ray.o[i] + ray.tmin * ray.d[i], b = ray.o[i] + ray.tmax * ray.d[i];
        box[i] = Interval(std::min(a, b) - 1, std::max(a, b) + 1);
    }
    return std::make_unique<RegionTapes>(t, box);
}

/// Against the certified answer c: a traced hit is never past the certified first root's
/// enclosure; a traced hit with a bracket (t_hi > t_lo: a zero proven in it) is never on a
/// certified miss and has the certified first root at or before t_hi (an approximate hit may be
/// on a certified miss: the surface within epsilon, outside the ray or touching it); a traced miss
/// never contradicts a certified hit. Returns false on a violation (for the mutant).
bool agrees(const RayResult& c, const RayResult& traced) {
    if (traced.status == Status::Hit) {
        const bool bracket = traced.t_hi > traced.t_lo;
        if (bracket && c.status == Status::Miss) return false;
        if (c.status == Status::Hit && traced.t > c.t_hi) return false;
        if (bracket && c.status == Status::Hit && c.t_lo > traced.t_hi) return false;
    }
    if (traced.status == Status::Miss && c.status == Status::Hit) return false;
    return true;
}

/// The ray and both answers, for the log of a failing case.
std::string describe(const SegmentOptions& so, const Ray& ray, const RayResult& r,
                     const RayResult& c) {
    return fmt(
        "%s: o (%.17g, %.17g, %.17g) d (%.17g, %.17g, %.17g) t [%.17g, %.17g] | %s "
        "[%.17g, %.17g] t %.17g | certified %s [%.17g, %.17g]\n",
        so.name, ray.o[0], ray.o[1], ray.o[2], ray.d[0], ray.d[1], ray.d[2], ray.tmin, ray.tmax,
        name(r.status).data(), r.t_lo, r.t_hi, r.t, name(c.status).data(), c.t_lo, c.t_hi);
}

RC_GTEST_PROP(SegmentTrace, RandomDagsNeverPastFirstRoot, ()) {
    expr::Graph g = *testing::gen_dag(12);
    const Ray ray = *testing::gen_ray(100, 80);
    if (*rc::gen::arbitrary<bool>()) {
        // f − f(o + u·d) for a u of the ray: a root where the ray meets that level set.
        const double u = *testing::gen_point_in(ray.tmin, ray.tmax);
        const double c = expr::eval<double>(
            Tape(g), {ray.o[0] + u * ray.d[0], ray.o[1] + u * ray.d[1], ray.o[2] + u * ray.d[2]});
        if (std::isfinite(c)) g.set_output(g.binary(expr::Op::Sub, g.output(), g.constant(c)));
    }
    const Tape t(g);
    TraceOptions o;
    o.budget = 500;
    o.epsilon = *rc::gen::element(1e-6, 1e-3);
    const RayResult c = solvers::certified_first_root(t, ray);
    const auto regions = regions_along(t, ray);
    for (const SegmentOptions& so : variants_and(regions.get())) {
        const RayResult r = segment_trace(t, ray, o, so);
        RC_LOG() << describe(so, ray, r, c);
        RC_ASSERT(r.evals.total() <= o.budget);
        RC_ASSERT(agrees(c, r));
    }
}

RC_GTEST_PROP(SegmentTrace, BlobSumsNeverPastFirstRoot, ()) {
    // Small random particle scenes (the falloff of the authors' scene): smooth, with kinks at
    // every support boundary that the switch cuts and the kink rules handle.
    const int n = *rc::gen::inRange(1, 8);
    std::string text = "0.5";
    for (int k = 0; k < n; ++k) {
        const double c[3] = {*rc::gen::inRange(-30, 30) / 10.0, *rc::gen::inRange(-30, 30) / 10.0,
                             *rc::gen::inRange(-30, 30) / 10.0};
        text += minus_blob(c[0], c[1], c[2]);
    }
    const Tape t = tape_of(text);
    Ray ray = *testing::gen_ray(100, 80);
    ray.tmax *= 3;
    TraceOptions o;
    o.budget = 500;
    const RayResult c = solvers::certified_first_root(t, ray);
    const auto regions = regions_along(t, ray);
    for (const SegmentOptions& so : variants_and(regions.get())) {
        const RayResult r = segment_trace(t, ray, o, so);
        RC_LOG() << describe(so, ray, r, c);
        RC_ASSERT(agrees(c, r));
    }
}

TEST(SegmentTrace, DoubledStepMutantIsCaught) {
    // The same checks must fail for a tracer whose safe steps are doubled (≙ λ/2): on random
    // blob scenes, some hit lands past the certified first root; the real tracer never does.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    SegmentOptions mutant;
    mutant.step_scale = 2;
    int caught = 0, rays = 0;
    for (int k = 0; k < 60; ++k) {
        std::string text = "0.5";
        for (int b = 0; b < 3; ++b) {
            const double cx = u(rng), cy = u(rng), cz = u(rng);
            text += minus_blob(cx, cy, cz);
        }
        const Tape t = tape_of(text);
        const Ray ray{{u(rng), -8, u(rng)}, {0.05 * u(rng), 1, 0.05 * u(rng)}, 0, 16};
        const TraceOptions o;
        const RayResult c = solvers::certified_first_root(t, ray);
        EXPECT_TRUE(agrees(c, segment_trace(t, ray, o))) << text;
        caught += !agrees(c, segment_trace(t, ray, o, mutant));
        ++rays;
    }
    EXPECT_GT(caught, 0) << "the doubled-step mutant went unnoticed on " << rays << " rays";
}

TEST(SegmentTrace, TimeBudgetEndsARayUnknown) {
    // sin(40x) + 1.5 has no zero; with no time left the tracer stops at once, unknown, never a hit;
    // with no limit (seconds = 0) it proves the miss.
    const expr::Tape tape(expr::parse_expr("sin(40 * x) + 1.5"));
    const Ray ray{{0, 0, 0}, {1, 0, 0}, 0, 50};
    TraceOptions opt;
    opt.seconds = 1e-12;
    const RayResult r = segment_trace(tape, ray, opt);
    EXPECT_EQ(r.status, Status::Unknown);
    EXPECT_EQ(r.t_lo, 0.0);
    opt.seconds = 0;
    EXPECT_EQ(segment_trace(tape, ray, opt).status, Status::Miss);
}

TEST(SegmentTrace, PassesAPoleWhereTheFieldStaysBounded) {
    // A box (max of four planes) united (min) with 1 + exp(−1/x²), which is ≥ 1 where it is
    // defined and undefined at x = 0 only (1/0), with its enclosures bounded around that point: as
    // in Fidget's bear. From (−1, 0, 0) along +x the first zero is the box's face x = 1.5, t = 2.5
    // (the second term is ≥ 1 > 0). Segment tracing passes the pole by the value of g over a
    // segment holding it (0 ∉ G(T): no zero there, defined or not), as the certified solver does;
    // it stopped there, unknown at t = 1.
    const Tape t = tape_of(
        "min(max(max(1.5 - x, x - 2.5), max(abs(y) - 1, abs(z) - 1)), 1 + exp(-1 / (x * x)))");
    const Ray ray{{-1, 0, 0}, {1, 0, 0}, 0, 4};
    for (const SegmentOptions& so : variants()) {
        TraceOptions o;
        o.seconds = 0;
        const RayResult r = segment_trace(t, ray, o, so);
        ASSERT_EQ(r.status, Status::Hit) << so.name;
        EXPECT_LE(r.t, 2.5) << so.name;  // never past the first root
        EXPECT_GE(r.t, 2.5 - o.epsilon) << so.name;
        EXPECT_LT(r.evals.total(), 100u) << so.name;
    }
}

TEST(SegmentTrace, ASwitchAtTheEndOfACutSegmentStillMovesOn) {
    // 5 + min(x, 1) + max(x, 1)/2 ≥ 5.5 > 0 for x ≥ 0: no zero on [0, 3]. Both switches sit at
    // x = 1: the first cuts the segment there, the second is then seen at its very end, and the
    // next segment had length 0 (next_factor × 0): the tracer spun at t = 1 until its budget ran
    // out (unknown) instead of proving the miss.
    const Tape t = tape_of("5 + min(x, 1) + max(x, 1) / 2");
    for (const double dy : {0.0, 1e-3}) {
        const Ray ray{{0, 0, 0}, {1, dy, 0}, 0, 3};
        TraceOptions o;
        o.seconds = 0;
        o.budget = 2000;
        const RayResult r = segment_trace(t, ray, o);
        EXPECT_EQ(r.status, Status::Miss) << dy;
        EXPECT_LT(r.evals.total(), 50u) << dy;
    }
}

TEST(SegmentTrace, SmoothThinShell) {
    // (|p|² − 1)² − 1e-8 < 0 only for |p|² ∈ (1 − 1e-4, 1 + 1e-4): a shell about 1e-4 thick.
    // From (0, 0, −3) along +z the first root is |p|² = 1 + 1e-4: t = 3 − √1.0001.
    const Tape t = tape_of("(x^2 + y^2 + z^2 - 1)^2 - 1e-8");
    const Ray ray{{0, 0, -3}, {0, 0, 1}, 0, 6};
    const double root = 3 - std::sqrt(1.0001);
    for (const SegmentOptions& so : variants()) {
        TraceOptions o;
        const RayResult r = segment_trace(t, ray, o, so);
        ASSERT_EQ(r.status, Status::Hit) << so.name;
        EXPECT_LE(r.t, root + 1e-15) << so.name;
        EXPECT_GE(r.t, root - o.epsilon) << so.name;
        if (r.t_hi > r.t_lo) {
            EXPECT_GE(r.t_hi, root - 1e-15) << so.name;
        }
    }
}

TEST(SegmentTrace, ProvenBracketHoldsTheRoot) {
    // The unit sphere's first root along +z from (0, 0.3, −3) is t = 3 − √(1 − 0.09); the
    // smooth second-order bounds prove it in a bracket narrower than epsilon.
    const Tape t = tape_of("x^2 + y^2 + z^2 - 1");
    const Ray ray{{0, 0.3, -3}, {0, 0, 1}, 0, 6};
    const double root = 3 - std::sqrt(0.91);
    const TraceOptions o;
    const RayResult r = segment_trace(t, ray, o);
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LT(r.t_lo, r.t_hi);
    EXPECT_LE(r.t_lo, root + 1e-15);  // root: rounded to nearest, so within one ulp
    EXPECT_GE(r.t_hi, root - 1e-15);
    EXPECT_LE(r.t_hi - r.t_lo, o.epsilon);
}

TEST(SegmentTrace, FidgetOpsNeverPastTheCertifiedFirstRoot) {
    // The smooth new ops go through the jet's chain rules, the others through flat or untracked
    // jets: either way no reported hit lies past the certified first root.
    const char* scenes[] = {
        "atan(3 * z) - 0.5", "tan(0.4 * z) - 1",          "asin(0.3 * z) - 0.2",
        "acos(0.3 * z) - 1", "floor(z) + z - 1.5",        "mod(z, 1.5) - 1",
        "atan2(z, 1) - 0.7", "and(compare(z, 0), z - 1)", "or(not(floor(z)), z - 2) - 0.5"};
    for (const char* text : scenes) {
        const Tape t = tape_of(text);
        const Ray ray{{0.1, 0.2, -2.3}, {0, 0, 1}, 0, 6};
        const RayResult ref = solvers::certified_first_root(t, ray);
        for (const SegmentOptions& so : variants()) {
            const RayResult r = segment_trace(t, ray, TraceOptions{}, so);
            if (ref.status == Status::Hit && r.status == Status::Hit) {
                EXPECT_LE(r.t, ref.t_hi + 1e-12) << text << " " << so.name;
            }
            if (ref.status == Status::Hit) {
                EXPECT_NE(r.status, Status::Miss) << text << " " << so.name;
            }
        }
    }
}

// ---- the particle scene ----------------------------------------------------------------------

TEST(SegmentTrace, ParticleSceneAgreesWithCertifiedRoots) {
    const Tape t(expr::import_particles_file(CERTRAY_SOURCE_DIR "/scenes/particles.txt"));
    Camera cam;
    cam.eye = {0, -80, 0};
    cam.target = {0, 0, 0};
    cam.up = {0, 0, 1};
    cam.fov_degrees = 35;
    const CameraFrame frame(cam, 100, 100);
    TraceOptions o;
    o.epsilon = 1e-6;
    int hits = 0, undecided = 0;
    std::uint64_t evals = 0, rays = 0;
    for (unsigned j = 5; j < 100; j += 10) {
        for (unsigned i = 5; i < 100; i += 10) {
            Ray ray = frame.ray(i + 0.5, j + 0.5);
            ray.tmax = 200;
            const RayResult r = segment_trace(t, ray, o);
            const RayResult c = solvers::certified_first_root(t, ray);
            evals += r.evals.total();
            ++rays;
            ASSERT_NE(r.status, Status::Unknown) << i << "," << j;
            if (c.status == Status::Unknown) {  // tangency: nothing to compare with
                ++undecided;
                continue;
            }
            ASSERT_EQ(r.status, c.status) << i << "," << j;
            if (c.status != Status::Hit) continue;
            ++hits;
            // Never past the first root, and within epsilon (‖d‖ = 1) before it.
            EXPECT_LE(r.t, c.t_hi) << i << "," << j;
            EXPECT_GE(r.t, c.t_lo - o.epsilon) << i << "," << j;
        }
    }
    EXPECT_GT(hits, 20);
    EXPECT_LT(undecided, 5);
    // The budget counts every evaluation, the pruning sweep included.
    Ray ray = frame.ray(50.5, 50.5);
    ray.tmax = 200;
    for (std::uint64_t budget = 1; budget < 6; ++budget) {
        TraceOptions small = o;
        small.budget = budget;
        const RayResult r = segment_trace(t, ray, small);
        EXPECT_LE(r.evals.total(), budget);
        EXPECT_NE(r.status, Status::Miss) << budget;  // this ray hits the scene
    }
    // The point of segment tracing: few evaluations per ray (sphere tracing needs thousands).
    EXPECT_LT(static_cast<double>(evals) / static_cast<double>(rays), 20.0);
}

}  // namespace
}  // namespace certray::tracers
