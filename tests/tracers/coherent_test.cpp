// tests/tracers/coherent_test.cpp — the coherent certified renderer (tracers/coherent.h) against
// the per-ray certified solver on the same rays, and against the MPFR reference.
//
// Agreement, pixel by pixel: the same status; two Hits both enclose the first root (a zero in the
// enclosure and none before it), so their enclosures intersect and each t_lo is at most the other's
// t_hi. On the gallery (pinhole and ortho) every pixel must agree. On random DAGs under random
// cameras the two may decide differently only where one says Unknown (their bisection grids and
// pruned tapes differ, and an undecided case is honest); a Hit against a Miss, or disjoint Hits,
// is a wrong answer of one of them and fails. Parts of the walk are checked on their own too: a
// lane list's walk against its whole list's, a segment's middle against the interval's midpoint,
// and every instruction set's copy of the walks and loads against the others, bit for bit.
#include "tracers/coherent.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "expr/derived.h"
#include "expr/load.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/solid.h"
#include "tests/support/batch_isa.h"
#include "tests/support/fp_env.h"
#include "tests/support/generators.h"
#include "tests/support/random_dag.h"
#include "tests/support/ray_checks.h"
#include "tracers/coherent_parts.h"
#include "tracers/segment_box.h"

namespace certray::tracers {
namespace {

namespace fs = std::filesystem;

const fs::path kScenes = fs::path(CERTRAY_SOURCE_DIR) / "scenes";

/// How the coherent answers compare with a per-ray solver's.
struct Agreement {
    unsigned rays = 0;        ///< pixels whose ray meets the bounds
    unsigned same = 0;        ///< same status (and consistent Hits)
    unsigned undecided = 0;   ///< one Unknown, the other decided
    unsigned wrong = 0;       ///< Hit against Miss, or Hits that cannot both hold
    std::string first_wrong;  ///< where the first wrong one is, and what each said
};

std::string describe(const RayResult& r) {
    return std::string(name(r.status)) + " [" + std::to_string(r.t_lo) + ", " +
           std::to_string(r.t_hi) + "]";
}

/// Whether two answers on one ray agree: the same status, and for two Hits enclosures that can
/// both hold the first root (each t_lo at most the other's t_hi).
bool agree(const RayResult& a, const RayResult& b) {
    if (a.status != b.status) return false;
    if (a.status != Status::Hit) return true;
    return a.t_lo <= b.t_hi && b.t_lo <= a.t_hi;
}

/// Whether two answers on one ray contradict each other (at least one is wrong).
bool contradict(const RayResult& a, const RayResult& b) {
    if (a.status == Status::Unknown || b.status == Status::Unknown) return false;
    return !agree(a, b);
}

void tally(Agreement& a, unsigned i, unsigned j, const RayResult& coherent, const RayResult& ref) {
    ++a.rays;
    if (agree(coherent, ref)) {
        ++a.same;
        return;
    }
    if (!contradict(coherent, ref)) {
        ++a.undecided;
        return;
    }
    if (a.wrong++ == 0) {
        a.first_wrong = "pixel (" + std::to_string(i) + ", " + std::to_string(j) + "): coherent " +
                        describe(coherent) + ", per-ray " + describe(ref);
    }
}

/// The coherent render of `tape` compared with the per-ray certified solver (its default options;
/// solid_first_entry under the solid surface) on every pixel's ray
/// (every `stride`-th pixel for the MPFR reference, when `reference` is set); the coherent answers
/// also into `coherent` when given, and what the walk did into `walk`.
Agreement against_per_ray(const expr::Tape& tape, const CoherentOptions& o, bool reference = false,
                          unsigned stride = 1, std::vector<RayResult>* coherent = nullptr,
                          CoherentStats* walk = nullptr) {
    CoherentStats own_stats;
    CoherentStats& stats = walk != nullptr ? *walk : own_stats;
    std::vector<RayResult> own;
    std::vector<RayResult>& results = coherent != nullptr ? *coherent : own;
    // Rendered as a host in CERTRAY_HOST_FPENV's state would call it (the default state unless the
    // fpenv runs set one): the answers must not depend on it.
    const RenderResult r =
        testing::as_host([&] { return render_3d_coherent(tape, o, &stats, &results); });
    const PixelRays rays(o);
    // The per-ray `certified` method: the solver's defaults, with the same budget per solve.
    solvers::CertifiedOptions per_ray;
    per_ray.budget = o.certified.budget;
    Agreement a;
    std::size_t k = 0;
    for (unsigned j = 0; j < o.render.height; ++j) {
        for (unsigned i = 0; i < o.render.width; ++i, ++k) {
            EXPECT_EQ(r.answers.status[k], results[k].status);
            EXPECT_EQ(r.answers.evals[k], results[k].evals.total());
            Ray ray;
            if (!rays.ray(i, j, ray)) {
                EXPECT_EQ(results[k].status, Status::Miss);
                EXPECT_EQ(results[k].evals.total(), 0u);
                continue;
            }
            if (k % stride != 0) continue;
            RayResult ref;
            if (o.surface == Surface::Solid) {
                solvers::SolidOptions so;
                so.budget = o.certified.budget;
                ref = reference ? solvers::solid_first_entry_reference(tape, ray, so)
                                : solvers::solid_first_entry(tape, ray, so);
            } else {
                ref = reference ? solvers::certified_first_root_reference(tape, ray, per_ray)
                                : solvers::certified_first_root(tape, ray, per_ray);
            }
            tally(a, i, j, results[k], ref);
        }
    }
    return a;
}

/// The 3D scenes of the gallery (.vm and .expr that read z).
std::vector<fs::path> gallery() {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(kScenes)) {
        const std::string ext = e.path().extension().string();
        if (ext != ".vm" && ext != ".expr") continue;
        if (e.path().filename() == "prospero.vm") continue;  // 2D
        out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

CoherentOptions small_view(Projection p) {
    CoherentOptions o;
    o.render.width = o.render.height = 48;
    o.render.bounds = {{{-2, 2}, {-2, 2}, {-2, 2}}};
    o.render.camera = frame_box(o.render.bounds, 35, 1.0);
    o.render.threads = 2;
    o.projection = p;
    return o;
}

TEST(Coherent, GalleryAgreesWithThePerRaySolverPixelByPixel) {
    unsigned scenes = 0;
    for (const fs::path& path : gallery()) {
        const expr::Tape tape(expr::load_graph_file(path.string()));
        if (!tape.uses_var(2)) continue;
        ++scenes;
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            const CoherentOptions o = small_view(p);
            const Agreement a = against_per_ray(tape, o);
            const std::string where =
                path.filename().string() + (p == Projection::Pinhole ? " pinhole" : " ortho");
            EXPECT_EQ(a.wrong, 0u) << where << ": " << a.first_wrong;
            EXPECT_EQ(a.undecided, 0u) << where;
            EXPECT_EQ(a.same, a.rays) << where;
            EXPECT_GT(a.rays, 0u) << where;
        }
    }
    EXPECT_GE(scenes, 10u);
}

// Solid: two answers agree as for the zero set (two Hits both enclose the first entry, so their
// enclosures intersect). The walk may decide where the per-ray solver cannot (its boxes are pruned
// per region), never the other way round, and never against it.
TEST(Coherent, SolidAgreesWithThePerRaySolidSolver) {
    std::vector<fs::path> scenes = gallery();
    for (const char* m : {"fidget/bear.vm", "fidget/colonnade.vm", "tanglecube.vm"}) {
        scenes.push_back(kScenes / m);
    }
    for (const fs::path& path : scenes) {
        const expr::Tape tape(expr::load_graph_file(path.string()));
        if (!tape.uses_var(2)) continue;
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            CoherentOptions o = small_view(p);
            o.surface = Surface::Solid;
            o.render.width = o.render.height = 24;
            if (path.parent_path().filename() == "fidget")
                o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
            o.render.camera = frame_box(o.render.bounds, 35, 1.0);
            std::vector<RayResult> results;
            const Agreement a = against_per_ray(tape, o, false, 1, &results);
            const std::string where =
                path.filename().string() + (p == Projection::Pinhole ? " pinhole" : " ortho");
            EXPECT_EQ(a.wrong, 0u) << where << ": " << a.first_wrong;
            EXPECT_GT(a.rays, 0u) << where;
            // Where the two differ, the per-ray solver is the one that said Unknown.
            const PixelRays rays(o);
            solvers::SolidOptions so;
            so.budget = o.certified.budget;
            for (std::size_t k = 0; k < results.size(); ++k) {
                if (results[k].status != Status::Unknown) continue;
                Ray ray;
                if (!rays.ray(static_cast<unsigned>(k % o.render.width),
                              static_cast<unsigned>(k / o.render.width), ray)) {
                    continue;
                }
                EXPECT_EQ(solvers::solid_first_entry(tape, ray, so).status, Status::Unknown)
                    << where << ": pixel " << k;
            }
        }
    }
}

/// An image's scan that leaves a segment undecided on a list with choices splits it with a tape
/// pruned to each half before any solver runs on it. Fidget's colonnade touches 0 along planes
/// (max(c − x, x − c) once its other choices are pruned): there the halves' pruned lists decide
/// what the solver on the scan's list could not. The answers agree with the per-ray solid solver,
/// no pixel is left unknown, and the splits are taken.
TEST(Coherent, UndecidedScansOnListsWithChoicesAreSplit) {
    const expr::Tape tape(expr::load_graph_file((kScenes / "fidget/colonnade.vm").string()));
    for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
        CoherentOptions o = small_view(p);
        o.surface = Surface::Solid;
        o.render.width = o.render.height = 40;
        o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
        o.render.camera = frame_box(o.render.bounds, 35, 1.0);
        o.certified = image_solver_options();
        o.depth_pixels = 0.5;  // scans, as the CLI's images
        std::vector<RayResult> results;
        CoherentStats stats;
        const Agreement a = against_per_ray(tape, o, false, 1, &results, &stats);
        const char* where = p == Projection::Pinhole ? "pinhole" : "ortho";
        EXPECT_EQ(a.wrong, 0u) << where << ": " << a.first_wrong;
        EXPECT_GT(a.rays, 0u) << where;
        EXPECT_EQ(std::count_if(results.begin(), results.end(),
                                [](const RayResult& r) { return r.status == Status::Unknown; }),
                  0)
            << where;
        EXPECT_GT(stats.splits, 0u) << where;
    }
}

