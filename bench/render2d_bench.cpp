// bench/render2d_bench.cpp — the 2D quadtree render of prospero.vm (tracers/image2d.h), Google
// Benchmark.
//
// Measures render_2d on scenes/prospero.vm at 1024×1024 over [−1, 1]² (Fidget's reference image:
// 132,816 pixels with f < 0; a run with another count is reported as an error) on 1 and 2 threads
// and for a few root tile sides, plus the brute-force batched evaluation of every pixel on 2
// threads for scale. Wall-clock time (UseRealTime): the render is multi-threaded. The first
// iteration faults in the walkers' pooled buffers; later ones reuse them, as repeated renders in
// one process do (a single `certray render` pays the faults: on a VM they cost ~35 µs a page).
// Counters: tiles decided from their enclosure and Batch walks per render.
// Command: build-*/bench/render2d_bench [--benchmark_repetitions=5]; results in docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <string>

#include "expr/load.h"
#include "expr/tape.h"
#include "tracers/image2d.h"

namespace certray {
namespace {

const expr::Tape& prospero() {
    static const expr::Tape tape(
        expr::load_graph_file(std::string(CERTRAY_SCENES_DIR) + "/prospero.vm"));
    return tape;
}

/// Arguments: threads, root tile side, quadtree (1) or brute force (0).
void BM_Prospero(benchmark::State& state) {
    const expr::Tape& tape = prospero();
    tracers::Image2dOptions o;
    o.threads = static_cast<unsigned>(state.range(0));
    o.root_tile = static_cast<unsigned>(state.range(1));
    o.use_quadtree = state.range(2) != 0;
    tracers::Image2d img;
    for (auto _ : state) {
        img = tracers::render_2d(tape, o);
        benchmark::DoNotOptimize(img.inside);
    }
    if (img.inside != 132816) {
        state.SkipWithError(("inside = " + std::to_string(img.inside)).c_str());
    }
    state.counters["inside"] = static_cast<double>(img.inside);
    state.counters["filled"] = static_cast<double>(img.tiles_filled);
    state.counters["batches"] = static_cast<double>(img.leaf_batches);
}
BENCHMARK(BM_Prospero)
    ->ArgNames({"threads", "root", "quadtree"})
    ->Args({1, 64, 1})
    ->Args({2, 64, 1})
    ->Args({1, 32, 1})
    ->Args({2, 32, 1})
    ->Args({1, 128, 1})
    ->Args({2, 128, 1})
    ->Args({2, 64, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace certray

BENCHMARK_MAIN();
