// tests/solvers/solid_test.cpp — the certified first entry into {f < 0} against entries that
// mathematics gives: spheres, a box SDF, scenes with an f ≡ 0 slab before the solid (where the
// zero-surface solver stops), undefined regions, tangents, the budget, degenerate rays; properties
// on random DAGs checked in MPFR and against the MPFR reference; the Fidget models of
// tests/data/models on a grid of rays (unknown counts against the zero-surface solver).
#include "solvers/solid.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "expr/vm_import.h"
#include "interval/mpfr_interval.h"
#include "solvers/certified.h"
#include "tests/support/generators.h"
#include "tests/support/random_dag.h"
#include "tests/support/ray_checks.h"

namespace certray::solvers {
namespace {

using expr::Tape;
constexpr double kInf = std::numeric_limits<double>::infinity();

using testing::tape_of;
using testing::ulps;

RayResult solid(const Tape& t, std::array<double, 3> o, std::array<double, 3> d, double tmin = 0,
                double tmax = kInf) {
    return solid_first_entry(t, Ray{o, d, tmin, tmax});
}
RayResult zero(const Tape& t, std::array<double, 3> o, std::array<double, 3> d, double tmin = 0,
               double tmax = kInf) {
    return certified_first_root(t, Ray{o, d, tmin, tmax});
}

void expect_entry_at(const RayResult& r, double entry, double max_ulps = 4) {
    testing::expect_hit_at(r, entry, max_ulps);
}

/// g at the point t in MPFR at `bits` bits.
MpfrInterval g_mpfr(const Tape& tape, const Ray& ray, double lo, double hi,
                    mpfr_prec_t bits = 512) {
    std::array<MpfrInterval, 3> p;
    const MpfrInterval t(lo, hi, Precision{bits});
    for (int i = 0; i < 3; ++i) {
        p[i] =
            MpfrInterval(ray.o[i], Precision{bits}) + t * MpfrInterval(ray.d[i], Precision{bits});
    }
    return expr::eval<MpfrInterval>(tape, p);
}

TEST(Solid, SphereEntryIsTight) {
    for (const char* f : {"x^2 + y^2 + z^2 - 1", "sqrt(x^2 + y^2 + z^2) - 1"}) {
        SCOPED_TRACE(f);
        const Tape s = tape_of(f);
        const RayResult r = solid(s, {0, 0, -3}, {0, 0, 1});
        expect_entry_at(r, 2.0);
        EXPECT_LE(r.evals.total(), 400u);
        expect_entry_at(solid(s, {0, 0, -3}, {0, 0, 2}), 1.0);           // scaled direction
        expect_entry_at(solid(s, {0, 0, -3}, {0, 0, 1}, 0, 7), 2.0);     // bounded segment
        EXPECT_EQ(solid(s, {0, 5, 0}, {1, 0, 0}).status, Status::Miss);  // clear miss
        EXPECT_EQ(solid(s, {0, 0, -3}, {0, 0, 1}, 0, 1.5).status, Status::Miss);  // stops short
        EXPECT_EQ(solid(s, {0, 0, -3}, {0, 0, -1}).status, Status::Miss);  // away, tmax = +inf
    }
}

TEST(Solid, HitWidthsStopTheNarrowingEarlyAndKeepTheEntry) {
    // The ball of radius 1 entered from (0, 0, -3) along +z at t = 2, and the ball of radius 2
    // centred at z = 10 along the same ray at t = 11 (after 2, so a second, far case): the entry
    // stays inside the enclosure, whose width the options bound.
    const std::pair<const char*, double> cases[] = {{"x^2 + y^2 + z^2 - 1", 2.0},
                                                    {"x^2 + y^2 + (z - 10)^2 - 4", 11.0}};
    for (const auto& [f, entry] : cases) {
        SCOPED_TRACE(f);
        const Tape s = tape_of(f);
        const Ray ray{{0, 0, -3}, {0, 0, 1}, 0, 30};
        const RayResult tight = solid_first_entry(s, ray);
        expect_entry_at(tight, entry);
        for (const auto& [relative, absolute] :
             {std::pair{1e-3, 0.0}, std::pair{0.0, 1e-3}, std::pair{1e-6, 0.05}}) {
            SolidOptions o;
            o.hit_width = relative;
            o.hit_width_absolute = absolute;
            const RayResult r = solid_first_entry(s, ray, o);
            ASSERT_EQ(r.status, Status::Hit);
            EXPECT_LE(r.t_lo, entry);
            EXPECT_GE(r.t_hi, entry);
            EXPECT_LE(r.t_hi - r.t_lo, std::max(relative * r.t_hi, absolute));
            EXPECT_LT(r.evals.total(), tight.evals.total());  // stopped before the ulps
        }
    }
}

TEST(Solid, StartsInside) {
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    const RayResult r = solid(s, {0, 0, 0}, {1, 0, 0});
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_EQ(r.t_lo, 0.0);
    EXPECT_EQ(r.t_hi, 0.0);
    // From inside the second crossing of the same ray: the entry is the start.
    const RayResult s2 = solid(s, {0, 0, -3}, {0, 0, 1}, 2.5, 10);
    ASSERT_EQ(s2.status, Status::Hit);
    EXPECT_EQ(s2.t_lo, 2.5);
    EXPECT_EQ(s2.t_hi, 2.5);
}

TEST(Solid, BoxSdf) {
    const Tape box = tape_of("max(max(abs(x), abs(y)), abs(z)) - 1");
    // g(2) = 0 exactly and g < 0 right after: the entry is 2, proven inside at t_hi > 2.
    const RayResult r = solid(box, {0.5, 0.25, -3}, {0, 0, 1});
    expect_entry_at(r, 2.0);
    EXPECT_GT(r.t_hi, 2.0);
    // Along the face z = −1: g ≡ 0 on [2, 4], > 0 elsewhere. Never inside: a miss, while the zero
    // surface is met at t = 2.
    EXPECT_EQ(solid(box, {-3, 0, -1}, {1, 0, 0}).status, Status::Miss);
    EXPECT_EQ(zero(box, {-3, 0, -1}, {1, 0, 0}).status, Status::Hit);
    // Along an edge, and diagonally into a corner.
    EXPECT_EQ(solid(box, {-3, 1, -1}, {1, 0, 0}).status, Status::Miss);
    expect_entry_at(solid(box, {-3, -3, -3}, {1, 1, 1}), 2.0);
}

// f = 0 on the slab −1 ≤ x ≤ 0, f < 0 in the ball of radius 1/2 around (2, 0, 0), f > 0 elsewhere.
constexpr const char* kSlabThenBall =
    "min(max(abs(x + 0.5) - 0.5, 0), (x - 2)^2 + y^2 + z^2 - 0.25)";

TEST(Solid, ZeroSlabBeforeTheBall) {
    const Tape t = tape_of(kSlabThenBall);
    // Along the axis: the slab at t ∈ [2, 3], the ball's entry at x = 1.5, t = 4.5.
    const RayResult r = solid(t, {-3, 0, 0}, {1, 0, 0});
    expect_entry_at(r, 4.5);
    const RayResult z = zero(t, {-3, 0, 0}, {1, 0, 0});
    EXPECT_TRUE(z.status == Status::Unknown || (z.status == Status::Hit && z.t_hi < 4.5))
        << name(z.status) << " " << z.t_lo << " " << z.t_hi;
    // Off the axis the ray crosses only the slab: never inside.
    EXPECT_EQ(solid(t, {-3, 1, 0}, {1, 0, 0}).status, Status::Miss);
    EXPECT_NE(zero(t, {-3, 1, 0}, {1, 0, 0}).status, Status::Miss);
    // Starting in the slab, and through it on a slant.
    expect_entry_at(solid(t, {-0.5, 0, 0}, {1, 0, 0}), 2.0);
    // x = −3 + 4t, y = 3.75 − 3t: the slab at t ∈ [1/2, 3/4], the ball's centre at t = 5/4 and
    // its entry at t = 5/4 − 1/10 (|d| = 5), where x = 1.6, y = 0.3.
    const RayResult sl = solid(t, {-3, 3.75, 0}, {4, -3, 0});
    ASSERT_EQ(sl.status, Status::Hit);
    EXPECT_LE(sl.t_lo, 1.15 + 1e-15);
    EXPECT_GE(sl.t_hi, 1.15 - 1e-15);
    EXPECT_LE(ulps(sl.t_lo, sl.t_hi), 4);
}

TEST(Solid, StartsOnAZeroHalfSpace) {
    // f = 0 for x ≤ 0, > 0 for x > 0 outside the ball around (2, 0, 0) of radius 1/2.
    const Tape t = tape_of("min(max(x, 0), (x - 2)^2 + y^2 + z^2 - 0.25)");
    expect_entry_at(solid(t, {-1, 0, 0}, {1, 0, 0}), 2.5);
    const RayResult z = zero(t, {-1, 0, 0}, {1, 0, 0});
    ASSERT_EQ(z.status, Status::Hit);
    EXPECT_EQ(z.t_lo, 0.0);
    // The other way: from the ball's far side back through it to the half-space.
    expect_entry_at(solid(t, {4, 0, 0}, {-1, 0, 0}), 1.5);
    EXPECT_EQ(solid(t, {-1, 3, 0}, {1, 0, 0}).status, Status::Miss);
}

TEST(Solid, PointsWhereFIsUndefinedAreNotInside) {
    // The solid is {p : f(p) defined and < 0}. sqrt(x) − 1/2 is undefined for x < 0 and < 0 on
    // [0, 1/4): from x = −1 along +x the first entry is x = 0, t = 1.
    const RayResult r = solid(tape_of("sqrt(x) - 0.5"), {-1, 0, 0}, {1, 0, 0});
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, 1.0);
    EXPECT_GE(r.t_hi, 1.0);
    EXPECT_LE(r.t_hi, 1.0 + 1e-9);
    // sqrt(x) + 1 ≥ 1 where defined, undefined for x < 0: no point of the ray is inside.
    const Tape p = tape_of("sqrt(x) + 1");
    EXPECT_EQ(solid(p, {-2, 0, 0}, {1, 0, 0}, 0, 1).status, Status::Miss);
    EXPECT_EQ(solid(p, {-1, 0, 0}, {1, 0, 0}, 0, 2).status, Status::Miss);
    EXPECT_EQ(solid(p, {1, 0, 0}, {1, 0, 0}, 0, 2).status, Status::Miss);
    EXPECT_EQ(solid(p, {1, 0, 0}, {-1, 0, 0}, 0, 2).status, Status::Miss);
    // 1/x − 1 < 0 for x < 0: inside from the start.
    const RayResult w = solid(tape_of("1 / x - 1"), {-2, 0, 0}, {1, 0, 0});
    ASSERT_EQ(w.status, Status::Hit);
    EXPECT_EQ(w.t_hi, 0.0);
}

TEST(Solid, RaysPassRemovablePoles) {
    // 3/4 − 1/(1 + (1/x)²) = 3/4 − x²/(x² + 1) where x ≠ 0, undefined at x = 0 (the pole of 1/x,
    // as in Fidget's bear): > 0 for |x| < √3, < 0 for |x| > √3. Across the pole nothing is
    // inside; the first entry past it is x = √3.
    const Tape t = tape_of("0.75 - 1 / (1 + (1 / x)^2)");
    EXPECT_EQ(solid(t, {-1, 0.5, 0}, {1, 0, 0}, 0, 2).status, Status::Miss);
    // (Nested divisions: a few more ulps than a simple crossing.)
    expect_entry_at(solid(t, {-1, 0, 0}, {1, 0, 0}, 0, 5), 1 + std::sqrt(3.0), 8);
    expect_entry_at(solid(t, {1, 0, 0}, {-1, 0, 0}, 0, 5), 1 + std::sqrt(3.0), 8);
}

TEST(Solid, TangentsAreNeverAHit) {
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    // Grazing at y = 1: g ≥ 0 everywhere, = 0 at t = 3. Miss or unknown, cheaply.
    const RayResult r = solid(s, {-3, 1, 0}, {1, 0, 0});
    EXPECT_NE(r.status, Status::Hit);
    EXPECT_LE(r.evals.total(), 2000u);
    if (r.status == Status::Unknown) {
        EXPECT_LE(r.t_lo, 3.0);
        EXPECT_GE(r.t_hi, 3.0);
    }
    EXPECT_NE(solid(s, {-3, 1 + std::ldexp(1.0, -40), 0}, {1, 0, 0}).status, Status::Hit);
    // Entering by 2⁻²⁰: the inside is a segment of length ~2⁻⁹ around t = 3; never a miss.
    const RayResult in = solid(s, {-3, 1 - std::ldexp(1.0, -20), 0}, {1, 0, 0});
    EXPECT_NE(in.status, Status::Miss);
    EXPECT_EQ(in.status, Status::Hit);
}

TEST(Solid, BudgetEndsWithUnknown) {
    // s² − s + 1/4 = (s − 1/2)² ≥ 0 for s = sin(64x), touching 0 (tangent) 42 times on [−1, 1]:
    // written expanded, no enclosure near a touching point is ≥ 0, and each costs evaluations.
    const RayResult r = solid_first_entry(tape_of("sin(64 * x) * sin(64 * x) - sin(64 * x) + 0.25"),
                                          Ray{{-1, 0, 0}, {1, 0, 0}, 0, 2}, {200});
    EXPECT_EQ(r.status, Status::Unknown);
    EXPECT_LE(r.evals.total(), 200u + 4);
    // sin(1/x) + 1 ≥ 0 wherever it is defined (it touches 0 infinitely often near the pole x = 0,
    // where it is undefined): the two-piece enclosure across the pole proves it outside.
    EXPECT_EQ(
        solid_first_entry(tape_of("sin(1 / x) + 1"), Ray{{-1, 0, 0}, {1, 0, 0}, 0, 2}, {20000})
            .status,
        Status::Miss);
}

TEST(Solid, DegenerateRays) {
    const Tape s = tape_of("x^2 + y^2 + z^2 - 1");
    const RayResult in = solid(s, {0, 0, 0}, {0, 0, 0}, 1, 5);
    ASSERT_EQ(in.status, Status::Hit);
    EXPECT_EQ(in.t_lo, 1.0);
    EXPECT_EQ(solid(s, {0, 0, 2}, {0, 0, 0}).status, Status::Miss);
    EXPECT_EQ(solid(s, {1, 0, 0}, {0, 0, 0}).status, Status::Miss);  // on the surface: g ≡ 0
    EXPECT_EQ(solid(s, {0, 0, -3}, {0, 0, 1}, 1, 1).status, Status::Miss);
    EXPECT_EQ(solid(s, {0, 0, -3}, {0, 0, 1}, 2, 2).status, Status::Miss);  // g(2) = 0
    const RayResult at = solid(s, {0, 0, -3}, {0, 0, 1}, 3, 3);
    ASSERT_EQ(at.status, Status::Hit);
    EXPECT_EQ(at.t_hi, 3.0);
}

TEST(Solid, AffineOptionProvesTheSameEntry) {
    const Tape t = tape_of("q = sqrt(x^2 + y^2) - 1\nsqrt(q^2 + z^2) - 0.25");
    SolidOptions aff;
    aff.affine = true;
    const Ray ray{{-3, 0.5, 0.1}, {1, 0.01, 0.02}, 0, 10};
    const RayResult a = solid_first_entry(t, ray, aff);
    const RayResult b = solid_first_entry(t, ray);
    ASSERT_EQ(a.status, Status::Hit);
    ASSERT_EQ(b.status, Status::Hit);
    EXPECT_LE(std::max(a.t_lo, b.t_lo), std::min(a.t_hi, b.t_hi));
}

TEST(SolidReference, EnclosuresAreAdjacentDoubles) {
    // 2 − x² < 0 past √2: the entry is irrational, enclosed by the two doubles around it.
    const RayResult q = solid_first_entry_reference(tape_of("2 - x^2"), Ray{{0, 0, 0}, {1, 0, 0}});
    ASSERT_EQ(q.status, Status::Hit);
    EXPECT_LE(ulps(q.t_lo, q.t_hi), 1);
    mpfr_t a;
    mpfr_init2(a, 200);
    mpfr_set_d(a, q.t_lo, MPFR_RNDN);
    mpfr_sqr(a, a, MPFR_RNDN);
    EXPECT_LT(mpfr_cmp_ui(a, 2), 0);
    mpfr_set_d(a, q.t_hi, MPFR_RNDN);
    mpfr_sqr(a, a, MPFR_RNDN);
    EXPECT_GT(mpfr_cmp_ui(a, 2), 0);
    mpfr_clear(a);
    const RayResult d = solid_first_entry(tape_of("2 - x^2"), Ray{{0, 0, 0}, {1, 0, 0}});
    ASSERT_EQ(d.status, Status::Hit);
    EXPECT_LE(d.t_lo, q.t_lo);
    EXPECT_GE(d.t_hi, q.t_hi);
    EXPECT_LE(ulps(d.t_lo, d.t_hi), 4);
    const Tape t = tape_of(kSlabThenBall);
    const RayResult r = solid_first_entry_reference(t, Ray{{-3, 0, 0}, {1, 0, 0}});
    ASSERT_EQ(r.status, Status::Hit);
    EXPECT_LE(r.t_lo, 4.5);
    EXPECT_GE(r.t_hi, 4.5);
}

// ---- the Fidget models: rays along −z over [−1, 1]² ------------------------------------------

struct GridCounts {
    int hit = 0, miss = 0, unknown = 0;
    double us_per_ray = 0, evals_per_ray = 0;
};

template <class F>
GridCounts trace_grid(const Tape& tape, int n, std::array<double, 3> d, F&& solve) {
    GridCounts c;
    const auto start = std::chrono::steady_clock::now();
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double x = -1 + (i + 0.5) * 2.0 / n, y = -1 + (j + 0.5) * 2.0 / n;
            const RayResult r = solve(tape, Ray{{x, y, 1}, d, 0, 2});
            (r.status == Status::Hit ? c.hit : r.status == Status::Miss ? c.miss : c.unknown)++;
            c.evals_per_ray += static_cast<double>(r.evals.total()) / (n * n);
        }
    }
    const std::chrono::duration<double, std::micro> dt = std::chrono::steady_clock::now() - start;
    c.us_per_ray = dt.count() / (n * n);
    return c;
}