TEST(Coherent, SolidHitsHoldTheEntryOfMathematics) {
    // The ball of radius 1 seen along −z over [−2, 2]³: a ray at (x, y) enters at
    // z = sqrt(1 − x² − y²), t = 2 − z; the first entry lies in every Hit's enclosure.
    const expr::Tape tape(expr::parse_expr("x^2 + y^2 + z^2 - 1"));
    CoherentOptions o = small_view(Projection::Ortho);
    o.surface = Surface::Solid;
    CoherentStats stats;
    std::vector<RayResult> results;
    const RenderResult r = render_3d_coherent(tape, o, &stats, &results);
    const PixelRays rays(o);
    unsigned hits = 0;
    for (std::size_t k = 0; k < results.size(); ++k) {
        Ray ray;
        ASSERT_TRUE(rays.ray(static_cast<unsigned>(k % 48), static_cast<unsigned>(k / 48), ray));
        const double x = ray.o[0], y = ray.o[1], rr = x * x + y * y;
        if (rr < 1 - 1e-9) {
            ASSERT_EQ(results[k].status, Status::Hit) << k;
            const double t = 2 - std::sqrt(1 - rr);
            EXPECT_LE(results[k].t_lo, t + 1e-12) << k;
            EXPECT_GE(results[k].t_hi, t - 1e-12) << k;
            ++hits;
        } else if (rr > 1 + 1e-9) {
            EXPECT_EQ(results[k].status, Status::Miss) << k;
        }
    }
    EXPECT_GT(hits, 100u);
    EXPECT_EQ(r.stats.unknown, 0u);

    // Over [−1/2, 1/2]³ every ray starts inside the ball (the corners are at distance √3/2 < 1):
    // boxes proven inside answer them Hit [0, 0] at once.
    o.render.bounds = {{{-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}}};
    const RenderResult in = render_3d_coherent(tape, o, &stats, &results);
    EXPECT_EQ(in.stats.hit, 48u * 48u);
    EXPECT_GT(stats.boxes_inside, 0u);
    for (const RayResult& res : results) {
        ASSERT_EQ(res.status, Status::Hit);
        EXPECT_EQ(res.t_lo, 0.0);
        EXPECT_EQ(res.t_hi, 0.0);
    }
}

TEST(Coherent, TilePiecesAnswerFlatFacesWithTheRootOfMathematics) {
    // A tilted plane seen as a heightmap over [−1, 1]³ (Fidget's columns and floors, tilted so
    // that no bound is a round number): the ray at (x, y) meets z = 0.3 + 0.05x − 0.02y at
    // t = 1 − z. Its tiles' pieces answer many rays at once (the piece after the one holding the
    // plane is proven inside, or the pieces either side have strict opposite signs; where the
    // plane crosses a piece's end inside a tile, its rays are scanned alone); every Hit
    // holds t, zero set and solid, with and without them, at 32² and 128². With the lines of
    // the node forms (clip_forms), which narrow a node to the plane before its scan, too. The
    // plane's list is smooth: with the segments' forms on (the default), the tile pieces yield to
    // them (Walker::tile_pieces_for) and are never tried; variants 0 and 2 turn the forms off.
    const expr::Tape tape(expr::parse_expr("z - 0.3 - 0.05*x + 0.02*y"));
    for (Surface surface : {Surface::Solid, Surface::Zero}) {
        for (int variant : {0, 1, 2, 3}) {  // tiles; no tiles; tiles and lines; the defaults
            const bool tiles = variant != 1;
            for (unsigned side : {32u, 128u}) {
                CoherentOptions o;
                o.render.width = o.render.height = side;
                o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
                o.render.threads = 1;
                o.projection = Projection::Ortho;
                o.surface = surface;
                o.certified = image_solver_options();
                o.depth_pixels = 0.5;
                o.tile_pieces = tiles;
                o.clip_forms = variant >= 2;
                o.segment_forms = variant == 3;
                CoherentStats stats;
                std::vector<RayResult> results;
                const RenderResult r = render_3d_coherent(tape, o, &stats, &results);
                const PixelRays rays(o);
                const std::string where =
                    std::string(surface == Surface::Solid ? "solid" : "zero") +
                    (tiles ? " tiles " : " no tiles ") + (o.clip_forms ? "lines " : "") +
                    (o.segment_forms ? "forms " : "") + std::to_string(side);
                ASSERT_EQ(r.stats.hit, std::size_t{side} * side) << where;
                for (std::size_t k = 0; k < results.size(); ++k) {
                    Ray ray;
                    ASSERT_TRUE(rays.ray(static_cast<unsigned>(k % side),
                                         static_cast<unsigned>(k / side), ray));
                    const double t = 1 - (0.3 + 0.05 * ray.o[0] - 0.02 * ray.o[1]);
                    EXPECT_LE(results[k].t_lo, t + 1e-12) << where << " " << k;
                    EXPECT_GE(results[k].t_hi, t - 1e-12) << where << " " << k;
                    EXPECT_LE(results[k].t_hi - results[k].t_lo, 0.5 * 2.0 / side + 1e-12)
                        << where << " " << k;
                }
                if (variant == 0) {
                    // A quarter of the rays at least (at 32², where each root tile tries the tile
                    // pieces while they answer rays: 256 of 1,024 rays; at 128², 43%).
                    EXPECT_GE(stats.tile_decided, std::size_t{side} * side / 4) << where;
                } else if (variant == 1) {
                    EXPECT_EQ(stats.tile_pieces, 0u) << where;
                } else if (variant == 2) {
                    EXPECT_GT(stats.clipped, 0u) << where;
                } else {
                    EXPECT_EQ(stats.tile_pieces, 0u) << where;  // the forms decide instead
                }
            }
        }
    }
}

/// Where the ray o + t·d meets the unit sphere x² + y² + z² = 1, in long double: the
/// discriminant of a·t² + b·t + c (a = d·d, b = 2 o·d, c = o·o − 1) and its first root
/// (−b − √disc) / 2a (NaN where disc < 0).
struct SphereRoot {
    long double disc, t;
};
SphereRoot unit_sphere_root(const Ray& ray) {
    using L = long double;
    const L a = L(ray.d[0]) * ray.d[0] + L(ray.d[1]) * ray.d[1] + L(ray.d[2]) * ray.d[2];
    const L b = 2 * (L(ray.o[0]) * ray.d[0] + L(ray.o[1]) * ray.d[1] + L(ray.o[2]) * ray.d[2]);
    const L c = L(ray.o[0]) * ray.o[0] + L(ray.o[1]) * ray.o[1] + L(ray.o[2]) * ray.o[2] - 1;
    const L disc = b * b - 4 * a * c;
    return {disc, (-b - std::sqrt(disc)) / (2 * a)};
}

TEST(Coherent, HitsAreHalfAPixelDeepAndHoldTheRootOfMathematics) {
    // The unit sphere: a ray o + t·d meets it first at t = (−b − √(b² − 4ac)) / 2a with a = d·d,
    // b = 2 o·d, c = o·o − 1. An image's hit enclosure holds that root and is at most half a pixel
    // footprint deep (pinhole: 0.5 · pitch · t; ortho: 0.5 · pitch); a depth AOV keeps 1e-6 (its
    // pieces are that deep: scanned only where the lines of the forms clip a node that short).
    // The third form (a positive factor: the same sphere, the same solid) is long enough for the
    // segment forms, which then prove the segments of rays that pass near the sphere.
    const char* const with_forms = "(x^2 + y^2 + z^2 - 1) * (2 + x^2 + 2*y^2 + 3*z^2)";
    for (const char* f : {"x^2 + y^2 + z^2 - 1", "sqrt(x^2 + y^2 + z^2) - 1", with_forms}) {
        const expr::Tape tape(expr::parse_expr(f));
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            for (Surface surface : {Surface::Zero, Surface::Solid}) {
                for (Aov aov : {Aov::Shade, Aov::Depth}) {
                    CoherentOptions o = small_view(p);
                    o.surface = surface;
                    o.render.aov = aov;
                    o.depth_pixels = 0.5;
                    std::vector<RayResult> results;
                    CoherentStats stats;
                    render_3d_coherent(tape, o, &stats, &results);
                    const PixelRays rays(o);
                    const double pitch = rays.pixel_pitch();
                    const std::string where = std::string(f) +
                                              (p == Projection::Pinhole ? " pinhole" : " ortho") +
                                              (surface == Surface::Solid ? " solid" : " zero") +
                                              (aov == Aov::Depth ? " depth" : " shade");
                    unsigned hits = 0;
                    double widest = 0;  // the widest enclosure relative to the allowed depth
                    for (std::size_t k = 0; k < results.size(); ++k) {
                        const RayResult& r = results[k];
                        if (r.status != Status::Hit) continue;
                        Ray ray;
                        ASSERT_TRUE(rays.ray(static_cast<unsigned>(k % 48),
                                             static_cast<unsigned>(k / 48), ray));
                        const SphereRoot root = unit_sphere_root(ray);
                        if (root.disc < 1e-9) continue;  // grazing: the tangent is its own question
                        const double t = static_cast<double>(root.t);
                        ++hits;
                        EXPECT_LE(r.t_lo, t + 1e-12) << where << " pixel " << k;
                        EXPECT_GE(r.t_hi, t - 1e-12) << where << " pixel " << k;
                        const double allowed = aov == Aov::Depth          ? 1e-6 * r.t_hi
                                               : p == Projection::Pinhole ? 0.5 * pitch * r.t_hi
                                                                          : 0.5 * pitch;
                        widest = std::max(widest, (r.t_hi - r.t_lo) / allowed);
                    }
                    EXPECT_GT(hits, 100u) << where;
                    EXPECT_LE(widest, 1.0 + 1e-9) << where;
                    // The option is used: some enclosure is wider than the depth AOV's 1e-6, and
                    // leaf segments were decided by scanning pieces of that depth.
                    if (aov == Aov::Shade) {
                        EXPECT_GT(widest, 1e-3) << where;
                        EXPECT_GT(stats.scans, 0u) << where;
                        EXPECT_GT(stats.together, 0u) << where;  // rays scanned together
                        if (f == with_forms) {
                            EXPECT_GT(stats.segment_forms, 0u) << where;
                            // Zeros (the solid: entries) bracketed on strictly monotone
                            // segments, halved at points.
                            EXPECT_GT(stats.monotone_segments, 0u) << where;
                        }
                    }
                }
            }
        }
    }
}

TEST(Coherent, ImageScansInLanesAgreeWithThePerRaySolver) {
    // What `certray render` asks for an image: hits half a pixel deep, leaf segments scanned in
    // lanes, undecided pieces given the mean value form in the same lanes (lane_mean_value) or
    // one ray at a time (off), and scanned again in quarters in lanes where that does not
    // decide. All keep every pixel's per-ray answer; on the polynomial scenes the lanes' form is
    // what decides pieces near the surface.
    std::uint64_t barth_forms = 0, quarters = 0;
    for (const fs::path& path : gallery()) {
        const expr::Tape tape(expr::load_graph_file(path.string()));
        if (!tape.uses_var(2)) continue;
        for (Surface surface : {Surface::Zero, Surface::Solid}) {
            for (int variant : {0, 1, 2}) {
                const bool lanes = variant != 2;
                CoherentOptions o = small_view(Projection::Pinhole);
                o.certified = image_solver_options();
                o.depth_pixels = 0.5;
                o.surface = surface;
                o.lane_mean_value = lanes;
                o.tile_pieces = variant == 0;
                CoherentStats stats;
                const Agreement a = against_per_ray(tape, o, false, 1, nullptr, &stats);
                const std::string where = path.filename().string() +
                                          (surface == Surface::Solid ? " solid" : " zero") +
                                          (variant == 0 ? " tiles"
                                           : lanes      ? " lane forms"
                                                        : " one ray at a time");
                EXPECT_EQ(a.wrong, 0u) << where << ": " << a.first_wrong;
                EXPECT_EQ(a.undecided, 0u) << where;
                EXPECT_EQ(a.same, a.rays) << where;
                if (!lanes) {
                    EXPECT_EQ(stats.lane_forms, 0u) << where;
                }
                if (lanes && path.filename() == "barth_sextic.vm") barth_forms += stats.lane_forms;
                quarters += stats.quarter_pieces;
            }
        }
    }
    EXPECT_GT(barth_forms, 0u);
    EXPECT_GT(quarters, 0u);  // the quarters' lanes were among what agreed
}

