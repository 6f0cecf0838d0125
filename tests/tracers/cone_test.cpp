// tests/tracers/cone_test.cpp — the cone march (tracers/cone.h) against the roots mathematics
// gives: unions of spheres, whose first root along a ray is the least of the spheres' closed-form
// roots, seen by random cameras; and images of the Lipschitz tracers with and without the march.
#include "tracers/cone.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "expr/parser.h"
#include "expr/tape.h"
#include "tracers/methods.h"
#include "tracers/render.h"

namespace certray::tracers {
namespace {

struct Ball {
    Vec3 c;
    double r;
};

/// The first t ≥ 0 where the ray o + t·d enters one of `balls` (long double), if any.
std::optional<long double> first_root(const Ray& ray, const std::vector<Ball>& balls) {
    std::optional<long double> best;
    for (const Ball& b : balls) {
        long double oc[3], dd = 0, od = 0, cc = 0;
        for (int i = 0; i < 3; ++i) {
            oc[i] = static_cast<long double>(ray.o[i]) - b.c[i];
            dd += static_cast<long double>(ray.d[i]) * ray.d[i];
            od += oc[i] * ray.d[i];
            cc += oc[i] * oc[i];
        }
        const long double disc = od * od - dd * (cc - static_cast<long double>(b.r) * b.r);
        if (disc < 0) continue;
        const long double s = std::sqrt(disc);
        for (const long double t : {(-od - s) / dd, (-od + s) / dd}) {
            if (t >= 0 && (!best || t < *best)) best = t;
        }
    }
    return best;
}

/// min over the balls of |p − c|² − r² as an expression (a union of spheres).
std::string union_of(const std::vector<Ball>& balls) {
    std::string e;
    for (const Ball& b : balls) {
        const std::string s = "((x - (" + std::to_string(b.c[0]) + "))^2 + (y - (" +
                              std::to_string(b.c[1]) + "))^2 + (z - (" + std::to_string(b.c[2]) +
                              "))^2 - " + std::to_string(b.r * b.r) + ")";
        e = e.empty() ? s : "min(" + e + ", " + s + ")";
    }
    return e;
}

/// The balls with their parameters as the expression printed them (to_string's 6 decimals).
std::vector<Ball> as_printed(std::vector<Ball> balls) {
    for (Ball& b : balls) {
        for (double& c : b.c) c = std::stod(std::to_string(c));
        b.r = std::sqrt(std::stod(std::to_string(b.r * b.r)));
    }
    return balls;
}

/// The tile of side × side pixels from (i0, j0) of the camera's image, each ray clipped to the
/// bounds (Active) or missing them (Outside).
ConeTile tile_of(const CameraFrame& frame, unsigned i0, unsigned j0, unsigned side,
                 const Box3& bounds) {
    ConeTile tile;
    tile.width = tile.height = side;
    for (unsigned j = 0; j < side; ++j) {
        for (unsigned i = 0; i < side; ++i) {
            Ray r = frame.ray(i0 + i + 0.5, j0 + j + 0.5);
            tile.state.push_back(clip_ray(r, bounds) ? ConeTile::Active : ConeTile::Outside);
            tile.rays.push_back(r);
        }
    }
    return tile;
}

// Every ray the march leaves active starts at or before its first root, and every ray it calls
// free has no root on its segment: random unions of 1–4 balls, random cameras, 48×48 pixels in
// 16×16 tiles. The march must also do its work: most rays that miss every ball are proven free.
TEST(ConeMarch, NeverPassesTheFirstRoot) {
    std::mt19937_64 rng(20261125);
    std::uniform_real_distribution<double> u(-1, 1), rad(0.2, 0.7), far(3, 9);
    const Box3 bounds{{{-2, 2}, {-2, 2}, {-2, 2}}};
    std::size_t misses = 0, freed = 0, hits = 0;
    for (int scene = 0; scene < 12; ++scene) {
        std::vector<Ball> balls(1 + scene % 4);
        for (Ball& b : balls) b = {{u(rng), u(rng), u(rng)}, rad(rng)};
        balls = as_printed(balls);
        const expr::Tape tape(expr::parse_expr(union_of(balls)));
        ConeOptions copt;
        copt.max_steps = 1000;
        copt.local_bounds = scene % 2 == 0;  // half of the scenes with the global λ alone
        const ConeMarch march(tape, bounds, copt);
        Camera cam;
        const Vec3 dir = normalize({u(rng), u(rng), u(rng)});
        const double dist = far(rng);
        cam.eye = {dir[0] * dist, dir[1] * dist, dir[2] * dist};
        cam.target = {0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)};
        const CameraFrame frame(cam, 48, 48);
        for (unsigned tj = 0; tj < 48; tj += 16) {
            for (unsigned ti = 0; ti < 48; ti += 16) {
                ConeTile tile = tile_of(frame, ti, tj, 16, bounds);
                const std::vector<Ray> before = tile.rays;
                const EvalCounts evals = march.march(tile);
                EXPECT_GT(evals.total(), 0u);
                for (std::size_t k = 0; k < tile.rays.size(); ++k) {
                    if (tile.state[k] == ConeTile::Outside) continue;
                    const Ray& r0 = before[k];
                    const std::optional<long double> root = first_root(r0, balls);
                    const bool hit = root && *root >= r0.tmin && *root <= r0.tmax;
                    // Closed-form roots carry a relative error near 1e-18 (long double).
                    const long double slack = 1e-12L * (1 + (root ? *root : 0));
                    if (tile.state[k] == ConeTile::Free) {
                        EXPECT_FALSE(root && *root >= r0.tmin + slack && *root <= r0.tmax - slack)
                            << "scene " << scene << " ray " << k << " root " << (double)*root;
                        ++freed;
                    } else {
                        EXPECT_EQ(tile.rays[k].tmax, r0.tmax);
                        EXPECT_GE(tile.rays[k].tmin, r0.tmin);
                        if (hit) {
                            EXPECT_LE(tile.rays[k].tmin, *root + slack)
                                << "scene " << scene << " ray " << k;
                        }
                    }
                    if (!hit) ++misses;
                    hits += hit;
                }
            }
        }
    }
    ASSERT_GT(hits, 1000u);
    ASSERT_GT(misses, 1000u);
    EXPECT_GT(freed, misses / 2) << "the march proved few misses";
}

// A ray the march advances toward a ball it hits gets close to it: with the ball's distance
// (λ = 1, tight), the start of every hit ray seen from afar is at least half of the way from the
// bounds to the root.
TEST(ConeMarch, AdvancesTheRaysThatHit) {
    const std::vector<Ball> balls = {{{0, 0, 0}, 1}};
    const expr::Tape tape(expr::parse_expr("sqrt(x^2 + y^2 + z^2) - 1"));
    const Box3 bounds{{{-2, 2}, {-2, 2}, {-2, 2}}};
    ConeOptions copt;
    copt.max_steps = 1000;
    const ConeMarch march(tape, bounds, copt);
    Camera cam;
    cam.eye = {0, -8, 0};
    cam.fov_degrees = 30;
    const CameraFrame frame(cam, 32, 32);
    ConeTile tile = tile_of(frame, 0, 0, 32, bounds);
    const std::vector<Ray> before = tile.rays;
    march.march(tile);
    int hits = 0;
    for (std::size_t k = 0; k < before.size(); ++k) {
        const std::optional<long double> root = first_root(before[k], balls);
        if (!root || tile.state[k] == ConeTile::Outside) continue;
        ASSERT_EQ(tile.state[k], ConeTile::Active);
        ++hits;
        const double t0 = before[k].tmin;
        EXPECT_GE(tile.rays[k].tmin, t0 + 0.5 * static_cast<double>(*root - t0)) << "ray " << k;
    }
    EXPECT_GT(hits, 100);
}

// The march's shares of evaluations sum to what it returns.
TEST(ConeMarch, SharesSumToTheEvaluations) {
    const std::vector<Ball> balls = {{{0.5, 0, 0}, 0.6}, {{-0.5, 0.2, 0}, 0.5}};
    const expr::Tape tape(expr::parse_expr(union_of(balls)));
    const Box3 bounds{{{-2, 2}, {-2, 2}, {-2, 2}}};
    const ConeMarch march(tape, bounds);
    Camera cam;
    cam.eye = {1, -6, 2};
    const CameraFrame frame(cam, 16, 16);
    ConeTile tile = tile_of(frame, 0, 0, 16, bounds);
    const EvalCounts evals = march.march(tile);
    double sum = 0;
    for (const double s : tile.share) sum += s;
    EXPECT_NEAR(sum, static_cast<double>(evals.total()), 1e-6 * evals.total());
    EXPECT_GT(evals.total(), 0u);
}

// Images of the cone-marched tracers: every hit within 1e-4 of the closed-form root and every
// miss a ray that meets no ball on its segment, as without the march; the march leaves the
// answers of each pixel as they were, up to the tracers' own epsilon.
TEST(ConeMarch, ImagesKeepTheAnswers) {
    const std::vector<Ball> balls =
        as_printed({{{0.5, 0, 0.1}, 0.6}, {{-0.6, 0.3, -0.2}, 0.45}, {{0, -0.2, 0.7}, 0.3}});
    const expr::Tape tape(expr::parse_expr(union_of(balls)));
    RenderOptions o;
    o.width = o.height = 40;
    o.camera.eye = {2, -6, 2.5};
    o.threads = 2;
    MethodOptions mo;
    mo.bounds = std::array<Interval, 3>{Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};
    const CameraFrame frame(o.camera, o.width, o.height);
    for (const MethodInfo& info : method_infos()) {
        if (info.cone == ConeMarching::None) continue;
        ConeOptions copt;
        copt.epsilon = mo.epsilon;
        copt.local_bounds = info.cone == ConeMarching::Local;
        const ConeMarch march(tape, o.bounds, copt);
        const RayFunction fn = make_method(info.name, tape, mo);
        RenderOptions with = o;
        with.cone = &march;
        const RenderResult a = render_3d(tape, fn, o), b = render_3d(tape, fn, with);
        int hits = 0;
        for (std::size_t k = 0; k < a.answers.status.size(); ++k) {
            Ray ray = frame.ray(k % o.width + 0.5, k / o.width + 0.5);
            const bool inside = clip_ray(ray, o.bounds);
            const std::optional<long double> root = inside ? first_root(ray, balls) : std::nullopt;
            const bool hit = root && *root >= ray.tmin && *root <= ray.tmax;
            for (const RenderResult* r : {&a, &b}) {
                const Status s = r->answers.status[k];
                ASSERT_NE(s, Status::Unknown) << info.name << " pixel " << k;
                ASSERT_EQ(s == Status::Hit, hit) << info.name << " pixel " << k;
                if (hit) {
                    EXPECT_NEAR(r->answers.t[k], static_cast<double>(*root), 1e-4)
                        << info.name << " pixel " << k;
                }
            }
            hits += hit;
        }
        EXPECT_GT(hits, 150) << info.name;
        if (info.name == "sphere") {  // the march shares the steps through empty space
            EXPECT_LT(b.stats.evals.total(), a.stats.evals.total());
        }
    }
}

}  // namespace
}  // namespace certray::tracers