TEST(SolidFidget, NoUnknownsOnTheModelGrids) {
    const std::filesystem::path dir = std::filesystem::path(CERTRAY_TEST_DATA) / "models";
    constexpr int kN = 64;
    for (const char* name : {"quarter.vm", "hi.vm"}) {
        const Tape tape(expr::import_vm_file(dir / name));
        for (const std::array<double, 3> d :
             {std::array<double, 3>{0, 0, -1}, std::array<double, 3>{0.25, -0.125, -1}}) {
            const GridCounts z = trace_grid(tape, kN, d, [](const Tape& t, const Ray& r) {
                return certified_first_root(t, r);
            });
            const GridCounts s = trace_grid(
                tape, kN, d, [](const Tape& t, const Ray& r) { return solid_first_entry(t, r); });
            std::printf(
                "%-10s d=(%g,%g,%g) %dx%d\n  zero:  %4d hit %4d miss %d unknown, %.1f evals "
                "%.2f us/ray\n  solid: %4d hit %4d miss %d unknown, %.1f evals %.2f us/ray\n",
                name, d[0], d[1], d[2], kN, kN, z.hit, z.miss, z.unknown, z.evals_per_ray,
                z.us_per_ray, s.hit, s.miss, s.unknown, s.evals_per_ray, s.us_per_ray);
            EXPECT_EQ(s.unknown, 0) << name;
            // Along −z, g is the constant f(x, y): inside exactly where f(x, y) < 0.
            if (d[0] == 0 && d[1] == 0) {
                int inside = 0;
                for (int j = 0; j < kN; ++j) {
                    for (int i = 0; i < kN; ++i) {
                        const double x = -1 + (i + 0.5) * 2.0 / kN, y = -1 + (j + 0.5) * 2.0 / kN;
                        const MpfrInterval v = g_mpfr(tape, Ray{{x, y, 0}, {0, 0, 0}}, 0, 0);
                        if (v.upper() < 0) ++inside;
                    }
                }
                EXPECT_EQ(s.hit, inside) << name;
            }
        }
    }
}