TEST(Coherent, SegmentFormsKeepEveryAnswerAndSpareEvaluations) {
    // The segment forms (CoherentOptions::segment_forms) only prove segments free that the
    // pieces would have proven free or left to the solver, and the monotone segments
    // (monotone_segments) only answer a zero that the pieces would have found: with and without
    // them, every pixel of the smooth algebraic scenes has the same status and consistent Hits,
    // and all agree with the per-ray solver. The forms prove segments on the zero sets, zeros are
    // bracketed on monotone segments, and on Chmutov's sextic, whose sheets many rays run beside,
    // the image takes fewer evaluations with each.
    std::uint64_t brackets = 0;
    for (const char* name : {"chmutov6.vm", "barth_sextic.vm", "mitchell.vm"}) {
        const expr::Tape tape(expr::load_graph_file((kScenes / name).string()));
        for (Surface surface : {Surface::Zero, Surface::Solid}) {
            std::vector<RayResult> answers[3];
            CoherentStats stats[3];
            std::uint64_t evals[3] = {0, 0, 0};
            for (int variant : {0, 1, 2}) {  // none, forms, forms and monotone segments
                CoherentOptions o = small_view(Projection::Pinhole);
                o.certified = image_solver_options();
                o.depth_pixels = 0.5;
                o.surface = surface;
                o.segment_forms = variant >= 1;
                o.monotone_segments = variant == 2;
                const Agreement a =
                    against_per_ray(tape, o, false, 1, &answers[variant], &stats[variant]);
                const std::string where = std::string(name) +
                                          (surface == Surface::Solid ? " solid" : " zero") +
                                          " variant " + std::to_string(variant);
                EXPECT_EQ(a.wrong, 0u) << where << ": " << a.first_wrong;
                EXPECT_EQ(a.undecided, 0u) << where;
                for (const RayResult& r : answers[variant]) evals[variant] += r.evals.total();
            }
            const std::string where =
                std::string(name) + (surface == Surface::Solid ? " solid" : " zero");
            for (int variant : {1, 2}) {
                ASSERT_EQ(answers[0].size(), answers[variant].size());
                for (std::size_t k = 0; k < answers[0].size(); ++k) {
                    EXPECT_TRUE(agree(answers[0][k], answers[variant][k]))
                        << where << " variant " << variant << " pixel " << k << ": "
                        << describe(answers[0][k]) << " against " << describe(answers[variant][k]);
                }
            }
            EXPECT_EQ(stats[0].segment_forms, 0u) << where;
            EXPECT_EQ(stats[1].monotone_segments, 0u) << where;
            if (surface == Surface::Zero) {
                EXPECT_GT(stats[1].segment_forms, 0u) << where;
                brackets += stats[2].monotone_segments;
            }
            if (surface == Surface::Zero && std::string(name) == "chmutov6.vm") {
                EXPECT_LT(evals[1], evals[0]) << where;
            }
        }
    }
    EXPECT_GT(brackets, 0u);
}

/// Renders `tape` with `o`, the option `flag` off and then on, each checked against the per-ray
/// solver (no wrong answer, none undecided), and checks that every pixel has the same status and
/// consistent Hits either way. The stats off and on.
std::array<CoherentStats, 2> expect_same_statuses_either_way(const expr::Tape& tape,
                                                             CoherentOptions o,
                                                             bool CoherentOptions::*flag,
                                                             const std::string& where) {
    std::vector<RayResult> answers[2];
    std::array<CoherentStats, 2> stats;
    for (int on : {0, 1}) {
        o.*flag = on == 1;
        const Agreement a = against_per_ray(tape, o, false, 1, &answers[on], &stats[on]);
        EXPECT_EQ(a.wrong, 0u) << where << (on ? " on" : " off") << ": " << a.first_wrong;
        EXPECT_EQ(a.undecided, 0u) << where << (on ? " on" : " off");
    }
    EXPECT_EQ(answers[0].size(), answers[1].size()) << where;
    for (std::size_t k = 0; k < std::min(answers[0].size(), answers[1].size()); ++k) {
        EXPECT_TRUE(agree(answers[0][k], answers[1][k]))
            << where << " pixel " << k << ": " << describe(answers[0][k]) << " against "
            << describe(answers[1][k]);
    }
    return stats;
}

TEST(Coherent, NewtonBracketsHoldTheRootOfMathematicsAndKeepTheAnswers) {
    // A monotone segment's zero bracketed by interval Newton steps (newton_brackets): every zero
    // lies in c − g(c)/G′, so a bracket narrowed to it still holds the root. The sphere as a
    // product with a positive factor (long enough for the segment forms): the first root of
    // a·t² + b·t + c in long double (a = d·d, b = 2 o·d, c = o·o − 1) lies in every Hit, to the
    // rounding of that root; the solid's g is < 0 at t_hi (past the entry, so t_hi > root). The
    // steps bracket zeros without an end point.
    const expr::Tape sphere(expr::parse_expr("(x^2 + y^2 + z^2 - 1) * (2 + x^2 + 2*y^2 + 3*z^2)"));
    for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
        for (Surface surface : {Surface::Zero, Surface::Solid}) {
            CoherentOptions o = small_view(p);
            o.surface = surface;
            o.depth_pixels = 0.5;
            o.coarse_scans = false;  // segments of at most 8 pieces, as the brackets were measured
            std::vector<RayResult> results;
            CoherentStats stats;
            render_3d_coherent(sphere, o, &stats, &results);
            const PixelRays rays(o);
            const std::string where = std::string(p == Projection::Pinhole ? "pinhole" : "ortho") +
                                      (surface == Surface::Solid ? " solid" : " zero");
            unsigned hits = 0;
            for (std::size_t k = 0; k < results.size(); ++k) {
                const RayResult& r = results[k];
                if (r.status != Status::Hit) continue;
                Ray ray;
                ASSERT_TRUE(
                    rays.ray(static_cast<unsigned>(k % 48), static_cast<unsigned>(k / 48), ray));
                const SphereRoot root = unit_sphere_root(ray);
                if (root.disc < 1e-9) continue;  // grazing
                const long double t = root.t;
                const long double slack = 1e-17L * t;  // the long double root's own rounding
                ++hits;
                EXPECT_LE(r.t_lo, t + slack) << where << " pixel " << k;
                EXPECT_GE(r.t_hi, t - slack) << where << " pixel " << k;
                if (surface == Surface::Solid) {
                    EXPECT_GT(r.t_hi, t - slack) << where << " pixel " << k;
                }
            }
            EXPECT_GT(hits, 100u) << where;
            EXPECT_GT(stats.newton_brackets, 30u) << where;
        }
    }
    // With and without the steps: every pixel of the smooth algebraic scenes the same status and
    // consistent Hits, both agreeing with the per-ray solver; without them no step brackets.
    std::uint64_t stepped = 0;
    for (const char* name : {"chmutov6.vm", "barth_sextic.vm", "mitchell.vm"}) {
        const expr::Tape tape(expr::load_graph_file((kScenes / name).string()));
        for (Surface surface : {Surface::Zero, Surface::Solid}) {
            CoherentOptions o = small_view(Projection::Pinhole);
            o.certified = image_solver_options();
            o.depth_pixels = 0.5;
            o.surface = surface;
            const std::string where =
                std::string(name) + (surface == Surface::Solid ? " solid" : " zero");
            const auto stats =
                expect_same_statuses_either_way(tape, o, &CoherentOptions::newton_brackets, where);
            EXPECT_EQ(stats[0].newton_brackets, 0u) << where;
            stepped += stats[1].newton_brackets;
        }
    }
    EXPECT_GT(stepped, 0u);
}

/// expect_same_statuses_either_way for `flag` on 96² views of Barth's, Chmutov's and Kummer's
/// surfaces, pinhole (bounds [−2, 2]³) and heightmap (over [−1, 1]³), zero set and solid, as the
/// CLI renders them; `check` gets each view's name and the stats off and on.
void for_smooth_views_either_way(
    bool CoherentOptions::*flag,
    const std::function<void(const std::string&, const std::array<CoherentStats, 2>&)>& check) {
    for (const char* name : {"barth_sextic.vm", "chmutov6.vm", "kummer_quartic.vm"}) {
        const expr::Tape tape(expr::load_graph_file((kScenes / name).string()));
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            for (Surface surface : {Surface::Zero, Surface::Solid}) {
                CoherentOptions o = small_view(p);
                o.render.width = o.render.height = 96;
                if (p == Projection::Ortho) o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
                o.certified = image_solver_options();
                o.depth_pixels = 0.5;
                o.surface = surface;
                const std::string where = std::string(name) +
                                          (p == Projection::Pinhole ? " pinhole" : " ortho") +
                                          (surface == Surface::Solid ? " solid" : " zero");
                check(where, expect_same_statuses_either_way(tape, o, flag, where));
            }
        }
    }
}

/// for_smooth_views_either_way for `flag`, where `counter` counts nothing without the option:
/// what it counts with the option, over all the views.
std::uint64_t smooth_views_count_only_with(bool CoherentOptions::*flag,
                                           std::uint64_t CoherentStats::*counter) {
    std::uint64_t counted = 0;
    for_smooth_views_either_way(flag, [&](const std::string& where, const auto& stats) {
        EXPECT_EQ(stats[0].*counter, 0u) << where;
        counted += stats[1].*counter;
    });
    return counted;
}

TEST(Coherent, MergedScansKeepTheAnswers) {
    // A node's quarters scanned together (merged_scans), each ray over its own quarter's [a, b]:
    // with and without, every pixel of the smooth algebraic scenes has the same status and
    // consistent Hits, both agreeing with the per-ray solver; scans were merged, and none
    // without the option.
    EXPECT_GT(
        smooth_views_count_only_with(&CoherentOptions::merged_scans, &CoherentStats::merged_scans),
        0u);
}

