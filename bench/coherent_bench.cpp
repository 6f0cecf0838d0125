// bench/coherent_bench.cpp — coherent certified rendering (tracers/coherent.h) against one
// certified solve per pixel (render_3d with `certified`), Google Benchmark.
//
// Scenes: scenes/barth_sextic.vm over [−2, 2]³, framed as `certray render` frames it (the cells
// where the surface may be, seen from (1, −2, 0.8), fov 35°), and the Fidget models of
// /work/shared/models (CERTRAY_MODELS_DIR) over [−1, 1]³. Pinhole and ortho (heightmap along −z)
// cameras; sizes 256², 512², 1024². Wall-clock time (UseRealTime): the renders are threaded.
// Counters per pixel: whole-tape evaluations (evals/px: box evaluations + every leaf solve's),
// box evaluations (boxes/px), leaf solves (leaves/px), and the image's hit/miss/unknown counts.
// Command: build/bench/coherent_bench [--benchmark_filter=…]; results in docs/benchmarks.md,
// "Coherent certified rendering".
#include <benchmark/benchmark.h>

#include <string>
#include <thread>
#include <vector>

#include "expr/load.h"
#include "expr/tape.h"
#include "tracers/camera.h"
#include "tracers/coherent.h"
#include "tracers/methods.h"
#include "tracers/render.h"

namespace certray {
namespace {

struct Scene {
    const char* path;
    double lo, hi;
};
const Scene kScenes[] = {{CERTRAY_SCENES_DIR "/barth_sextic.vm", -2, 2},
                         {CERTRAY_MODELS_DIR "/hi.vm", -1, 1},
                         {CERTRAY_MODELS_DIR "/quarter.vm", -1, 1},
                         {CERTRAY_SCENES_DIR "/tanglecube.vm", -2, 2}};

const expr::Tape& tape_of(int scene) {
    static std::vector<expr::Tape> tapes = [] {
        std::vector<expr::Tape> t;
        for (const Scene& s : kScenes) t.emplace_back(expr::load_graph_file(s.path));
        return t;
    }();
    return tapes[scene];
}

/// The options of a square image of `scene`: bounds, and the CLI's auto-framed pinhole camera.
tracers::CoherentOptions options(int scene, unsigned side, bool ortho, unsigned threads) {
    tracers::CoherentOptions o;
    const Scene& s = kScenes[scene];
    o.render.width = o.render.height = side;
    for (auto& a : o.render.bounds) a = {s.lo, s.hi};
    const std::vector<tracers::Box3> cells =
        tracers::surface_cells(tape_of(scene), o.render.bounds);
    const auto extent = tracers::hull(cells);
    o.render.camera = extent ? tracers::frame_boxes(cells, *extent, 35, 1.0)
                             : tracers::frame_box(o.render.bounds, 35, 1.0);
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
        options(scene, side, state.range(2) != 0, static_cast<unsigned>(state.range(3)));
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
    state.counters["box_len"] =
        s.box_evals > 0 ? static_cast<double>(s.box_instructions) / s.box_evals : 0;
}

/// The per-ray baseline: render_3d with the `certified` method on the same rays.
void BM_PerRay(benchmark::State& state) {
    const int scene = static_cast<int>(state.range(0));
    const unsigned side = static_cast<unsigned>(state.range(1));
    const bool ortho = state.range(2) != 0;
    const tracers::CoherentOptions o =
        options(scene, side, ortho, static_cast<unsigned>(state.range(3)));
    const tracers::PixelRays rays(o);
    const expr::Tape& tape = tape_of(scene);
    const tracers::RayFunction certified = tracers::make_method("certified", tape, {});
    tracers::RenderResult r;
    for (auto _ : state) {
        if (!ortho) {
            r = tracers::render_3d(tape, certified, o.render);
        } else {
            // render_3d has no ortho camera: the same per-pixel loop over PixelRays' rays, rows
            // dealt out to the threads.
            const unsigned threads = static_cast<unsigned>(state.range(3));
            std::vector<tracers::RenderStats> part(threads);
            std::vector<std::thread> pool;
            for (unsigned w = 0; w < threads; ++w) {
                pool.emplace_back([&, w] {
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
            }
            for (std::thread& t : pool) t.join();
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

// Barth: coherent against per-ray at 512², pinhole and ortho, 2 threads; coherent at 256², 1024².
BENCHMARK(BM_Coherent)
    ->ArgNames({"scene", "side", "ortho", "threads"})
    ->Args({0, 512, 0, 2})
    ->Args({0, 512, 1, 2})
    ->Args({0, 512, 0, 1})
    ->Args({0, 256, 0, 2})
    ->Args({0, 1024, 0, 2})
    ->Args({0, 256, 1, 2})
    ->Args({0, 1024, 1, 2})
    ->Args({1, 256, 1, 2})
    ->Args({1, 512, 1, 2})
    ->Args({2, 256, 1, 2})
    ->Args({2, 512, 1, 2})
    ->Args({1, 256, 0, 2})
    ->Args({2, 256, 0, 2})
    ->Args({3, 512, 0, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PerRay)
    ->ArgNames({"scene", "side", "ortho", "threads"})
    ->Args({0, 512, 0, 2})
    ->Args({0, 512, 1, 2})
    ->Args({1, 256, 1, 2})
    ->Args({2, 256, 1, 2})
    ->Args({1, 256, 0, 2})
    ->Args({2, 256, 0, 2})
    ->Args({3, 512, 0, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace certray

BENCHMARK_MAIN();