// ---- properties ------------------------------------------------------------------------------

/// The answer's claims, checked in MPFR at 512 bits: the proven-inside point t_hi of a Hit has
/// g defined and < 0; no point (nor piece) of the proven prefix [tmin, t_lo) — all of [tmin, tmax]
/// for a Miss — is proven inside (g defined and < 0 there); points where f is undefined are not
/// inside.
void check_in_mpfr(const Tape& tape, const Ray& ray, const RayResult& res) {
    if (res.status == Status::Hit) {
        RC_ASSERT(ray.tmin <= res.t_lo);
        RC_ASSERT(res.t_lo <= res.t_hi);
        RC_ASSERT(res.t_hi <= ray.tmax);
        const MpfrInterval v = g_mpfr(tape, ray, res.t_hi, res.t_hi);
        RC_ASSERT(!v.is_empty());
        RC_ASSERT(v.upper() < 0);
    }
    if (res.status == Status::Unknown) RC_ASSERT(ray.tmin <= res.t_lo);
    const double end = res.status == Status::Miss ? ray.tmax : res.t_lo;
    const bool closed = res.status == Status::Miss;  // [tmin, tmax] against [tmin, t_lo)
    constexpr int kPieces = 32;
    double prev = ray.tmin;
    for (int k = 0; k <= kPieces; ++k) {
        double s = ray.tmin + (end - ray.tmin) * k / kPieces;
        s = std::min(s, end);
        if (!(closed ? s <= end : s < end)) break;
        const MpfrInterval v = g_mpfr(tape, ray, s, s);
        RC_ASSERT(!(!v.is_empty() && v.defined && v.upper() < 0));
        if (k > 0 && prev < s) {
            const MpfrInterval w = g_mpfr(tape, ray, prev, s);
            RC_ASSERT(!(!w.is_empty() && w.defined && w.upper() < 0));
        }
        prev = s;
    }
}