TEST(Coherent, CoarseScansKeepTheAnswers) {
    // Scans of segments up to 32 pieces long, the undecided ones left to the node's halves in t
    // (coarse_scans): with and without, every pixel of the smooth algebraic scenes has the same
    // status and consistent Hits, both agreeing with the per-ray solver (a ray that the halves
    // lost, or one they answered although it was closed, would be a Miss or a wrong Hit); rays
    // were left to the halves, and none without the option.
    EXPECT_GT(smooth_views_count_only_with(&CoherentOptions::coarse_scans,
                                           &CoherentStats::coarse_deferred),
              0u);
    // The root that mathematics gives, in every Hit of a coarse scan: the sphere as a product
    // with a positive factor (a smooth list long enough for the segment forms), its first root
    // of a·t² + b·t + c in long double.
    const expr::Tape sphere(expr::parse_expr("(x^2 + y^2 + z^2 - 1) * (2 + x^2 + 2*y^2 + 3*z^2)"));
    for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
        CoherentOptions o = small_view(p);
        o.render.width = o.render.height = 96;
        o.depth_pixels = 0.5;
        std::vector<RayResult> results;
        render_3d_coherent(sphere, o, nullptr, &results);
        const PixelRays rays(o);
        unsigned hits = 0;
        for (std::size_t k = 0; k < results.size(); ++k) {
            Ray ray;
            const RayResult& r = results[k];
            if (!rays.ray(static_cast<unsigned>(k % 96), static_cast<unsigned>(k / 96), ray)) {
                EXPECT_EQ(r.status, Status::Miss) << k;  // outside the bounds
                continue;
            }
            const SphereRoot root = unit_sphere_root(ray);
            if (root.disc < -1e-9) {
                EXPECT_EQ(r.status, Status::Miss) << k;
                continue;
            }
            if (root.disc < 1e-9 || root.t < ray.tmin || root.t > ray.tmax)
                continue;  // grazing, or off
            ASSERT_EQ(r.status, Status::Hit) << k;
            const long double slack = 1e-17L * root.t;
            EXPECT_LE(r.t_lo, root.t + slack) << k;
            EXPECT_GE(r.t_hi, root.t - slack) << k;
            ++hits;
        }
        // Not a vacuous check: the heightmap sees the sphere's disc, π/16 of 96² pixels (1809).
        EXPECT_GT(hits, p == Projection::Pinhole ? 400u : 1700u);
    }
}

TEST(Coherent, SecondOrderFormsKeepTheAnswers) {
    // A segment that its first-order form leaves undecided and not monotone gets the
    // second-order form (second_order_forms): what it proves free holds no zero (the solid: no
    // inside point). With and without, every pixel of the smooth algebraic scenes has the same
    // status and consistent Hits, both agreeing with the per-ray solver; Chmutov's heightmap,
    // whose rays run beside the walls of its holes, has segments proven so, and none is without
    // the option.
    std::uint64_t proven = 0;
    for_smooth_views_either_way(&CoherentOptions::second_order_forms,
                                [&](const std::string& where, const auto& stats) {
                                    EXPECT_EQ(stats[0].second_order, 0u) << where;
                                    proven += stats[1].second_order;
                                    if (where == "chmutov6.vm ortho solid") {
                                        EXPECT_GT(stats[1].second_order, 0u) << where;
                                    }
                                });
    EXPECT_GT(proven, 0u);

    // Rays that come within a hair of a surface again and again: g(t) = T₆(z) + x + 1.5 along a
    // heightmap's ray at (x, y) (T₆ = 32z⁶ − 48z⁴ + 18z² − 1, Chebyshev's, whose minima −1 lie at
    // z = cos(π/6), 0, −cos(π/6)), over [−1.05, 1.05]³ at 96². A ray with x > −0.5 meets nothing
    // (g ≥ x + 0.5 > 0) and passes three near-tangencies where x is close to −0.5; one with
    // x < −0.5 enters first at z = cos(arccos(−(x + 1.5))/6), t = 1.05 − z. Every pixel has the
    // status mathematics gives and every Hit holds its root, with the second-order forms
    // proving grazing segments free.
    const expr::Tape rims(expr::parse_expr("32*z^6 - 48*z^4 + 18*z^2 - 1 + x + 1.5"));
    for (Surface surface : {Surface::Zero, Surface::Solid}) {
        CoherentOptions o = small_view(Projection::Ortho);
        o.render.width = o.render.height = 96;
        o.render.bounds = {{{-1.05, 1.05}, {-1.05, 1.05}, {-1.05, 1.05}}};
        o.certified = image_solver_options();
        o.depth_pixels = 0.5;
        o.surface = surface;
        std::vector<RayResult> results;
        CoherentStats stats;
        render_3d_coherent(rims, o, &stats, &results);
        const PixelRays rays(o);
        const std::string where = surface == Surface::Solid ? "T6 rims, solid" : "T6 rims, zero";
        unsigned misses = 0, hits = 0;
        for (std::size_t k = 0; k < results.size(); ++k) {
            Ray ray;
            ASSERT_TRUE(
                rays.ray(static_cast<unsigned>(k % 96), static_cast<unsigned>(k / 96), ray));
            const double x = ray.o[0];
            if (x > -0.5 + 1e-9) {
                EXPECT_EQ(results[k].status, Status::Miss) << where << " pixel " << k;
                ++misses;
            } else if (x < -0.5 - 1e-9) {
                ASSERT_EQ(results[k].status, Status::Hit) << where << " pixel " << k;
                const double t = 1.05 - std::cos(std::acos(-(x + 1.5)) / 6);
                EXPECT_LE(results[k].t_lo, t + 1e-9) << where << " pixel " << k;
                EXPECT_GE(results[k].t_hi, t - 1e-9) << where << " pixel " << k;
                ++hits;
            }
        }
        EXPECT_GT(misses, 1000u) << where;
        EXPECT_GT(hits, 1000u) << where;
        EXPECT_GT(stats.second_order, 0u) << where;
    }
}

TEST(Coherent, LinesOfTheFormsClipSegmentsAndKeepTheAnswers) {
    // Where a mean value form does not prove a node's box or a scanned segment free, its line in
    // t narrows the parameter range (clip_forms): what it cuts off holds no zero (the solid: no
    // inside point), so with and without the clips every pixel of the smooth algebraic scenes has
    // the same status and consistent Hits, both agree with the per-ray solver, and Chmutov's
    // solid heightmap, whose rays run beside its sheets, takes fewer evaluations with them.
    for (const char* name : {"chmutov6.vm", "barth_sextic.vm", "kummer_quartic.vm"}) {
        const expr::Tape tape(expr::load_graph_file((kScenes / name).string()));
        for (Projection projection : {Projection::Pinhole, Projection::Ortho}) {
            for (Surface surface : {Surface::Zero, Surface::Solid}) {
                std::vector<RayResult> answers[2];
                CoherentStats stats[2];
                std::uint64_t evals[2] = {0, 0};
                const std::string where = std::string(name) +
                                          (projection == Projection::Ortho ? " ortho" : "") +
                                          (surface == Surface::Solid ? " solid" : " zero");
                for (int clip : {0, 1}) {
                    CoherentOptions o = small_view(projection);
                    if (projection == Projection::Ortho) {
                        o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
                    }
                    o.certified = image_solver_options();
                    o.depth_pixels = 0.5;
                    o.surface = surface;
                    o.clip_forms = clip == 1;
                    const Agreement a =
                        against_per_ray(tape, o, false, 1, &answers[clip], &stats[clip]);
                    EXPECT_EQ(a.wrong, 0u) << where << " clip " << clip << ": " << a.first_wrong;
                    EXPECT_EQ(a.undecided, 0u) << where << " clip " << clip;
                    for (const RayResult& r : answers[clip]) evals[clip] += r.evals.total();
                }
                ASSERT_EQ(answers[0].size(), answers[1].size());
                for (std::size_t k = 0; k < answers[0].size(); ++k) {
                    EXPECT_TRUE(agree(answers[0][k], answers[1][k]))
                        << where << " pixel " << k << ": " << describe(answers[0][k]) << " against "
                        << describe(answers[1][k]);
                }
                EXPECT_EQ(stats[0].clipped, 0u) << where;
                EXPECT_GT(stats[1].clipped, 0u) << where;
                if (std::string(name) == "chmutov6.vm" && projection == Projection::Ortho &&
                    surface == Surface::Solid) {
                    EXPECT_LT(evals[1], evals[0]) << where;
                }
            }
        }
    }
}

TEST(Coherent, FoldedListsKeepTheRootsOfMathematics) {
    // The unit sphere times a positive factor 1 + Σ exp(−40·|p − c_i|²) with twelve Gaussians
    // centred beside it: the zero set and the solid are exactly the unit ball's, and the list
    // (about 180 instructions, nothing to prune) has terms that are all but constant near the
    // sphere, which the scans fold (CoherentOptions::fold_lists). Seen along −z over [−2, 2]³, a
    // ray at (x, y) with x² + y² < 1 meets the sphere first at z = √(1 − x² − y²), t = 2 − z:
    // every Hit holds it, with folding and without, the same statuses, on both surfaces. Fidget's
    // bear, folded, agrees with the per-ray solver.
    std::string factor = "1";
    for (int k = 0; k < 12; ++k) {
        const double a = 0.5 * k;  // centres on a helix of radius 1.6 around the z axis
        const double c[3] = {1.6 * std::cos(a), 1.6 * std::sin(a), -1.5 + 0.25 * k};
        factor += " + exp(-40*((x - " + std::to_string(c[0]) + ")^2 + (y - " +
                  std::to_string(c[1]) + ")^2 + (z - " + std::to_string(c[2]) + ")^2))";
    }
    const expr::Tape tape(expr::parse_expr("(x^2 + y^2 + z^2 - 1)*(" + factor + ")"));
    ASSERT_GE(tape.size(), 128u);
    for (Surface surface : {Surface::Zero, Surface::Solid}) {
        // Not folded; folded; folded, with nodes of 64 rays scanned together.
        std::vector<RayResult> answers[3];
        CoherentStats stats[3];
        for (int fold : {0, 1, 2}) {
            CoherentOptions o = small_view(Projection::Ortho);
            o.depth_pixels = 0.5;
            o.surface = surface;
            o.fold_lists = fold > 0 ? 128 : 0;
            o.folded_together_rays = fold == 2 ? 64 : 0;
            // Coarse scans take this smooth list's nodes of 64 rays apart before they would fold.
            o.coarse_scans = fold < 2;
            render_3d_coherent(tape, o, &stats[fold], &answers[fold]);
            const PixelRays rays(o);
            unsigned hits = 0;
            for (std::size_t k = 0; k < answers[fold].size(); ++k) {
                Ray ray;
                ASSERT_TRUE(
                    rays.ray(static_cast<unsigned>(k % 48), static_cast<unsigned>(k / 48), ray));
                const double x = ray.o[0], y = ray.o[1], rr = x * x + y * y;
                const RayResult& r = answers[fold][k];
                if (rr < 1 - 1e-9) {
                    ASSERT_EQ(r.status, Status::Hit) << k;
                    const double t = 2 - std::sqrt(1 - rr);
                    EXPECT_LE(r.t_lo, t + 1e-12) << k;
                    EXPECT_GE(r.t_hi, t - 1e-12) << k;
                    ++hits;
                } else if (rr > 1 + 1e-9) {
                    EXPECT_EQ(r.status, Status::Miss) << k;
                }
            }
            EXPECT_GT(hits, 400u);  // π/16 of 48²: 452
        }
        for (std::size_t k = 0; k < answers[0].size(); ++k) {
            EXPECT_EQ(answers[0][k].status, answers[1][k].status) << k;
            EXPECT_EQ(answers[0][k].status, answers[2][k].status) << k;
        }
        EXPECT_EQ(stats[0].folds, 0u);
        EXPECT_GT(stats[1].folds, 0u);
        EXPECT_GT(stats[1].folded_instructions, stats[1].folds);
        EXPECT_EQ(stats[1].folded_scans, 0u);
        EXPECT_GT(stats[2].folded_scans, 0u);
    }
    const expr::Tape bear(expr::load_graph_file((kScenes / "fidget/bear.vm").string()));
    for (Projection p : {Projection::Ortho, Projection::Pinhole}) {
        CoherentOptions o = small_view(p);
        o.surface = Surface::Solid;
        o.depth_pixels = 0.5;
        o.render.width = o.render.height = 48;
        o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
        o.render.camera = frame_box(o.render.bounds, 35, 1.0);
        CoherentStats stats;
        std::vector<RayResult> coherent;
        const Agreement a = against_per_ray(bear, o, false, 1, &coherent, &stats);
        EXPECT_EQ(a.wrong, 0u) << a.first_wrong;
        EXPECT_GT(a.rays, 0u);
        EXPECT_GT(stats.folds, 0u);
        EXPECT_GT(stats.folded_scans, 0u);  // nodes of 64 rays scanned on their folded lists
        // Its folded lists have kinks (max, min): their segment forms hold Clarke's derivative.
        EXPECT_GT(stats.segment_forms, 0u);
        // The segments' plain enclosures first or not: the same decisions, the same answers.
        o.segment_enclosures_first = false;
        std::vector<RayResult> all_forms;
        render_3d_coherent(bear, o, nullptr, &all_forms);
        testing::expect_same_answers(all_forms, coherent);
    }
}

