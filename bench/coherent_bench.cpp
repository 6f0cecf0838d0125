// bench/coherent_bench.cpp — coherent certified rendering (tracers/coherent.h) against one
// certified solve per pixel (render_3d with `certified`), Google Benchmark.
//
// Scenes: scenes/barth_sextic.vm over [−2, 2]³, framed as `certray render` frames it (the cells
// where the surface may be, seen from (1, −2, 0.8), fov 35°), Fidget's 2D models
// scenes/fidget/hi.vm and quarter.vm (prisms along z) over [−1, 1]³, scenes/tanglecube.vm, and
// Fidget's 3D models scenes/fidget/bear.vm and colonnade.vm over [−1, 1]³ as solids (f < 0: what
// Fidget and libfive draw; `solid` 1).
// Pinhole and ortho (heightmap along −z) cameras; sizes 256², 512², 1024². Wall-clock time
// (UseRealTime): the renders are threaded; the CPU column is the whole process's
// (MeasureProcessCPUTime), steadier on a shared machine. `image` 1: the solver options an image
// needs (CertifiedOptions::tighten off, hit_width 1e-6), for both engines, and for the coherent
// one hits half a pixel deep (CoherentOptions::depth_pixels 0.5, as `certray render`); 0: the
// defaults (hits narrowed to 4 ulps, by the exact oracle where the intervals cannot). Counters per
// pixel: whole-tape evaluations (evals/px: box evaluations and every solve's), box evaluations
// (boxes/px), leaf solves (leaves/px), of those decided by scans (scans/px) and by scans of
// several rays at once (together/px), and the image's hit/miss/unknown counts. Command:
// build/bench/coherent_bench [--benchmark_filter=…]; results in docs/benchmarks.md, "Coherent
// certified rendering". BM_Cone: the Lipschitz tracers with and without the cone march
// (docs/benchmarks.md, "Cone marching for the Lipschitz tracers"). BM_Option: the gallery's
// smooth scenes with and without one CoherentOptions switch, for interleaved runs
// (docs/benchmarks.md, "Segment forms, and where Barth's evaluations go"). BM_Fold: the long-list
// scenes (the bear, the molecule, the particles, test.json) with and without folded lists
// (docs/benchmarks.md, "Lists folded to their boxes").
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/solid.h"
#include "tracers/camera.h"
#include "tracers/coherent.h"
#include "tracers/cone.h"
#include "tracers/methods.h"
#include "tracers/parallel.h"
#include "tracers/render.h"

