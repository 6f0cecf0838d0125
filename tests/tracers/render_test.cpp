// tests/tracers/render_test.cpp — 3D rendering (tracers/render, tracers/camera) and PNG files
// (tracers/png_io): a unit sphere seen head-on against the closed-form ray–sphere intersection.
#include "tracers/render.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "expr/parser.h"
#include "expr/tape.h"
#include "tests/support/batch_isa.h"
#include "tracers/camera.h"
#include "tracers/methods.h"
#include "tracers/png_io.h"

namespace certray::tracers {
namespace {

namespace fs = std::filesystem;

/// The unit sphere seen from (0, −5, 0) looking at the origin: 33×33 pixels, so that the centre
/// pixel (16, 16) is the ray straight down the y axis.
RenderOptions sphere_view() {
    RenderOptions o;
    o.width = 33;
    o.height = 33;
    o.camera.eye = {0, -5, 0};
    o.camera.target = {0, 0, 0};
    o.camera.up = {0, 0, 1};
    o.camera.fov_degrees = 30;
    o.light = {0, -1, 0};  // from the camera
    o.threads = 2;
    return o;
}

const expr::Tape& sphere() {
    static const expr::Tape t(expr::parse_expr("x^2 + y^2 + z^2 - 1"));
    return t;
}

RenderResult render_sphere(const RenderOptions& o, std::uint64_t budget = 20000) {
    MethodOptions mo;
    mo.budget = budget;
    return render_3d(sphere(), make_method("certified", sphere(), mo), o);
}

// Every registered method renders two scenes — the torus (a hole, grazing rays at its rim; its
// exact-distance sqrt defeats a global interval Lipschitz bound, so `sphere` and `enhanced` answer
// unknown there) and an algebraic sphere (a finite global bound) — and is compared with
// `certified` pixel by pixel: the certified methods must agree exactly (hit against hit at the
// same t, miss against miss); the approximate ones may differ on a few silhouette pixels (their
// ε and step knobs). Unknown is honest, never counted as a difference; but every method must
// answer most pixels of at least one scene.
TEST(Render, EveryMethodAgreesWithTheCertifiedSolverPixelByPixel) {
    const expr::Tape torus(expr::parse_expr("q = sqrt(x^2 + y^2) - 1\nsqrt(q^2 + z^2) - 0.35"));
    RenderOptions o = sphere_view();
    o.camera.eye = {0, -3.5, 2.2};
    o.width = o.height = 24;
    MethodOptions mo;
    mo.bounds = std::array<Interval, 3>{Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};
    std::map<std::string, std::uint64_t> answered;
    for (const expr::Tape* scene : {&torus, &sphere()}) {
        const RenderResult ref = render_3d(*scene, make_method("certified", *scene, mo), o);
        ASSERT_EQ(ref.stats.unknown, 0u);
        ASSERT_GT(ref.stats.hit, 50u);
        ASSERT_GT(ref.stats.miss, 50u);
        for (const std::string& m : method_names()) {
            if (m == "reference") continue;  // MPFR: slow, and tested with the solver
            if ((m == "analytic" || m == "bernstein" || m == "exact") && scene == &torus) {
                continue;  // not polynomial
            }
            const RenderResult r = render_3d(*scene, make_method(m, *scene, mo), o);
            const bool certified = m.starts_with("certified") || m == "certified-taylor" ||
                                   m == "bernstein" || m == "exact";
            answered[m] += r.stats.hit + r.stats.miss;
            unsigned differ = 0;
            for (std::size_t i = 0; i < ref.answers.status.size(); ++i) {
                const Status a = ref.answers.status[i], b = r.answers.status[i];
                if (b == Status::Unknown) continue;
                if (a != b) ++differ;
                if (a == Status::Hit && b == Status::Hit && certified) {
                    EXPECT_NEAR(r.answers.t[i], ref.answers.t[i], 1e-12) << m << " pixel " << i;
                }
            }
            if (certified) {
                EXPECT_EQ(differ, 0u) << m;
            } else {
                EXPECT_LE(differ, 6u) << m;
            }
        }
    }
    for (const auto& [m, n] : answered) EXPECT_GE(n, 400u) << m << " answered too few pixels";
}

TEST(Render, SphereHeadOnMatchesTheClosedForm) {
    const RenderOptions o = sphere_view();
    const RenderResult r = render_sphere(o);
    const auto& a = r.answers;
    // The centre ray o = (0, −5, 0), d = (0, 1, 0) meets y = −1 at t = 4.
    const std::size_t centre = 16 * 33 + 16;
    ASSERT_EQ(a.status[centre], Status::Hit);
    EXPECT_NEAR(a.t[centre], 4.0, 1e-9);
    // The normal there is (0, −1, 0), facing the camera.
    EXPECT_NEAR(a.normal[centre][1], -1.0f, 1e-6f);
    // Corners: about 20° off axis, the sphere subtends asin(1/5) ≈ 11.5°.
    EXPECT_EQ(a.status[0], Status::Miss);
    EXPECT_EQ(a.status[33 * 33 - 1], Status::Miss);
    // Every pixel against |o + t·d|² = 1: t = −b − √(b² − c), b = o·d, c = |o|² − 1 (|d| = 1).
    const CameraFrame frame(o.camera, o.width, o.height);
    std::size_t hits = 0;
    for (unsigned j = 0; j < 33; ++j) {
        for (unsigned i = 0; i < 33; ++i) {
            const Ray ray = frame.ray(i + 0.5, j + 0.5);
            const double b = dot(ray.o, ray.d), c = dot(ray.o, ray.o) - 1;
            const double disc = b * b - c;
            const std::size_t k = j * 33 + i;
            if (std::abs(disc) < 1e-6) continue;  // grazing: either answer is honest
            if (disc < 0) {
                EXPECT_EQ(a.status[k], Status::Miss) << i << "," << j;
            } else {
                ++hits;
                EXPECT_EQ(a.status[k], Status::Hit) << i << "," << j;
                EXPECT_NEAR(a.t[k], -b - std::sqrt(disc), 1e-7) << i << "," << j;
            }
        }
    }
    EXPECT_GT(hits, 100u);
    EXPECT_EQ(r.stats.hit + r.stats.miss + r.stats.unknown, 33u * 33u);
    EXPECT_EQ(r.stats.hit, hits);
    EXPECT_GT(r.stats.evals.total(), 0u);
}

TEST(Render, StatusAovColoursAndUnknownsAreMarked) {
    RenderOptions o = sphere_view();
    o.aov = Aov::Status;
    const RenderResult r = render_sphere(o);
    const std::uint8_t* centre = r.image.at(16, 16);
    EXPECT_EQ(centre[0], 255);  // hit: white
    EXPECT_EQ(centre[1], 255);
    EXPECT_EQ(centre[2], 255);
    const std::uint8_t* corner = r.image.at(0, 0);
    EXPECT_LT(corner[0], 40);  // miss: dark blue
    EXPECT_GT(corner[2], corner[0]);
    // A budget of 2 evaluations cannot prove a hit: those pixels are unknown, shown magenta.
    const RenderResult u = render_sphere(o, 2);
    EXPECT_GT(u.stats.unknown, 0u);
    EXPECT_EQ(u.answers.status[16 * 33 + 16], Status::Unknown);
    const std::uint8_t* m = u.image.at(16, 16);
    EXPECT_EQ(m[0], 255);
    EXPECT_EQ(m[1], 0);
    EXPECT_EQ(m[2], 255);
}

TEST(Render, ShadeFollowsLambert) {
    const RenderResult r = render_sphere(sphere_view());
    // Light from the camera: the centre (normal towards the light) is the brightest hit; a hit
    // near the rim (oblique normal) is darker.
    const std::uint8_t* centre = r.image.at(16, 16);
    unsigned rim = 16;
    while (rim > 0 && r.answers.status[16 * 33 + rim - 1] == Status::Hit) --rim;
    ASSERT_LT(rim, 16u);
    EXPECT_GT(centre[0], r.image.at(rim, 16)[0] + 20);
}

/// The shade AOV, by hand: a hit is (0.92, 0.86, 0.74)·(0.18 + 0.82·max(0, n·l)), a miss its row's
/// sky (0.62 − 0.35s, 0.70 − 0.35s, 0.82 − 0.30s at s = row / (rows − 1)), an unknown magenta;
/// each channel as the byte ⌊255v + 0.5⌋.
TEST(Render, ShadeColoursByHand) {
    PixelAnswers a;
    a.width = 2;
    a.height = 3;
    a.status = {Status::Hit, Status::Miss, Status::Hit, Status::Unknown, Status::Miss, Status::Hit};
    a.t.resize(6, 1.0);
    a.evals.resize(6, 0);
    a.normal = {{0, 0, 1}, {0, 0, 0}, {0.6f, 0, 0.8f}, {0, 0, 0}, {0, 0, 0}, {0, 0, -1}};
    const RgbImage img = colorize(a, Aov::Shade, {0, 0, 2}, 2);
    const auto byte = [](double v) { return static_cast<int>(std::floor(255 * v + 0.5)); };
    const auto expect = [&](unsigned i, unsigned j, double r, double g, double b) {
        const std::uint8_t* p = img.at(i, j);
        EXPECT_EQ(p[0], byte(r)) << "pixel (" << i << ", " << j << ")";
        EXPECT_EQ(p[1], byte(g)) << "pixel (" << i << ", " << j << ")";
        EXPECT_EQ(p[2], byte(b)) << "pixel (" << i << ", " << j << ")";
    };
    expect(0, 0, 0.92, 0.86, 0.74);  // n·l = 1
    expect(1, 0, 0.62, 0.70, 0.82);  // the top row's sky
    const double c = 0.18 + 0.82 * double{0.8f};
    expect(0, 1, 0.92 * c, 0.86 * c, 0.74 * c);
    expect(1, 1, 1, 0, 1);
    expect(0, 2, 0.62 - 0.35, 0.70 - 0.35, 0.82 - 0.30);  // the bottom row's sky
    expect(1, 2, 0.92 * 0.18, 0.86 * 0.18, 0.74 * 0.18);  // facing away: ambient only
}

/// Pixel buffers of 2 MiB and more are aligned to 2 MiB (for transparent huge pages) and hold
/// what is written; small ones are ordinary.
TEST(Render, PixelBuffersHoldWhatIsWritten) {
    for (std::size_t n :
         {std::size_t{1}, std::size_t{1000}, std::size_t{1} << 18, (std::size_t{3} << 18) + 5}) {
        PixelBuffer<double> b;
        b.resize(n, boost::container::default_init);
        ASSERT_EQ(b.size(), n);
        if (n * sizeof(double) >= (std::size_t{2} << 20)) {
            EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % (std::size_t{2} << 20), 0u);
        }
        for (std::size_t k = 0; k < n; ++k) b[k] = static_cast<double>(k);
        PixelBuffer<double> copy = b;
        b.resize(n + 1, 0.0);
        for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(b[k], static_cast<double>(k));
        EXPECT_EQ(b[n], 0.0);
        EXPECT_EQ(copy.size(), n);
        EXPECT_EQ(copy[n - 1], static_cast<double>(n - 1));
    }
}

TEST(Render, ThreadsGiveTheSameAnswers) {
    RenderOptions o = sphere_view();
    o.threads = 1;
    const RenderResult one = render_sphere(o);
    o.threads = 3;
    const RenderResult three = render_sphere(o);
    EXPECT_EQ(one.answers.status, three.answers.status);
    EXPECT_EQ(one.image.rgb, three.image.rgb);
}

TEST(Camera, ClipRayToBounds) {
    const Box3 box{{{-2, 2}, {-2, 2}, {-2, 2}}};
    Ray r;
    r.o = {0, -5, 0};
    r.d = {0, 1, 0};
    ASSERT_TRUE(clip_ray(r, box));
    EXPECT_LE(r.tmin, 3.0);  // enters at y = −2, t = 3
    EXPECT_NEAR(r.tmin, 3.0, 1e-12);
    EXPECT_GE(r.tmax, 7.0);  // leaves at y = 2, t = 7
    EXPECT_NEAR(r.tmax, 7.0, 1e-12);
    Ray away = r;
    away.d = {0, -1, 0};
    EXPECT_FALSE(clip_ray(away, box));
    Ray beside;
    beside.o = {3, 0, 0};
    beside.d = {0, 0, 1};
    EXPECT_FALSE(clip_ray(beside, box));
}

TEST(Camera, ClippedRowsAreTheRaysOneByOne) {
    // CameraFrame::clipped_row computes a row's rays eight at a time: each is, bit for bit,
    // CameraFrame::ray then clip_ray, and meets the bounds when clip_ray says so. Cameras with
    // pixels whose direction has zero components (an odd image looking down an axis), eyes inside
    // and outside the bounds, rays that miss them, slab parameters beyond step_up's integer
    // range (bounds of 1e300, and of 1e-305 around the eye), rows that are not multiples of 8.
    const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
    struct View {
        Camera camera;
        Box3 bounds;
        unsigned width, height;
    };
    const Box3 unit{{{-1, 1}, {-1, 1}, {-1, 1}}};
    std::vector<View> views = {
        {{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 35}, unit, 33, 17},         // straight down −z
        {{{4, -8, 3.2}, {0, 0, 0}, {0, 0, 1}, 35}, unit, 45, 30},      // the default view
        {{{0.2, 0.1, -0.3}, {1, 2, 3}, {0, 0, 1}, 60}, unit, 19, 11},  // eye inside
        {{{9, 0, 0}, {0, 0, 0}, {0, 0, 1}, 120}, unit, 21, 21},        // most rays miss
        {{{3, -1, 2}, {0, 0, 0}, {0, 0, 1}, 20},
         {{{-1e300, 1e300}, {-1e300, 1e300}, {-1e300, 1e300}}},
         13,
         9},
        {{{1e-3, 2e-3, 5e-4}, {1, 1, 1}, {0, 0, 1}, 35},
         {{{1e-3 - 1e-305, 1e-3 + 1e-305},
           {2e-3 - 1e-305, 2e-3 + 1e-305},
           {5e-4 - 1e-305, 5e-4 + 1e-305}}},
         11,
         7},
    };
    std::size_t lanes = 0, inside = 0;
    testing::BatchIsaGuard guard;  // each copy of the row's vector code (expr::batch_isa())
    for (const expr::BatchIsa isa : testing::batch_isas()) {
        expr::set_batch_isa(isa);
        SCOPED_TRACE(expr::batch_isa_name(isa));
        for (const View& view : views) {
            const CameraFrame frame(view.camera, view.width, view.height);
            std::vector<Ray> row(view.width);
            std::unique_ptr<bool[]> in(new bool[view.width]);
            for (unsigned j = 0; j < view.height; ++j) {
                for (unsigned i0 : {0u, 3u}) {
                    const unsigned n = view.width - i0;
                    frame.clipped_row(i0, j, n, view.bounds, row.data(), in.get());
                    for (unsigned k = 0; k < n; ++k) {
                        Ray one = frame.ray(i0 + k + 0.5, j + 0.5);
                        const bool meets = clip_ray(one, view.bounds);
                        ++lanes;
                        inside += meets;
                        EXPECT_EQ(in[k], meets) << i0 + k << ", " << j;
                        EXPECT_EQ(bits(row[k].tmin), bits(one.tmin)) << i0 + k << ", " << j;
                        EXPECT_EQ(bits(row[k].tmax), bits(one.tmax)) << i0 + k << ", " << j;
                        for (int c = 0; c < 3; ++c) {
                            EXPECT_EQ(bits(row[k].o[c]), bits(one.o[c])) << i0 + k << ", " << j;
                            EXPECT_EQ(bits(row[k].d[c]), bits(one.d[c])) << i0 + k << ", " << j;
                        }
                    }
                }
            }
        }
    }
    EXPECT_GT(inside, lanes / 4);
    EXPECT_LT(inside, lanes);
}

TEST(Camera, RectanglesThatMissTheBoundsHoldNoRayThatMeetsThem) {
    // CameraFrame::misses(rectangle) says true only where clip_ray finds no pixel ray of the
    // rectangle meeting the bounds (what clipped_row says too, ClippedRowsAreTheRaysOneByOne):
    // random cameras, boxes and rectangles (a fixed seed), half of the views aimed at a corner of
    // the box so that rays graze it. And it does tell: most of the 4 × 4 rectangles whose rays all
    // miss the box are found so.
    std::mt19937 rng(20261127);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto in = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    std::size_t claimed = 0, all_miss = 0, caught = 0;
    for (int view = 0; view < 300; ++view) {
        Box3 box;
        for (auto& a : box) {
            a[0] = in(-2, 2);
            a[1] = a[0] + in(0.01, 3);
        }
        Camera camera;
        camera.eye = {in(-8, 8), in(-8, 8), in(-8, 8)};
        if (view % 2 == 0) {
            camera.target = {box[0][view % 4 == 0], box[1][view % 3 == 0], box[2][view % 5 == 0]};
        } else {
            camera.target = {in(-3, 3), in(-3, 3), in(-3, 3)};
        }
        const Vec3 f =
            normalize({camera.target[0] - camera.eye[0], camera.target[1] - camera.eye[1],
                       camera.target[2] - camera.eye[2]});
        camera.up = std::fabs(f[2]) > 0.9 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
        camera.fov_degrees = std::array{10.0, 35.0, 90.0, 150.0}[view % 4];
        const unsigned width = 8 + view % 33, height = 8 + (view * 7) % 29;
        const CameraFrame frame(camera, width, height);
        const auto misses_all = [&](unsigned i0, unsigned j0, unsigned w, unsigned h) {
            for (unsigned j = j0; j < j0 + h; ++j) {
                for (unsigned i = i0; i < i0 + w; ++i) {
                    Ray r = frame.ray(i + 0.5, j + 0.5);
                    if (clip_ray(r, box)) return false;
                }
            }
            return true;
        };
        for (int k = 0; k < 20; ++k) {
            const unsigned i0 = static_cast<unsigned>(in(0, width)) % width;
            const unsigned j0 = static_cast<unsigned>(in(0, height)) % height;
            const unsigned w = 1 + static_cast<unsigned>(in(0, width - i0)) % (width - i0);
            const unsigned h = 1 + static_cast<unsigned>(in(0, height - j0)) % (height - j0);
            if (!frame.misses(i0, j0, w, h, box)) continue;
            ++claimed;
            EXPECT_TRUE(misses_all(i0, j0, w, h))
                << view << ": " << i0 << ", " << j0 << ", " << w << " x " << h;
        }
        for (unsigned j0 = 0; j0 + 4 <= height; j0 += 4) {
            for (unsigned i0 = 0; i0 + 4 <= width; i0 += 4) {
                const bool told = frame.misses(i0, j0, 4, 4, box);
                const bool all = misses_all(i0, j0, 4, 4);
                EXPECT_TRUE(!told || all) << view << ": " << i0 << ", " << j0;
                all_miss += all;
                caught += told && all;
            }
        }
    }
    EXPECT_GT(claimed, 100u);
    EXPECT_GT(caught, all_miss / 2);
}

TEST(Camera, SurfaceExtentEnclosesTheSurface) {
    const Box3 bounds{{{-2, 2}, {-2, 2}, {-2, 2}}};
    const auto box = surface_extent(sphere(), bounds);
    ASSERT_TRUE(box.has_value());
    for (int a = 0; a < 3; ++a) {
        EXPECT_LE((*box)[a][0], -1.0);
        EXPECT_GE((*box)[a][1], 1.0);
        EXPECT_GE((*box)[a][0], -1.5);  // cells of side 1/8 around the sphere
        EXPECT_LE((*box)[a][1], 1.5);
    }
    EXPECT_FALSE(surface_extent(expr::Tape(expr::parse_expr("x^2 + y^2 + z^2 + 1")), bounds));
    // A framed camera sees the whole box: its centre ray hits the sphere.
    const Camera cam = frame_box(*box, 35, 4.0 / 3.0);
    const CameraFrame f(cam, 64, 48);
    Ray r = f.ray(32, 24);
    ASSERT_TRUE(clip_ray(r, bounds));
    EXPECT_EQ(make_method("certified", sphere(), {})(r).status, Status::Hit);
}

/// Whether some cell of surface_cells touches a face of the bounds, cell by cell: what
/// surface_cells_touch_bounds must answer.
bool some_cell_touches(const expr::Tape& tape, const Box3& bounds) {
    for (const Box3& c : surface_cells(tape, bounds)) {
        for (int a = 0; a < 3; ++a) {
            if (c[a][0] <= bounds[a][0] || c[a][1] >= bounds[a][1]) return true;
        }
    }
    return false;
}

TEST(Camera, SurfaceTouchesTheBoundsAsItsCellsDo) {
    // The unit sphere inside [−2, 2]³ does not reach the faces; cut by them in [−0.9, 0.9]³ and
    // [0.5, 3]³ (a face at x = 0.5 crosses it) it does; a plane z = 1.5 reaches the sides of
    // [−2, 2]³ but not a box below it; an empty set reaches nothing.
    const expr::Tape plane(expr::parse_expr("z - 1.5"));
    const expr::Tape none(expr::parse_expr("x^2 + y^2 + z^2 + 1"));
    const Box3 wide{{{-2, 2}, {-2, 2}, {-2, 2}}}, tight{{{-0.9, 0.9}, {-0.9, 0.9}, {-0.9, 0.9}}},
        corner{{{0.5, 3}, {0.5, 3}, {-0.25, 0.25}}}, low{{{-2, 2}, {-2, 2}, {-2, 1}}};
    const struct {
        const expr::Tape& tape;
        Box3 bounds;
        bool touches;
    } cases[] = {{sphere(), wide, false}, {sphere(), tight, true}, {sphere(), corner, true},
                 {plane, wide, true},     {plane, low, false},     {none, wide, false}};
    for (const auto& c : cases) {
        EXPECT_EQ(surface_cells_touch_bounds(c.tape, c.bounds), c.touches);
        EXPECT_EQ(some_cell_touches(c.tape, c.bounds), c.touches);
    }
}

/// The subdivision on 1, 2 and 3 workers: the same cells in the same order, and the same answer
/// on the faces, at every depth; every point of the unit sphere (drawn on it) lies in a cell, and
/// every cell of the sphere's holds a point at distance 1 from the origin (a cell of side 1/8 at
/// level 5 reaches within its diagonal of the sphere).
TEST(Camera, SurfaceCellsAreTheSameOnAnyNumberOfThreads) {
    const expr::Tape torus(expr::parse_expr("(sqrt(x^2 + y^2) - 1)^2 + z^2 - 0.09"));
    const Box3 wide{{{-2, 2}, {-2, 2}, {-2, 2}}}, tight{{{-0.9, 0.9}, {-0.9, 0.9}, {-0.9, 0.9}}};
    for (const expr::Tape* tape : {&sphere(), &torus}) {
        for (const Box3& bounds : {wide, tight}) {
            for (int levels = 0; levels <= 5; ++levels) {
                const std::vector<Box3> one = surface_cells(*tape, bounds, levels, 1);
                const bool touches = surface_cells_touch_bounds(*tape, bounds, levels, 1);
                for (unsigned threads : {2u, 3u}) {
                    EXPECT_EQ(surface_cells(*tape, bounds, levels, threads), one)
                        << levels << " levels, " << threads << " threads";
                    EXPECT_EQ(surface_cells_touch_bounds(*tape, bounds, levels, threads), touches)
                        << levels << " levels, " << threads << " threads";
                }
            }
        }
    }
    const std::vector<Box3> cells = surface_cells(sphere(), wide, 5, 2);
    ASSERT_FALSE(cells.empty());
    std::mt19937 rng(7);
    std::normal_distribution<double> normal;
    for (int n = 0; n < 2000; ++n) {
        std::array<double, 3> p{normal(rng), normal(rng), normal(rng)};
        const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (double& c : p) c /= r;
        const bool inside = std::any_of(cells.begin(), cells.end(), [&](const Box3& c) {
            for (int a = 0; a < 3; ++a) {
                if (p[a] < c[a][0] - 1e-12 || p[a] > c[a][1] + 1e-12) return false;
            }
            return true;
        });
        EXPECT_TRUE(inside) << p[0] << " " << p[1] << " " << p[2];
    }
    for (const Box3& c : cells) {
        double near = 0, far = 0;  // squared distances from the origin to the cell
        for (int a = 0; a < 3; ++a) {
            const double lo = c[a][0], hi = c[a][1];
            const double nearest = lo > 0 ? lo : hi < 0 ? hi : 0.0;
            near += nearest * nearest;
            far += std::max(lo * lo, hi * hi);
        }
        EXPECT_LE(near, 1.0 + 1e-12);
        EXPECT_GE(far, 1.0 - 1e-12);
    }
}

TEST(Png, RoundTrip) {
    const fs::path dir =
        fs::temp_directory_path() / ("certray_png_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    RgbImage img(37, 21);
    std::mt19937 rng(7);
    for (auto& b : img.rgb) b = static_cast<std::uint8_t>(rng());
    const std::string path = (dir / "a.png").string();
    write_png(path, img);
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    const RgbImage back = read_png(path);
    EXPECT_EQ(back.width, 37u);
    EXPECT_EQ(back.height, 21u);
    EXPECT_EQ(back.rgb, img.rgb);
    // An unwritable place: an error, and no file.
    const std::string bad = (dir / "no_such_dir" / "b.png").string();
    EXPECT_THROW(write_png(bad, img), std::runtime_error);
    EXPECT_FALSE(fs::exists(bad));
    EXPECT_THROW(read_png((dir / "missing.png").string()), std::runtime_error);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace certray::tracers