TEST(Coherent, PerRaySolverDefaultsKeepTheAnswers) {
    // The solver's defaults (4-ulp hits, the exact oracle narrowing them) instead of the image
    // options: the same statuses, Hits still consistent.
    const expr::Tape tape(expr::load_graph_file((kScenes / "barth_sextic.vm").string()));
    for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
        CoherentOptions o = small_view(p);
        o.certified = {};
        o.render.width = o.render.height = 32;
        const Agreement a = against_per_ray(tape, o);
        EXPECT_EQ(a.wrong, 0u) << a.first_wrong;
        EXPECT_EQ(a.same, a.rays);
    }
}

TEST(Coherent, AgreesWithTheMpfrReferenceOnASubsetOfPixels) {
    for (const char* scene : {"barth_sextic.vm", "torus.expr", "gyroid.expr", "csg.expr"}) {
        const expr::Tape tape(expr::load_graph_file((kScenes / scene).string()));
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            CoherentOptions o = small_view(p);
            o.render.width = o.render.height = 24;
            const Agreement a = against_per_ray(tape, o, /*reference=*/true, /*stride=*/7);
            EXPECT_EQ(a.wrong, 0u) << scene << ": " << a.first_wrong;
            EXPECT_GE(a.same + a.undecided, a.rays) << scene;
            EXPECT_GT(a.rays, 20u) << scene;
        }
    }
}

TEST(Coherent, ThreadsAndMeanValueFormDoNotChangeAnswersAndMeanValueSavesWork) {
    const expr::Tape tape(expr::load_graph_file((kScenes / "barth_sextic.vm").string()));
    CoherentOptions o = small_view(Projection::Pinhole);
    o.render.threads = 1;
    std::vector<RayResult> one, two;
    render_3d_coherent(tape, o, nullptr, &one);
    o.render.threads = 3;
    render_3d_coherent(tape, o, nullptr, &two);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t k = 0; k < one.size(); ++k) {
        EXPECT_EQ(one[k].status, two[k].status);
        if (one[k].status != Status::Miss) {
            EXPECT_EQ(one[k].t_lo, two[k].t_lo);
        }
        EXPECT_EQ(one[k].evals.total(), two[k].evals.total());
    }
    CoherentStats with, without, adaptive;
    o.mean_value_rays = 16;
    const RenderResult a = render_3d_coherent(tape, o, &with);
    o.mean_value_rays = 0;
    const RenderResult b = render_3d_coherent(tape, o, &without);
    EXPECT_EQ(a.answers.status, b.answers.status);
    EXPECT_LT(with.leaf_solves, without.leaf_solves);
    // Unset: tried while it pays in each tile, which on Barth's sextic it does.
    o.mean_value_rays.reset();
    const RenderResult c = render_3d_coherent(tape, o, &adaptive);
    EXPECT_EQ(c.answers.status, b.answers.status);
    EXPECT_LT(adaptive.leaf_solves, without.leaf_solves);
    // The same on the solid surface of a polynomial (Chmutov's sextic, where plain intervals are
    // loosest): fewer box evaluations than without the form.
    const expr::Tape chmutov(expr::load_graph_file((kScenes / "chmutov6.vm").string()));
    CoherentOptions s = small_view(Projection::Ortho);
    s.surface = Surface::Solid;
    s.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
    s.coarse_scans = false;  // its longer segments spare more than the form on this small view
    CoherentStats solid_adaptive, solid_without;
    const RenderResult d = render_3d_coherent(chmutov, s, &solid_adaptive);
    s.mean_value_rays = 0;
    const RenderResult e = render_3d_coherent(chmutov, s, &solid_without);
    EXPECT_EQ(d.answers.status, e.answers.status);
    EXPECT_LT(solid_adaptive.box_evals + solid_adaptive.leaf_solves,
              solid_without.box_evals + solid_without.leaf_solves);
}

/// How many of the results differ between x and y in status, enclosure bits (NaN too) or
/// evaluations (a difference in count counts once).
std::size_t differing(const std::vector<RayResult>& x, const std::vector<RayResult>& y) {
    const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
    std::size_t differ = x.size() != y.size();
    for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
        differ += x[k].status != y[k].status || bits(x[k].t_lo) != bits(y[k].t_lo) ||
                  bits(x[k].t_hi) != bits(y[k].t_hi) || x[k].evals.total() != y[k].evals.total();
    }
    return differ;
}

/// A 96² image view as the CLI renders it: Barth's sextic through the pinhole, its zero set
/// (scene 0), or Chmutov's heightmap over [−1, 1]³, its solid (scene 1).
CoherentOptions image_view(int scene) {
    CoherentOptions o = small_view(scene == 0 ? Projection::Pinhole : Projection::Ortho);
    o.render.width = o.render.height = 96;
    if (scene == 1) {
        o.surface = Surface::Solid;
        o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
    }
    o.certified = image_solver_options();
    o.depth_pixels = 0.5;
    return o;
}

/// Renders `tape` with `o`, the option `flag` on and then off, and checks that every answer, its
/// enclosure and its evaluations, the image and the box counts are the same.
void expect_same_either_way(const expr::Tape& tape, CoherentOptions o, bool CoherentOptions::*flag,
                            const std::string& where) {
    std::vector<RayResult> on_results, off_results;
    CoherentStats on, off;
    o.*flag = true;
    const RenderResult a = render_3d_coherent(tape, o, &on, &on_results);
    o.*flag = false;
    const RenderResult b = render_3d_coherent(tape, o, &off, &off_results);
    EXPECT_EQ(differing(on_results, off_results), 0u) << where;
    EXPECT_TRUE(a.image.rgb == b.image.rgb) << where;
    EXPECT_EQ(on.box_evals, off.box_evals) << where;
    EXPECT_EQ(on.boxes_excluded, off.boxes_excluded) << where;
    EXPECT_GT(on.boxes_excluded, 0u) << where;
    EXPECT_GT(a.stats.hit, 0u) << where;
}

TEST(Coherent, MiddlesInFormsAreTheMiddlesWalkedAlone) {
    // The segment forms' middles as lanes of the tangent list's walk (middles_in_forms) have the
    // values of a walk of the list: every answer, enclosure, evaluation count and image the same.
    // Barth's sextic (pinhole, zero set), Chmutov's (heightmap, solid) and Fidget's bear
    // (heightmap, solid, folded lists, whose segments' plain enclosures may come first).
    const expr::Tape barth(expr::load_graph_file((kScenes / "barth_sextic.vm").string()));
    const expr::Tape chmutov(expr::load_graph_file((kScenes / "chmutov6.vm").string()));
    const expr::Tape bear(expr::load_graph_file((kScenes / "fidget" / "bear.vm").string()));
    expect_same_either_way(barth, image_view(0), &CoherentOptions::middles_in_forms, "Barth");
    expect_same_either_way(chmutov, image_view(1), &CoherentOptions::middles_in_forms, "Chmutov");
    expect_same_either_way(bear, image_view(1), &CoherentOptions::middles_in_forms, "bear");
}

TEST(Coherent, QuartersInLanesAreTheQuartersWalkedOneByOne) {
    // A node's four quarters evaluated in lanes of one walk, and their mean value forms in lanes
    // of another (children_in_lanes), give each quarter the enclosure and form of its own walks
    // bit for bit: with the forms tried on a fixed rule (mean_value_rays set, so no trial depends
    // on the order of the tries), every answer, its enclosure and its evaluations are the same,
    // and so are the images. Barth's sextic (pinhole, zero set) and Chmutov's (heightmap, solid),
    // with the forms on boxes of up to 16 rays and on every box; and where the quarters' slot
    // enclosures are kept from the lanes for pruning and folding: csg.expr (min, max and abs;
    // pinhole) and Fidget's colonnade (heightmap, solid, folded lists). The quarters walked one
    // by one are not scanned together (merged_scans needs their boxes first): off in both.
    const expr::Tape barth(expr::load_graph_file((kScenes / "barth_sextic.vm").string()));
    const expr::Tape chmutov(expr::load_graph_file((kScenes / "chmutov6.vm").string()));
    for (int scene = 0; scene < 2; ++scene) {
        CoherentOptions o = image_view(scene);
        o.merged_scans = false;
        for (unsigned rays : {16u, 1000u}) {
            o.mean_value_rays = rays;
            expect_same_either_way(scene == 0 ? barth : chmutov, o,
                                   &CoherentOptions::children_in_lanes,
                                   (scene == 0 ? "Barth, " : "Chmutov, ") + std::to_string(rays));
        }
    }
    const expr::Tape csg(expr::load_graph_file((kScenes / "csg.expr").string()));
    const expr::Tape colonnade(
        expr::load_graph_file((kScenes / "fidget" / "colonnade.vm").string()));
    CoherentOptions o = image_view(0);
    o.merged_scans = false;
    o.mean_value_rays = 16;
    expect_same_either_way(csg, o, &CoherentOptions::children_in_lanes, "csg");
    o = image_view(1);
    o.merged_scans = false;
    o.mean_value_rays = 16;
    o.fold_lists = 4;  // folded wherever it drops enough
    expect_same_either_way(colonnade, o, &CoherentOptions::children_in_lanes, "colonnade");
}