RC_GTEST_PROP(SolidProperty, AnswersHoldInMpfr, ()) {
    const expr::Graph g = *testing::gen_dag(16);
    const Tape t(g);
    const Ray ray = *testing::gen_ray();
    SolidOptions opt;
    opt.budget = 4000;
    opt.affine = *rc::gen::arbitrary<bool>();
    const RayResult res = solid_first_entry(t, ray, opt);
    RC_TAG(name(res.status));
    check_in_mpfr(t, ray, res);
}

// The double solver and the MPFR reference agree: two hits overlap (both hold the first entry), and
// neither proves a miss where the other proves a hit.
RC_GTEST_PROP(SolidProperty, AgreesWithTheMpfrReference, ()) {
    const expr::Graph g = *testing::gen_dag(8);
    const Tape t(g);
    const Ray ray = *testing::gen_ray();
    SolidOptions opt;
    opt.budget = 400;
    const RayResult d = solid_first_entry(t, ray, opt);
    const RayResult m = solid_first_entry_reference(t, ray, opt);
    check_in_mpfr(t, ray, m);
    if (d.status == Status::Hit && m.status == Status::Hit) {
        RC_ASSERT(std::max(d.t_lo, m.t_lo) <= std::min(d.t_hi, m.t_hi));
    }
    RC_ASSERT(!(d.status == Status::Hit && m.status == Status::Miss));
    RC_ASSERT(!(d.status == Status::Miss && m.status == Status::Hit));
}

