// bench/heightmap_bench.cpp — the certified heightmap of any model, timed as a peer times its own:
// in one process, after a render to warm up, Google Benchmark.
//
// `certray render MODEL --camera ortho --surface solid --bounds -1 1 --size N×N --threads 2`
// runs once in a fresh process: its time includes the first touch of the image's pages and a
// cold cache. libfive's heightmap timings (and the driver docs/benchmarks.md compares with, which
// renders once to warm up and then takes the median of five) are warm. This program renders the
// same image through the same call as the command line (certray::render with its settings:
// heightmap over [−1, 1]³, the solid surface, hits half a pixel deep, shade AOV, 2 threads) in one
// process, so that both sides are measured alike.
//
// Usage: build/bench/heightmap_bench MODEL... [--side=N]... [Google Benchmark flags]
//   e.g. heightmap_bench scenes/fidget/bear.vm --side=256 --side=512
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// (median of five, as the libfive driver). Default side 512. Counters: hit and miss pixels and
// whole-tape evaluations per pixel. Results in docs/benchmarks.md (session 23).

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "certray/render.h"
#include "certray/scene.h"

namespace {

using certray::RenderSettings;
using certray::Scene;

void bm_heightmap(benchmark::State& state, const Scene* scene, unsigned side) {
    RenderSettings s;
    s.width = s.height = side;
    s.ortho = true;
    s.surface = certray::tracers::Surface::Solid;
    s.bounds = certray::tracers::Box3{{{-1, 1}, {-1, 1}, {-1, 1}}};
    s.depth_pixels = 0.5;  // as `certray render` writes an image
    s.threads = 2;
    certray::tracers::RenderResult r = certray::render(*scene, s);  // warm-up
    for (auto _ : state) {
        r = certray::render(*scene, s);
        benchmark::DoNotOptimize(r.stats.hit);
    }
    const double px = static_cast<double>(side) * side;
    state.counters["hit"] = static_cast<double>(r.stats.hit);
    state.counters["miss"] = static_cast<double>(r.stats.miss);
    state.counters["unknown"] = static_cast<double>(r.stats.unknown);
    state.counters["evals/px"] = static_cast<double>(r.stats.evals.total()) / px;
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    // What Google Benchmark left: models and --side=N.
    std::vector<std::string> models;
    std::vector<unsigned> sides;
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        if (a.rfind("--side=", 0) == 0) {
            const long n = std::strtol(a.c_str() + 7, nullptr, 10);
            if (n < 1 || n > 16384) {
                std::fprintf(stderr, "heightmap_bench: bad side '%s' (1 to 16384)\n", a.c_str());
                return 2;
            }
            sides.push_back(static_cast<unsigned>(n));
        } else if (a.rfind("--", 0) == 0) {
            std::fprintf(stderr, "heightmap_bench: unknown flag '%s'\n", a.c_str());
            return 2;
        } else {
            models.push_back(a);
        }
    }
    if (models.empty()) {
        std::fprintf(stderr,
                     "usage: heightmap_bench MODEL... [--side=N]... [Google Benchmark flags]\n");
        return 2;
    }
    if (sides.empty()) sides.push_back(512);
    std::vector<Scene> scenes;
    scenes.reserve(models.size());
    for (const std::string& m : models) {
        try {
            scenes.push_back(Scene::load(m));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "heightmap_bench: %s: %s\n", m.c_str(), e.what());
            return 1;
        }
    }
    for (std::size_t k = 0; k < scenes.size(); ++k) {
        for (unsigned side : sides) {
            const std::string name = "heightmap/" + models[k] + "/" + std::to_string(side);
            benchmark::RegisterBenchmark(name.c_str(), bm_heightmap, &scenes[k], side)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
        }
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