TEST(Coherent, BlockHullsAreThePixelHulls) {
    // A node's hull taken from its 4 × 4 blocks' cached hulls (block_hulls) is the hull a pass
    // over its pixels takes, bit for bit: every answer, its enclosure and its evaluations are the
    // same, and so are the images and the box counts. Barth's sextic (pinhole, zero set),
    // Chmutov's (heightmap, solid) and a bundle of query rays (whose hulls take origins and
    // directions both), with root tiles of 16 pixels (whole blocks) and of 10 and 7 (blocks cut
    // at the tiles' ends, quarters off the blocks' corners).
    const expr::Tape barth(expr::load_graph_file((kScenes / "barth_sextic.vm").string()));
    const expr::Tape chmutov(expr::load_graph_file((kScenes / "chmutov6.vm").string()));
    for (int scene = 0; scene < 2; ++scene) {
        CoherentOptions o = image_view(scene);
        for (unsigned side : {16u, 10u, 7u}) {
            o.root_tile = side;
            expect_same_either_way(scene == 0 ? barth : chmutov, o, &CoherentOptions::block_hulls,
                                   (scene == 0 ? "Barth, " : "Chmutov, ") + std::to_string(side));
        }
    }
    // Query rays from one eye through a jittered grid: a bundle laid out by bundle_rays.
    std::vector<Ray> rays;
    for (int j = 0; j < 40; ++j) {
        for (int i = 0; i < 40; ++i) {
            const double u = (i + 0.5 + 0.3 * ((i * 7 + j * 3) % 5 - 2) / 2.0) / 40 - 0.5;
            const double v = (j + 0.5 + 0.3 * ((i * 5 + j * 11) % 5 - 2) / 2.0) / 40 - 0.5;
            rays.push_back({{0, 0, 6}, {u, v, -1}, 0, 12});
        }
    }
    CoherentOptions q;
    q.render.bounds = {{{-2, 2}, {-2, 2}, {-2, 2}}};
    q.render.threads = 2;
    for (unsigned side : {16u, 10u}) {
        q.root_tile = side;
        CoherentStats with, without;
        q.block_hulls = true;
        const std::optional<std::vector<RayResult>> a = query_coherent(barth, rays, q, &with);
        q.block_hulls = false;
        const std::optional<std::vector<RayResult>> b = query_coherent(barth, rays, q, &without);
        ASSERT_TRUE(a.has_value() && b.has_value());
        EXPECT_EQ(differing(*a, *b), 0u) << "query rays, " << side;
        EXPECT_EQ(with.box_evals, without.box_evals) << "query rays, " << side;
        EXPECT_GT(std::count_if(a->begin(), a->end(),
                                [](const RayResult& r) { return r.status == Status::Hit; }),
                  0);
    }
}

TEST(Coherent, WideBoxFormsOnSmoothListsKeepTheAnswers) {
    // With mean_value_rays unset, boxes of more than 16 rays whose list is smooth get the mean
    // value form too (tried while it pays). On Chmutov's solid heightmap at image resolution some
    // are proven by it; with the cap given as 16 none are; the answers agree with the per-ray
    // solver either way.
    const expr::Tape chmutov(expr::load_graph_file((kScenes / "chmutov6.vm").string()));
    CoherentOptions o = small_view(Projection::Ortho);
    o.render.width = o.render.height = 128;
    o.render.bounds = {{{-1, 1}, {-1, 1}, {-1, 1}}};
    o.surface = Surface::Solid;
    o.certified = image_solver_options();
    o.depth_pixels = 0.5;
    for (bool capped : {false, true}) {
        if (capped) o.mean_value_rays = 16;
        CoherentStats stats;
        const Agreement a = against_per_ray(chmutov, o, false, 1, nullptr, &stats);
        EXPECT_EQ(a.wrong, 0u) << a.first_wrong;
        EXPECT_EQ(a.same, a.rays);
        if (capped) {
            EXPECT_EQ(stats.wide_forms, 0u);
        } else {
            EXPECT_GT(stats.wide_forms, 0u);
        }
    }
}

/// Each worker colours its tiles as it answers them (shade, normal, status) and counts their
/// pixels: the image is colorize()'s of the answers, for every AOV, and the counts are the
/// answers', whatever the tiles (an image not a multiple of the root tile) and threads; also
/// where tiles are answered without their rays (a heightmap over bounds wider than the torus,
/// a camera that sees past the bounds), counted at once and filled with their rows' colours.
/// Without the image's answers kept (RenderOptions::answers), each tile coloured from its own: the
/// same image and counts.
TEST(Coherent, ImageAndCountsAreThoseOfTheAnswers) {
    const expr::Tape tape(expr::parse_expr("(x^2 + y^2 + z^2 + 0.84)^2 - 4*(x^2 + y^2)"));
    for (int view = 0; view < 4; ++view) {
        const Projection p = view % 2 == 0 ? Projection::Pinhole : Projection::Ortho;
        for (Aov aov : {Aov::Shade, Aov::Depth, Aov::Steps, Aov::Normal, Aov::Status}) {
            for (unsigned threads : {1u, 3u}) {
                CoherentOptions o = small_view(p);
                o.render.width = 37;
                o.render.height = 29;
                o.render.aov = aov;
                o.render.threads = threads;
                o.depth_pixels = 0.5;
                if (view >= 2) {
                    o.render.width = 70;
                    o.render.height = 53;
                    // Pinhole: the bounds' box seen from afar, small in a wide view.
                    o.render.camera.eye = {9, -12, 6};
                    o.render.camera.fov_degrees = 60;
                    if (p == Projection::Ortho) o.render.bounds = {{{-4, 4}, {-4, 4}, {-2, 2}}};
                }
                CoherentStats stats;
                const RenderResult r = render_3d_coherent(tape, o, &stats);
                if (view >= 2) {
                    EXPECT_GT(stats.empty_tiles, 0u) << view;
                }
                const RgbImage want = colorize(r.answers, aov, o.render.light, 1);
                EXPECT_EQ(r.image.width, want.width);
                EXPECT_EQ(r.image.height, want.height);
                EXPECT_TRUE(r.image.rgb == want.rgb) << "aov " << static_cast<int>(aov);
                std::uint64_t hit = 0, miss = 0, unknown = 0, most = 0;
                for (std::size_t k = 0; k < r.answers.status.size(); ++k) {
                    hit += r.answers.status[k] == Status::Hit;
                    miss += r.answers.status[k] == Status::Miss;
                    unknown += r.answers.status[k] == Status::Unknown;
                    most = std::max(most, r.answers.evals[k]);
                }
                EXPECT_EQ(r.stats.hit, hit);
                EXPECT_EQ(r.stats.miss, miss);
                EXPECT_EQ(r.stats.unknown, unknown);
                EXPECT_EQ(r.stats.max_pixel_evals, most);
                EXPECT_GT(hit, 0u);
                EXPECT_GT(miss, 0u);
                // Without the image's answers (RenderOptions::answers), a local AOV's tiles are
                // coloured from their own: the same image and totals, no image-sized arrays.
                o.render.answers = false;
                const RenderResult lean = render_3d_coherent(tape, o);
                EXPECT_TRUE(lean.image.rgb == want.rgb) << "aov " << static_cast<int>(aov);
                EXPECT_EQ(lean.stats.hit, hit);
                EXPECT_EQ(lean.stats.miss, miss);
                EXPECT_EQ(lean.stats.max_pixel_evals, most);
                EXPECT_EQ(lean.stats.evals.total(), r.stats.evals.total());
                EXPECT_EQ(lean.answers.width, o.render.width);
                EXPECT_EQ(lean.answers.status.empty(), aov_is_local(aov));
            }
        }
    }
}

/// Hit normals are render_3d's: the unit gradient of the full tape at the hit (expr::gradient,
/// normalised in round-to-nearest), facing the ray, bit for bit; with batch_normals (a scan's hits
/// in one walk of Dual lanes) and without. (They come from the pruned lists, whose pruning once
/// folded a heightmap ray's x and y, points on its box, into constants without derivatives.)
/// The solid surface's boxes proven inside answer their rays at once; their normals too. A
/// batch's normalisations run in vectors: each copy of that code (expr::batch_isa()) is checked.
TEST(Coherent, HitNormalsAreRender3dNormalsBatchedOrNot) {
    std::size_t hits = 0, boxes_inside = 0;
    // Every Hit of one render against the gradient of the full tape at its t.
    const auto check = [&](const expr::Tape& tape, const CoherentOptions& o,
                           const std::string& where) {
        CoherentStats stats;
        const RenderResult r = render_3d_coherent(tape, o, &stats);
        boxes_inside += stats.boxes_inside;
        const PixelRays rays(o);
        std::size_t k = 0;
        for (unsigned j = 0; j < o.render.height; ++j) {
            for (unsigned i = 0; i < o.render.width; ++i, ++k) {
                if (r.answers.status[k] != Status::Hit) continue;
                ++hits;
                Ray ray;
                ASSERT_TRUE(rays.ray(i, j, ray));
                const double t = r.answers.t[k];
                const Vec3 q{ray.o[0] + t * ray.d[0], ray.o[1] + t * ray.d[1],
                             ray.o[2] + t * ray.d[2]};
                const Dual<double, 3> g = expr::gradient(tape, q);
                Vec3 want = normalize({g.v[0], g.v[1], g.v[2]});
                if (dot(want, ray.d) > 0) want = {-want[0], -want[1], -want[2]};
                for (int c = 0; c < 3; ++c) {
                    EXPECT_EQ(std::bit_cast<std::uint32_t>(r.answers.normal[k][c]),
                              std::bit_cast<std::uint32_t>(static_cast<float>(want[c])))
                        << where << " pixel (" << i << ", " << j << ") component " << c;
                }
            }
        }
    };
    testing::BatchIsaGuard guard;
    for (const expr::BatchIsa isa : testing::batch_isas()) {
        expr::set_batch_isa(isa);
        for (const fs::path& scene : gallery()) {
            const expr::Tape tape(expr::load_graph_file(scene.string()));
            for (auto [p, surface] : {std::pair{Projection::Pinhole, Surface::Zero},
                                      std::pair{Projection::Ortho, Surface::Zero},
                                      std::pair{Projection::Ortho, Surface::Solid}}) {
                for (bool batch : {true, false}) {
                    CoherentOptions o = small_view(p);
                    o.surface = surface;
                    o.depth_pixels = 0.5;  // scans of rays in lanes, as the CLI's images
                    o.batch_normals = batch;
                    check(tape, o,
                          scene.string() + " " + expr::batch_isa_name(isa) +
                              (batch ? " batched" : "") +
                              (surface == Surface::Solid ? " solid" : ""));
                }
            }
        }
    }
    EXPECT_GT(hits, 1000u);
    EXPECT_GT(boxes_inside, 100u);
}