// g(t) = Π (t − rᵢ) along x, negated or not: its sign pattern is known, so the first entry is.
RC_GTEST_PROP(SolidProperty, PolynomialWithKnownEntry, ()) {
    const auto [text, roots] = *testing::gen_root_product(5);
    const bool negate = *rc::gen::arbitrary<bool>();
    const double tmin = *rc::gen::inRange(-300, 300) / 64.0;
    const double tmax = tmin + *rc::gen::inRange(0, 400) / 64.0;
    const Tape t(expr::parse_expr(negate ? "-(" + text + ")" : text));
    const RayResult res = solid_first_entry(t, Ray{{0, 0, 0}, {1, 0, 0}, tmin, tmax});
    // The sign of g at s, exactly (the roots are dyadic, the product of signs is exact).
    auto sign = [&](double s) {
        int sg = negate ? -1 : 1;
        for (double r : roots) {
            if (s == r) return 0;
            if (s < r) sg = -sg;
        }
        return sg;
    };
    // The first entry: tmin if g(tmin) < 0, else the first root r ≥ tmin after which g < 0.
    std::vector<double> pts{tmin};
    for (double r : roots) {
        if (r >= tmin && r < tmax) pts.push_back(r);
    }
    std::sort(pts.begin(), pts.end());
    double entry = kInf;
    for (double p : pts) {
        // g < 0 just right of p (roots are ≥ 1/64 apart; tmax − p ≥ 1/64 or the segment ends).
        const double right = std::min(p + 1.0 / 256, tmax);
        if (sign(p) < 0 || (right > p && sign(right) < 0)) {
            entry = p;
            break;
        }
    }
    if (res.status == Status::Miss) RC_ASSERT(entry == kInf);
    if (res.status == Status::Hit) RC_ASSERT(res.t_lo <= entry && entry <= res.t_hi);
    if (res.status == Status::Unknown) RC_ASSERT(entry == kInf || res.t_lo <= entry);
    if (entry != kInf) RC_ASSERT(res.status == Status::Hit);
}

}  // namespace
}  // namespace certray::solvers