namespace certray {
namespace {

struct Scene {
    const char* path;
    double lo, hi;
};
const Scene kScenes[] = {{CERTRAY_SCENES_DIR "/barth_sextic.vm", -2, 2},
                         {CERTRAY_SCENES_DIR "/fidget/hi.vm", -1, 1},
                         {CERTRAY_SCENES_DIR "/fidget/quarter.vm", -1, 1},
                         {CERTRAY_SCENES_DIR "/tanglecube.vm", -2, 2},
                         {CERTRAY_SCENES_DIR "/fidget/bear.vm", -1, 1},
                         {CERTRAY_SCENES_DIR "/fidget/colonnade.vm", -1, 1}};

const expr::Tape& tape_of(int scene) {
    static std::vector<expr::Tape> tapes = [] {
        std::vector<expr::Tape> t;
        for (const Scene& s : kScenes) t.emplace_back(expr::load_graph_file(s.path));
        return t;
    }();
    return tapes[scene];
}

/// A square image of side `side` of `tape` over the cube of `s`, its pinhole camera auto-framed as
/// the CLI frames it (on the cells where the surface may be).
void frame(tracers::CoherentOptions& o, const expr::Tape& tape, const Scene& s, unsigned side) {
    o.render.width = o.render.height = side;
    for (auto& a : o.render.bounds) a = {s.lo, s.hi};
    const std::vector<tracers::Box3> cells = tracers::surface_cells(tape, o.render.bounds);
    const auto extent = tracers::hull(cells);
    o.render.camera = extent ? tracers::frame_boxes(cells, *extent, 35, 1.0)
                             : tracers::frame_box(o.render.bounds, 35, 1.0);
}

/// The options of a square image of `scene`: bounds, and the CLI's auto-framed pinhole camera;
/// `image`: the solver options for images (no exact narrowing of hits, hit width 1e-6 relative).
tracers::CoherentOptions options(int scene, unsigned side, bool ortho, unsigned threads, bool image,
                                 bool solid = false) {
    tracers::CoherentOptions o;
    o.surface = solid ? tracers::Surface::Solid : tracers::Surface::Zero;
    o.certified = image ? tracers::image_solver_options() : solvers::CertifiedOptions{};
    o.depth_pixels = image ? 0.5 : 0.0;
    frame(o, tape_of(scene), kScenes[scene], side);
    o.render.threads = threads;
    o.projection = ortho ? tracers::Projection::Ortho : tracers::Projection::Pinhole;
    return o;
}

void report(benchmark::State& state, const tracers::RenderResult& r, double pixels) {
    state.counters["evals/px"] = static_cast<double>(r.stats.evals.total()) / pixels;
    state.counters["hit"] = static_cast<double>(r.stats.hit);
    state.counters["miss"] = static_cast<double>(r.stats.miss);
    state.counters["unknown"] = static_cast<double>(r.stats.unknown);
}

/// Arguments: scene, side, ortho, threads.
void BM_Coherent(benchmark::State& state) {
    const int scene = static_cast<int>(state.range(0));
    const unsigned side = static_cast<unsigned>(state.range(1));
    const tracers::CoherentOptions o =
        options(scene, side, state.range(2) != 0, static_cast<unsigned>(state.range(3)),
                state.range(4) != 0, state.range(5) != 0);
    tracers::RenderResult r;
    tracers::CoherentStats s;
    for (auto _ : state) {
        r = tracers::render_3d_coherent(tape_of(scene), o, &s);
        benchmark::DoNotOptimize(r.stats.hit);
    }
    const double px = static_cast<double>(side) * side;
    report(state, r, px);
    state.counters["boxes/px"] = static_cast<double>(s.box_evals) / px;
    state.counters["leaves/px"] = static_cast<double>(s.leaf_solves) / px;
    state.counters["scans/px"] = static_cast<double>(s.scans) / px;
    state.counters["together/px"] = static_cast<double>(s.together) / px;
    state.counters["tiles/px"] = static_cast<double>(s.tile_pieces) / px;
    state.counters["tile_hits/px"] = static_cast<double>(s.tile_decided) / px;
    state.counters["quarters/px"] = static_cast<double>(s.quarter_pieces) / px;
    state.counters["leaf_evals/px"] = static_cast<double>(r.stats.evals.total() - s.box_evals) / px;
    state.counters["box_len"] =
        s.box_evals > 0 ? static_cast<double>(s.box_instructions) / s.box_evals : 0;
}

/// The per-ray baseline: render_3d with the `certified` method on the same rays.
void BM_PerRay(benchmark::State& state) {
    const int scene = static_cast<int>(state.range(0));
    const unsigned side = static_cast<unsigned>(state.range(1));
    const bool ortho = state.range(2) != 0;
    const bool solid = state.range(5) != 0;
    const tracers::CoherentOptions o = options(
        scene, side, ortho, static_cast<unsigned>(state.range(3)), state.range(4) != 0, solid);
    const tracers::PixelRays rays(o);
    const expr::Tape& tape = tape_of(scene);
    const solvers::CertifiedOptions co = o.certified;
    solvers::SolidOptions so;
    so.budget = co.budget;
    so.hit_width = co.hit_width;
    const tracers::RayFunction certified = [&tape, co, so, solid](const Ray& ray) {
        return solid ? solvers::solid_first_entry(tape, ray, so)
                     : solvers::certified_first_root(tape, ray, co);
    };
    tracers::RenderResult r;
    for (auto _ : state) {
        if (!ortho) {
            r = tracers::render_3d(tape, certified, o.render);
        } else {
            // render_3d has no ortho camera: the same per-pixel loop over PixelRays' rays, rows
            // dealt out to the library's workers (tracers/parallel.h).
            const unsigned threads = static_cast<unsigned>(state.range(3));
            std::vector<tracers::RenderStats> part(threads);
            tracers::run_workers(threads, [&](unsigned w) {
                for (unsigned j = w; j < side; j += threads) {
                    for (unsigned i = 0; i < side; ++i) {
                        Ray ray;
                        if (!rays.ray(i, j, ray)) continue;
                        const RayResult a = certified(ray);
                        part[w].evals += a.evals;
                        part[w].hit += a.status == Status::Hit;
                        part[w].miss += a.status == Status::Miss;
                        part[w].unknown += a.status == Status::Unknown;
                    }
                }
            });
            r.stats = {};
            for (const tracers::RenderStats& p : part) {
                r.stats.evals += p.evals;
                r.stats.hit += p.hit;
                r.stats.miss += p.miss;
                r.stats.unknown += p.unknown;
            }
        }
        benchmark::DoNotOptimize(r.stats.hit);
    }
    report(state, r, static_cast<double>(side) * side);
}

// Arguments: scene (0 Barth, 1 hi, 2 quarter, 3 tanglecube, 4 Fidget's bear, 5 Fidget's
// colonnade), side, ortho, threads, image options, solid surface.
BENCHMARK(BM_Coherent)
    ->ArgNames({"scene", "side", "ortho", "threads", "image", "solid"})
    ->Args({0, 512, 0, 2, 0, 0})
    ->Args({0, 512, 0, 2, 1, 0})
    ->Args({0, 512, 1, 2, 0, 0})
    ->Args({0, 512, 1, 2, 1, 0})
    ->Args({0, 512, 0, 1, 1, 0})
    ->Args({0, 256, 0, 2, 1, 0})
    ->Args({0, 1024, 0, 2, 1, 0})
    ->Args({0, 256, 1, 2, 1, 0})
    ->Args({0, 1024, 1, 2, 1, 0})
    ->Args({1, 256, 1, 2, 1, 0})
    ->Args({1, 512, 1, 2, 1, 0})
    ->Args({2, 256, 1, 2, 1, 0})
    ->Args({2, 512, 1, 2, 1, 0})
    ->Args({1, 256, 0, 2, 1, 0})
    ->Args({2, 256, 0, 2, 1, 0})
    ->Args({3, 512, 0, 2, 1, 0})
    ->Args({4, 256, 1, 2, 1, 1})
    ->Args({4, 512, 1, 2, 1, 1})
    ->Args({4, 256, 0, 2, 1, 1})
    ->Args({4, 512, 0, 2, 1, 1})
    ->Args({5, 256, 1, 2, 1, 1})
    ->Args({5, 512, 1, 2, 1, 1})
    ->Args({5, 256, 0, 2, 1, 1})
    ->Args({5, 512, 0, 2, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_PerRay)
    ->ArgNames({"scene", "side", "ortho", "threads", "image", "solid"})
    ->Args({0, 512, 0, 2, 0, 0})
    ->Args({0, 512, 0, 2, 1, 0})
    ->Args({0, 512, 1, 2, 0, 0})
    ->Args({0, 512, 1, 2, 1, 0})
    ->Args({1, 256, 1, 2, 1, 0})
    ->Args({2, 256, 1, 2, 1, 0})
    ->Args({1, 256, 0, 2, 1, 0})
    ->Args({2, 256, 0, 2, 1, 0})
    ->Args({3, 512, 0, 2, 1, 0})
    ->Args({4, 256, 1, 2, 1, 1})
    ->Args({4, 256, 0, 2, 1, 1})
    ->Args({5, 256, 1, 2, 1, 1})
    ->Args({5, 256, 0, 2, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);

/// The tapes of `scenes`, in order.
template <std::size_t N>
std::vector<expr::Tape> tapes_of(const Scene (&scenes)[N]) {
    std::vector<expr::Tape> t;
    for (const Scene& s : scenes) t.emplace_back(expr::load_graph_file(s.path));
    return t;
}

/// The options of a square image of `tape` over the cube of `s` as `certray render` makes it:
/// pinhole camera framed by frame(), the image options, hits half a pixel deep, 2 threads.
tracers::CoherentOptions image_of(const expr::Tape& tape, const Scene& s, unsigned side) {
    tracers::CoherentOptions o;
    o.depth_pixels = 0.5;
    frame(o, tape, s, side);
    o.render.threads = 2;
    return o;
}

/// The smooth scenes of the gallery (tangent lists without kinks), over their files' bounds.
const Scene kSmooth[] = {{CERTRAY_SCENES_DIR "/barth_sextic.vm", -2, 2},
                         {CERTRAY_SCENES_DIR "/chmutov6.vm", -1.2, 1.2},
                         {CERTRAY_SCENES_DIR "/clebsch_cubic.vm", -2, 2},
                         {CERTRAY_SCENES_DIR "/kummer_quartic.vm", -3, 3},
                         {CERTRAY_SCENES_DIR "/mitchell.vm", -2.5, 2.5},
                         {CERTRAY_SCENES_DIR "/steiner_roman.vm", -1, 1},
                         {CERTRAY_SCENES_DIR "/tangle_knoll.vm", -3, 3},
                         {CERTRAY_SCENES_DIR "/tanglecube.vm", -4.5045, 4.5045},
                         {CERTRAY_SCENES_DIR "/blobs.expr", -2, 2},
                         {CERTRAY_SCENES_DIR "/gyroid.expr", -2, 2},
                         {CERTRAY_SCENES_DIR "/sphere.expr", -2, 2},
                         {CERTRAY_SCENES_DIR "/torus.expr", -2, 2}};

/// The coherent image of a smooth scene (its zero set, pinhole, framed as `certray render` frames
/// it, the image options, 2 threads) with and without one option, to be run with
/// --benchmark_enable_random_interleaving and repetitions: the two of each scene then alternate in
/// one process. Arguments: scene (kSmooth), side, option (0 segment_forms, 1 monotone_segments,
/// 2 float_lanes), on.
void BM_Option(benchmark::State& state) {
    static const std::vector<expr::Tape> tapes = tapes_of(kSmooth);
    const expr::Tape& tape = tapes[static_cast<std::size_t>(state.range(0))];
    const unsigned side = static_cast<unsigned>(state.range(1));
    tracers::CoherentOptions o = image_of(tape, kSmooth[state.range(0)], side);
    const bool on = state.range(3) != 0;
    switch (state.range(2)) {
        case 0:
            o.segment_forms = on;
            break;
        case 1:
            o.monotone_segments = on;
            break;
        case 2:
            o.float_lanes = on;
            break;
        default:
            state.SkipWithError("unknown option");
            return;
    }
    tracers::RenderResult r;
    for (auto _ : state) {
        r = tracers::render_3d_coherent(tape, o);
        benchmark::DoNotOptimize(r.stats.hit);
    }
    report(state, r, static_cast<double>(side) * side);
}

// Arguments: scene (kSmooth), side, option (0 segment_forms, 1 monotone_segments, 2
// float_lanes), on.
BENCHMARK(BM_Option)
    ->ArgNames({"scene", "side", "option", "on"})
    ->ArgsProduct({{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}, {512}, {0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

/// Scenes whose lists are long (hundreds to thousands of instructions), over their bounds.
const Scene kLong[] = {{CERTRAY_SCENES_DIR "/fidget/bear.vm", -1, 1},
                       {CERTRAY_SCENES_DIR "/molecule.json", -1.1, 1.1},
                       {CERTRAY_SCENES_DIR "/particles.txt", -2, 2},
                       {CERTRAY_SCENES_DIR "/test.json", -1, 1}};

/// The coherent image of a long-list scene (kLong) from the arguments scene, side, ortho, solid,
/// with `set` applied to the options, and its folds' counters: folds per pixel, the instructions
/// a fold drops on average, the scans of folded_together_rays per pixel.
template <class Set>
void long_image(benchmark::State& state, Set set) {
    static const std::vector<expr::Tape> tapes = tapes_of(kLong);
    const expr::Tape& tape = tapes[static_cast<std::size_t>(state.range(0))];
    const unsigned side = static_cast<unsigned>(state.range(1));
    tracers::CoherentOptions o = image_of(tape, kLong[state.range(0)], side);
    o.projection = state.range(2) != 0 ? tracers::Projection::Ortho : tracers::Projection::Pinhole;
    o.surface = state.range(3) != 0 ? tracers::Surface::Solid : tracers::Surface::Zero;
    set(o);
    tracers::RenderResult r;
    tracers::CoherentStats s;
    for (auto _ : state) {
        r = tracers::render_3d_coherent(tape, o, &s);
        benchmark::DoNotOptimize(r.stats.hit);
    }
    const double px = static_cast<double>(side) * side;
    report(state, r, px);
    state.counters["folds/px"] = static_cast<double>(s.folds) / px;
    state.counters["dropped"] =
        s.folds > 0 ? static_cast<double>(s.folded_instructions) / s.folds : 0;
    state.counters["wide/px"] = static_cast<double>(s.folded_scans) / px;
}

/// The other long-list scenes of an interleaved run of one option (the molecule's 128² pinhole
/// image, the particles' zero set and test.json at 512²), each with the option off (0) and `on`,
/// and the units of those runs.
void other_long_scenes(benchmark::internal::Benchmark* b, std::int64_t on) {
    for (const std::int64_t v : {std::int64_t{0}, on}) {
        b->Args({1, 128, 0, 1, v});
        b->Args({2, 512, 0, 0, v});
        b->Args({3, 512, 0, 1, v});
    }
    b->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
}

/// The lists of the scans folded to their boxes (CoherentOptions::fold_lists, 128) or not (0),
/// for interleaved runs as BM_Option. Arguments: scene (kLong), side, ortho, solid, fold.
void BM_Fold(benchmark::State& state) {
    long_image(state,
               [&](tracers::CoherentOptions& o) { o.fold_lists = state.range(4) != 0 ? 128 : 0; });
}

// Arguments: scene (kLong), side, ortho, solid, fold.
BENCHMARK(BM_Fold)
    ->ArgNames({"scene", "side", "ortho", "solid", "fold"})
    ->ArgsProduct({{0}, {512}, {1, 0}, {1}, {0, 1}})
    ->Apply([](benchmark::internal::Benchmark* b) { other_long_scenes(b, 1); });

/// Nodes of up to `rays` rays scanned together where their list folds
/// (CoherentOptions::folded_together_rays; 0: as together_rays allows), for interleaved runs.
/// Arguments: scene (kLong), side, ortho, solid, rays.
void BM_FoldedTogether(benchmark::State& state) {
    long_image(state, [&](tracers::CoherentOptions& o) {
        o.folded_together_rays = static_cast<unsigned>(state.range(4));
    });
}

// Arguments: scene (kLong), side, ortho, solid, rays.
BENCHMARK(BM_FoldedTogether)
    ->ArgNames({"scene", "side", "ortho", "solid", "rays"})
    ->ArgsProduct({{0}, {256, 512}, {0, 1}, {1}, {0, 64, 128}})
    ->Apply([](benchmark::internal::Benchmark* b) { other_long_scenes(b, 64); });

/// The segment forms on folded lists with the segments' plain enclosures first or not
/// (CoherentOptions::segment_enclosures_first), for interleaved runs: the same answers, fewer
/// lanes. Arguments: scene (kLong), side, ortho, solid, on.
void BM_SegmentEnclosures(benchmark::State& state) {
    long_image(state, [&](tracers::CoherentOptions& o) {
        o.segment_enclosures_first = state.range(4) != 0;
    });
}

// Arguments: scene (kLong), side, ortho, solid, on.
BENCHMARK(BM_SegmentEnclosures)
    ->ArgNames({"scene", "side", "ortho", "solid", "on"})
    ->ArgsProduct({{0}, {256, 512}, {0, 1}, {1}, {0, 1}})
    ->Apply([](benchmark::internal::Benchmark* b) { other_long_scenes(b, 1); });

/// The walks in lanes in binary32 bounds or in double (CoherentOptions::float_lanes), for
/// interleaved runs. Arguments: scene (kLong), side, ortho, solid, on.
void BM_FloatLanes(benchmark::State& state) {
    long_image(state, [&](tracers::CoherentOptions& o) { o.float_lanes = state.range(4) != 0; });
}

// Arguments: scene (kLong), side, ortho, solid, on.
BENCHMARK(BM_FloatLanes)
    ->ArgNames({"scene", "side", "ortho", "solid", "on"})
    ->ArgsProduct({{0}, {256, 512}, {0, 1}, {1}, {0, 1}})
    ->Apply([](benchmark::internal::Benchmark* b) { other_long_scenes(b, 1); });

/// The Lipschitz tracers' images with and without the cone march (tracers/cone.h): `certray render
/// --method M` and `--per-ray`. Arguments: scene, side, method (0 sphere, 1 enhanced, 2 bvh),
/// cone (1: march each tile first). The method and the march are built outside the timed loop
/// (as `make_method` builds them before `certray render` times the image), the zero surface.
void BM_Cone(benchmark::State& state) {
    static constexpr const char* kMethods[] = {"sphere", "enhanced", "bvh"};
    const int scene = static_cast<int>(state.range(0));
    const unsigned side = static_cast<unsigned>(state.range(1));
    const tracers::CoherentOptions o = options(scene, side, false, 2, true);
    const expr::Tape& tape = tape_of(scene);
    tracers::MethodOptions mo;
    const auto& b = o.render.bounds;
    mo.bounds = std::array<Interval, 3>{Interval(b[0][0], b[0][1]), Interval(b[1][0], b[1][1]),
                                        Interval(b[2][0], b[2][1])};
    const tracers::RayFunction fn = tracers::make_method(kMethods[state.range(2)], tape, mo);
    tracers::ConeOptions copt;
    copt.epsilon = mo.epsilon;
    const tracers::ConeMarch march(tape, b, copt);
    tracers::RenderOptions ro = o.render;
    if (state.range(3) != 0) ro.cone = &march;
    tracers::RenderResult r;
    for (auto _ : state) {
        r = tracers::render_3d(tape, fn, ro);
        benchmark::DoNotOptimize(r.stats.hit);
    }
    report(state, r, static_cast<double>(side) * side);
}

// Arguments: scene (0 Barth, 3 tanglecube), side, method (0 sphere, 1 enhanced, 2 bvh), cone.
BENCHMARK(BM_Cone)
    ->ArgNames({"scene", "side", "method", "cone"})
    ->ArgsProduct({{0, 3}, {512}, {0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace certray

BENCHMARK_MAIN();