/// Every instruction set's copy of the walks (and of the lanes' loads, eight boxes at a time on
/// AVX-512) gives every pixel of the gallery's images the same answer, bit for bit: status,
/// enclosure, evaluations.
TEST(Coherent, EveryInstructionSetGivesTheSameAnswers) {
    testing::BatchIsaGuard guard;
    const std::vector<expr::BatchIsa> isas = testing::batch_isas();
    std::size_t compared = 0;
    for (const fs::path& scene : gallery()) {
        const expr::Tape tape(expr::load_graph_file(scene.string()));
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            CoherentOptions o = small_view(p);
            o.render.width = o.render.height = 64;
            o.depth_pixels = 0.5;
            std::vector<std::vector<RayResult>> results(isas.size());
            for (std::size_t k = 0; k < isas.size(); ++k) {
                expr::set_batch_isa(isas[k]);
                render_3d_coherent(tape, o, nullptr, &results[k]);
            }
            for (std::size_t k = 1; k < isas.size(); ++k) {
                const std::string where = scene.string() + " " + expr::batch_isa_name(isas[k]) +
                                          (p == Projection::Ortho ? " ortho" : " pinhole");
                ASSERT_EQ(results[k].size(), results[0].size()) << where;
                for (std::size_t i = 0; i < results[0].size(); ++i) {
                    const RayResult &a = results[0][i], &b = results[k][i];
                    EXPECT_EQ(a.status, b.status) << where << " pixel " << i;
                    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.t_lo),
                              std::bit_cast<std::uint64_t>(b.t_lo))
                        << where << " pixel " << i;
                    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.t_hi),
                              std::bit_cast<std::uint64_t>(b.t_hi))
                        << where << " pixel " << i;
                    EXPECT_EQ(a.evals.total(), b.evals.total()) << where << " pixel " << i;
                    ++compared;
                }
            }
        }
    }
    // Not vacuous where this CPU has more than the baseline copy.
    if (isas.size() > 1) {
        EXPECT_GT(compared, 10000u);
    }
}

/// Where the gradient at a hit is 0, its normal is normalize's answer, (+0, +0, +0), turned to
/// face nothing: f = (x − x) − 1 < 0 everywhere, so the solid is entered at every ray's first
/// point, where ∇f = (1 − 1, 0, 0) = 0 exactly; batched or not, on every instruction set.
TEST(Coherent, ZeroGradientsGiveTheZeroNormal) {
    const expr::Tape tape(expr::parse_expr("(x - x) - 1"));
    testing::BatchIsaGuard guard;
    for (const expr::BatchIsa isa : testing::batch_isas()) {
        expr::set_batch_isa(isa);
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            for (bool batch : {true, false}) {
                CoherentOptions o = small_view(p);
                o.surface = Surface::Solid;
                o.depth_pixels = 0.5;
                o.batch_normals = batch;
                const RenderResult r = render_3d_coherent(tape, o);
                const std::string where = std::string(expr::batch_isa_name(isa)) +
                                          (p == Projection::Ortho ? " ortho" : " pinhole") +
                                          (batch ? " batched" : "");
                ASSERT_GT(r.stats.hit, 0u) << where;
                for (std::size_t k = 0; k < r.answers.status.size(); ++k) {
                    if (r.answers.status[k] != Status::Hit) continue;
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_EQ(std::bit_cast<std::uint32_t>(r.answers.normal[k][c]), 0u)
                            << where << " pixel " << k << " component " << c;
                    }
                }
            }
        }
    }
}

TEST(Coherent, OrthoRaysAreTheHeightmapRays) {
    CoherentOptions o;
    o.projection = Projection::Ortho;
    o.render.width = 4;
    o.render.height = 2;
    o.render.bounds = {{{-1, 1}, {-1, 1}, {-0.5, 1.5}}};
    const PixelRays rays(o);
    Ray r;
    ASSERT_TRUE(rays.ray(0, 0, r));
    EXPECT_EQ(r.o[0], -0.75);
    EXPECT_EQ(r.o[1], 0.5);
    EXPECT_EQ(r.o[2], 1.5);
    EXPECT_EQ(r.d[2], -1.0);
    EXPECT_EQ(r.tmin, 0.0);
    EXPECT_GE(r.tmax, 2.0);
    ASSERT_TRUE(rays.ray(3, 1, r));
    EXPECT_EQ(r.o[0], 0.75);
    EXPECT_EQ(r.o[1], -0.5);
    o.render.bounds[2] = {1, 1};
    EXPECT_THROW(PixelRays{o}, std::invalid_argument);
    o.render.width = 0;
    EXPECT_THROW(render_3d_coherent(expr::Tape(expr::parse_expr("x + y + z")), o),
                 std::invalid_argument);
}

TEST(Coherent, PinholeRaysAreRender3dRays) {
    const CoherentOptions o = small_view(Projection::Pinhole);
    const PixelRays rays(o);
    const CameraFrame frame(o.render.camera, o.render.width, o.render.height);
    for (unsigned j = 0; j < o.render.height; j += 5) {
        for (unsigned i = 0; i < o.render.width; i += 3) {
            Ray a, b = frame.ray(i + 0.5, j + 0.5);
            const bool in = clip_ray(b, o.render.bounds);
            ASSERT_EQ(rays.ray(i, j, a), in);
            if (!in) continue;
            EXPECT_EQ(a.o, b.o);
            EXPECT_EQ(a.d, b.d);
            EXPECT_EQ(a.tmin, b.tmin);
            EXPECT_EQ(a.tmax, b.tmax);
        }
    }
}

// Random DAGs under random cameras (pinhole and ortho), random tile sides, split shapes and
// thread counts: never a contradiction with the per-ray solver; Unknown on one side only where
// the other decides is allowed, and must stay rare.
// One ray's box by two products and two sums a bound is the box of the interval arithmetic
// (segment_box, whose outward rounding the interval suites check), value for value.
RC_GTEST_PROP(Coherent, RayBoxIsTheSegmentBoxOfOneRay, ()) {
    Ray ray;
    for (int c = 0; c < 3; ++c) {
        ray.o[c] = *testing::gen_finite_double();
        ray.d[c] = *testing::gen_finite_double();
    }
    double p = *testing::gen_finite_double(), q = *testing::gen_finite_double();
    if (q < p) std::swap(p, q);
    if (*rc::gen::arbitrary<bool>()) q = p;  // a point, as the scans' point tests use
    RoundingScope up;
    const std::array<UpInterval, 3> fast = ray_box(ray, p, q);
    const std::array<UpInterval, 3> box =
        segment_box(ray.o.data(), ray.o.data(), ray.d.data(), ray.d.data(), p, q);
    for (int c = 0; c < 3; ++c) {
        RC_ASSERT(fast[c].lower() == box[c].lower());
        RC_ASSERT(fast[c].upper() == box[c].upper());
        RC_ASSERT(fast[c].defined == box[c].defined);
    }
}

RC_GTEST_PROP(Coherent, SmoothDagsScannedInLanesAgreeWithThePerRaySolver, ()) {
    // Ops that all have tangent rules (expr/tangent.h): the scans' undecided pieces get the mean
    // value form in lanes.
    expr::Graph g;
    if (*rc::gen::arbitrary<bool>()) {
        g = *testing::gen_dag(16, /*smooth=*/true);
    } else {
        // A random polynomial of degree ≤ 4 in x, y, z: curved, and its natural enclosures loose
        // (the dependency problem), where the form is what decides pieces near the surface.
        expr::NodeId sum = g.constant(0.0);
        const int terms = *rc::gen::inRange(2, 8);
        for (int k = 0; k < terms; ++k) {
            expr::NodeId term = g.constant(*rc::gen::inRange(-16, 17) / 8.0);
            for (int axis = 0; axis < 3; ++axis) {
                const unsigned n = *rc::gen::inRange(0u, 3u);
                if (n > 0) term = g.binary(expr::Op::Mul, term, g.pow(g.var(axis), n));
            }
            sum = g.binary(expr::Op::Add, sum, term);
        }
        g.set_output(sum);
    }
    // The level set through a drawn point of the view, so that the surface is in the picture.
    const std::array<double, 3> p{*rc::gen::inRange(-8, 9) / 8.0, *rc::gen::inRange(-8, 9) / 8.0,
                                  *rc::gen::inRange(-8, 9) / 8.0};
    const double c = expr::eval<double>(expr::Tape(g), p);
    if (std::isfinite(c)) g.set_output(g.binary(expr::Op::Sub, g.output(), g.constant(c)));
    const int factor = *rc::gen::inRange(0, 3);
    if (factor == 1) {
        // Times 2 + x² + 2y² + 3z² > 0: the same zero set and solid, a list long enough for the
        // segment forms and the monotone segments.
        expr::NodeId w = g.constant(2.0);
        for (int axis = 0; axis < 3; ++axis) {
            w = g.binary(expr::Op::Add, w,
                         g.binary(expr::Op::Mul, g.constant(axis + 1.0), g.pow(g.var(axis), 2)));
        }
        g.set_output(g.binary(expr::Op::Mul, g.output(), w));
    } else if (factor == 2) {
        // Times 1 + exp(−k·|p − q|²) > 0 with q at a corner of the view: a term all but constant
        // on boxes away from q, which the scans fold (fold_lists).
        const double k = *rc::gen::element(10.0, 40.0);
        expr::NodeId d = g.constant(0.0);
        for (int axis = 0; axis < 3; ++axis) {
            const expr::NodeId u = g.binary(expr::Op::Sub, g.var(axis), g.constant(1.75));
            d = g.binary(expr::Op::Add, d, g.pow(u, 2));
        }
        const expr::NodeId e = g.unary(expr::Op::Exp, g.binary(expr::Op::Mul, g.constant(-k), d));
        g.set_output(
            g.binary(expr::Op::Mul, g.output(), g.binary(expr::Op::Add, g.constant(1.0), e)));
    }
    const expr::Tape tape(g);
    CoherentOptions o = small_view(*rc::gen::element(Projection::Pinhole, Projection::Ortho));
    o.render.width = *rc::gen::inRange(8u, 33u);
    o.render.height = *rc::gen::inRange(8u, 33u);
    o.render.threads = 1;
    o.depth_pixels = *rc::gen::element(0.5, 2.0, 8.0);
    o.together_rays = *rc::gen::element(1u, 8u);
    o.smooth_together_rays = *rc::gen::element(1u, 16u, 64u);
    o.tile_pieces = *rc::gen::arbitrary<bool>();
    o.segment_forms = *rc::gen::arbitrary<bool>();
    o.monotone_segments = *rc::gen::arbitrary<bool>();
    o.segment_enclosures_first = *rc::gen::arbitrary<bool>();
    o.children_in_lanes = *rc::gen::arbitrary<bool>();
    o.clip_forms = *rc::gen::arbitrary<bool>();
    o.block_hulls = *rc::gen::arbitrary<bool>();
    o.float_lanes = *rc::gen::arbitrary<bool>();  // binary32 walks, where the list is arithmetic
    o.newton_brackets = *rc::gen::arbitrary<bool>();
    o.middles_in_forms = *rc::gen::arbitrary<bool>();
    o.merged_scans = *rc::gen::arbitrary<bool>();
    o.second_order_forms = *rc::gen::arbitrary<bool>();
    o.fold_lists = *rc::gen::element(0u, 4u, 16u, 128u);  // 4: folded wherever it drops enough
    o.folded_together_rays = *rc::gen::element(0u, 64u, 1024u);  // nodes of up to 1024 rays
    o.surface = *rc::gen::element(Surface::Zero, Surface::Solid);
    o.certified = image_solver_options();
    o.certified.budget = 2000;
    CoherentStats stats;
    const Agreement a = against_per_ray(tape, o, false, 1, nullptr, &stats);
    RC_ASSERT(a.wrong == 0u);
    RC_TAG(stats.lane_forms > 0 ? "lane forms proved pieces" : "no lane form needed");
    RC_TAG(stats.tile_decided > 0 ? "tile pieces answered rays" : "no ray answered by tiles");
    RC_TAG(stats.quarter_pieces > 0 ? "pieces scanned in quarters in lanes" : "no quarters");
    RC_TAG(stats.segment_forms > 0 ? "segment forms proved segments" : "no segment form");
    RC_TAG(stats.monotone_segments > 0 ? "zeros bracketed on monotone segments"
                                       : "no monotone bracket");
    RC_TAG(stats.newton_brackets > 0 ? "brackets from Newton steps" : "no Newton bracket");
    RC_TAG(stats.merged_scans > 0 ? "quarters scanned together" : "no merged scan");
    RC_TAG(stats.second_order > 0 ? "second-order forms proved segments" : "no second-order form");
    RC_TAG(stats.folds > 0 ? "lists folded" : "no fold");
    RC_TAG(stats.folded_scans > 0 ? "wide scans on folded lists" : "no wide scan");
}

RC_GTEST_PROP(Coherent, RandomDagsAgreeWithThePerRaySolver, ()) {
    const expr::Tape tape(*testing::gen_dag(16));
    CoherentOptions o;
    o.render.width = *rc::gen::inRange(1u, 14u);
    o.render.height = *rc::gen::inRange(1u, 14u);
    const double lo = *rc::gen::element(-2.0, -1.0, -0.3);
    const double hi = *rc::gen::element(2.0, 1.0, 0.7);
    o.render.bounds = {{{lo, hi}, {lo, hi}, {lo, hi}}};
    o.projection = *rc::gen::element(Projection::Pinhole, Projection::Ortho);
    const double az = *rc::gen::inRange(0, 628) / 100.0;
    const double el = *rc::gen::inRange(-120, 120) / 100.0;
    const double dist = *rc::gen::element(2.0, 4.0, 8.0);
    o.render.camera.eye = {dist * std::cos(el) * std::cos(az), dist * std::cos(el) * std::sin(az),
                           dist * std::sin(el)};
    o.render.camera.target = {0, 0, 0};
    o.render.camera.fov_degrees = *rc::gen::element(20.0, 35.0, 60.0);
    o.root_tile = *rc::gen::element(1u, 4u, 6u, 16u);
    o.aspect = *rc::gen::element(0.25, 0.5, 2.0);
    o.mean_value_rays = *rc::gen::element(0u, 4u, 16u, 1000u);
    o.render.threads = *rc::gen::element(1u, 2u);
    o.depth_pixels = *rc::gen::element(0.0, 0.5, 2.0);          // leaf segments scanned in pieces
    o.together_rays = *rc::gen::element(0u, 1u, 4u, 16u, 64u);  // several rays' pieces at once
    o.smooth_together_rays = *rc::gen::element(0u, 16u, 64u);
    o.lane_mean_value = *rc::gen::arbitrary<bool>();
    o.tile_pieces = *rc::gen::arbitrary<bool>();
    o.segment_forms = *rc::gen::arbitrary<bool>();
    o.monotone_segments = *rc::gen::arbitrary<bool>();
    o.segment_enclosures_first = *rc::gen::arbitrary<bool>();
    o.children_in_lanes = *rc::gen::arbitrary<bool>();
    o.clip_forms = *rc::gen::arbitrary<bool>();
    o.block_hulls = *rc::gen::arbitrary<bool>();
    o.newton_brackets = *rc::gen::arbitrary<bool>();
    o.merged_scans = *rc::gen::arbitrary<bool>();
    o.second_order_forms = *rc::gen::arbitrary<bool>();
    o.fold_lists = *rc::gen::element(0u, 4u, 16u, 128u);
    o.folded_together_rays = *rc::gen::element(0u, 64u, 1024u);
    o.surface = *rc::gen::element(Surface::Zero, Surface::Solid);
    o.certified.budget = 2000;  // the image options otherwise
    CoherentStats stats;
    const Agreement a = against_per_ray(tape, o, false, 1, nullptr, &stats);
    RC_ASSERT(a.wrong == 0u);
    RC_TAG(a.undecided == 0 ? "all agree" : "some undecided");
    RC_TAG(stats.folds > 0 ? "lists folded" : "no fold");
    RC_TAG(stats.folded_scans > 0 ? "wide scans on folded lists" : "no wide scan");
}

/// A LaneList (tracers/coherent_parts.h) walks the rest of a list over its own registers: with
/// its variables' slots loaded with the boxes, every slot of the list holds what a walk of the
/// whole list writes there, bit for bit, in binary32 and in double lanes, for any count of
/// lanes, walk after walk (its constants are written once).
template <class L>
void lane_list_walks_the_list(const expr::Tape& tape, int walks) {
    const std::vector<expr::Instr>& list = tape.ssa();
    const auto slots = static_cast<std::uint32_t>(list.size());
    std::optional<detail::coherent::LaneList<L>> made =
        detail::coherent::make_lane_list<L>(list, slots);
    RC_ASSERT(made.has_value());  // a Graph's list writes each variable once
    detail::coherent::LaneList<L>& ll = *made;
    std::size_t consts = 0, vars = 0;
    for (const expr::Instr& in : list) {
        consts += in.op == expr::Op::Const;
        vars += in.op == expr::Op::VarX || in.op == expr::Op::VarY || in.op == expr::Op::VarZ;
    }
    RC_ASSERT(ll.core.size() == list.size() - consts - vars);
    std::array<L, 3> in{};
    std::vector<L> regs(slots);
    for (int walk = 0; walk < walks; ++walk) {
        const int n = *rc::gen::inRange(1, expr::kIntervalLanes + 1);
        for (int c = 0; c < 3; ++c) {
            for (int k = 0; k < n; ++k) {
                const auto [lo, hi] = *testing::gen_bounds();
                expr::set_lane(in[c], k, UpInterval(lo, hi));
            }
            if (ll.var[c] != detail::coherent::LaneList<L>::kNoVar) ll.file.regs[ll.var[c]] = in[c];
        }
        RoundingScope up;
        expr::run_interval_batch(list.data(), list.data() + list.size(), in.data(), regs.data(), n);
        expr::run_interval_batch(ll.core.data(), ll.core.data() + ll.core.size(), ll.file.in.data(),
                                 ll.file.regs.data(), n);
        for (const expr::Instr& x : list) {
            for (int k = 0; k < n; ++k) {
                const UpInterval a = expr::lane(regs[x.out], k),
                                 b = expr::lane(ll.file.regs[x.out], k);
                RC_ASSERT(std::bit_cast<std::uint64_t>(a.lower()) ==
                          std::bit_cast<std::uint64_t>(b.lower()));
                RC_ASSERT(std::bit_cast<std::uint64_t>(a.upper()) ==
                          std::bit_cast<std::uint64_t>(b.upper()));
                RC_ASSERT(a.defined == b.defined);
            }
        }
    }
}

/// middle(a, b) is midpoint(UpInterval(a, b)) bit for bit, for finite a ≤ b of any magnitude
/// (signed zeros, subnormals, the largest doubles), in the walk's upward mode and to nearest.
RC_GTEST_PROP(Coherent, MiddleIsTheIntervalsMidpoint, ()) {
    const auto [a, b] = *testing::gen_bounds();
    RC_PRE(std::isfinite(a) && std::isfinite(b));
    const auto same = [&] {
        return std::bit_cast<std::uint64_t>(detail::coherent::middle(a, b)) ==
               std::bit_cast<std::uint64_t>(midpoint(UpInterval(a, b)));
    };
    RC_ASSERT(same());
    RoundingScope up;
    RC_ASSERT(same());
}

TEST(Coherent, MiddleIsTheIntervalsMidpointAtOddSubnormals) {
    // Where a half of a bound rounds (an odd subnormal: up to the bound itself upward, to 0 to
    // nearest), the sum leaves [a, b] and is brought back, as midpoint() does.
    const double d = std::numeric_limits<double>::denorm_min();
    const double m = std::numeric_limits<double>::max();
    for (const auto& [a, b] : std::vector<std::pair<double, double>>{{d, d},
                                                                     {3 * d, 3 * d},
                                                                     {-d, -d},
                                                                     {-3 * d, d},
                                                                     {d, 3 * d},
                                                                     {-m, m},
                                                                     {m, m},
                                                                     {0.0, -0.0}}) {
        for (const bool up : {false, true}) {
            std::optional<RoundingScope> scope;
            if (up) scope.emplace();
            EXPECT_EQ(std::bit_cast<std::uint64_t>(detail::coherent::middle(a, b)),
                      std::bit_cast<std::uint64_t>(midpoint(UpInterval(a, b))))
                << a << " " << b << (up ? " upward" : " nearest");
        }
    }
}

TEST(Coherent, ALaneListWritesEachVariableOnce) {
    // x read from two slots: no LaneList (the walks' shared registers serve it); once: one.
    using LL = detail::coherent::LaneList<expr::IntervalLanesF>;
    const std::vector<expr::Instr> twice = {{expr::Op::VarX, 0, 0, 0, 0.0},
                                            {expr::Op::VarX, 1, 0, 0, 0.0},
                                            {expr::Op::Add, 2, 0, 1, 0.0}};
    EXPECT_FALSE(detail::coherent::make_lane_list<expr::IntervalLanesF>(twice, 3).has_value());
    const std::vector<expr::Instr> once = {{expr::Op::VarY, 0, 0, 0, 0.0},
                                           {expr::Op::Const, 1, 0, 0, 2.0},
                                           {expr::Op::Mul, 2, 0, 1, 0.0}};
    const std::optional<LL> ll = detail::coherent::make_lane_list<expr::IntervalLanesF>(once, 3);
    ASSERT_TRUE(ll.has_value());
    EXPECT_EQ(ll->var[0], LL::kNoVar);
    EXPECT_EQ(ll->var[1], 0u);
    EXPECT_EQ(ll->var[2], LL::kNoVar);
    ASSERT_EQ(ll->core.size(), 1u);
    EXPECT_EQ(ll->core[0].op, expr::Op::Mul);
    // The constant 2 in every lane, as the Const step writes it.
    for (int k = 0; k < expr::kIntervalLanes; ++k) {
        EXPECT_EQ(ll->file.regs[1].lo[k], 2.0f);
        EXPECT_EQ(ll->file.regs[1].hi[k], 2.0f);
    }
    EXPECT_EQ(ll->file.regs[1].defined[0], ~std::uint64_t{0});
}

RC_GTEST_PROP(Coherent, LaneListsWalkTheirListsBits, ()) {
    const expr::Tape tape(*testing::gen_dag(20));
    RC_TAG(std::any_of(tape.ssa().begin(), tape.ssa().end(),
                       [](const expr::Instr& in) { return in.op == expr::Op::Const; })
               ? "constants"
               : "no constant");
    lane_list_walks_the_list<expr::IntervalLanesF>(tape, 3);
    lane_list_walks_the_list<expr::IntervalLanes>(tape, 3);
}

}  // namespace
}  // namespace certray::tracers
