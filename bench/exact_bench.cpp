// bench/exact_bench.cpp — the exact oracle (solvers/exact.h): time per ray against the degree of
// g, Google Benchmark.
//
// g(t) = Π (t − rᵢ) along the x axis from tmin = −2 to tmax = +∞ (the Cauchy bound caps it), with
// `degree` roots in [−1, 1]: either dyadic rᵢ = kᵢ/64 (small coefficients) or random doubles with
// 53-bit mantissas (coefficients of about 53·degree bits), each product built once (fixed seed);
// and the same products with every root doubled (degree 2n: the square-free part does the work).
// For scale: the certified interval solver and the exact oracle on the Barth sextic
// (scenes/barth_sextic.vm, degree 6) over 64 rays through the scene. Counters: exact evaluations
// per ray (Sturm sequences or single polynomials at a point).
// Command: build/bench/exact_bench; results in docs/theory/exact.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "expr/builder.h"
#include "expr/graph.h"
#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/exact.h"

namespace certray {
namespace {

/// Π (x − rᵢ)^mult over `n` roots in [−1, 1]; dyadic (k/64) or random doubles.
expr::Tape product(int n, bool dyadic, unsigned mult) {
    std::mt19937_64 rng(20261124u + static_cast<unsigned>(n));
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    expr::Graph g;
    auto [x, y, z] = expr::vars(g);
    expr::Expr f = expr::constant(g, 1.0);
    for (int i = 0; i < n; ++i) {
        const double r = dyadic ? std::round(u(rng) * 64) / 64 : u(rng);
        f = f * expr::pow(x - r, mult);
    }
    g.set_output(f.id);
    return expr::Tape(g);
}

/// Arguments: number of distinct roots, dyadic (1) or random doubles (0), multiplicity.
void BM_ExactProduct(benchmark::State& state) {
    const auto n = static_cast<int>(state.range(0));
    const auto mult = static_cast<unsigned>(state.range(2));
    const expr::Tape tape = product(n, state.range(1) != 0, mult);
    const Ray ray{{0, 0, 0}, {1, 0, 0}, -2, std::numeric_limits<double>::infinity()};
    RayResult r;
    for (auto _ : state) {
        r = solvers::exact_first_root(tape, ray);
        benchmark::DoNotOptimize(r);
    }
    if (r.status != Status::Hit) state.SkipWithError("not a hit");
    state.counters["degree"] = static_cast<double>(n) * mult;
    state.counters["evals"] = static_cast<double>(r.evals.value);
}
BENCHMARK(BM_ExactProduct)
    ->ArgNames({"roots", "dyadic", "mult"})
    ->ArgsProduct({{1, 2, 4, 6, 8, 12, 16, 24, 32, 48, 64}, {1, 0}, {1}})
    ->ArgsProduct({{2, 4, 8, 16, 32}, {1, 0}, {2}})
    ->Unit(benchmark::kMicrosecond);

const expr::Tape& barth() {
    static const expr::Tape tape(
        expr::load_graph_file(std::string(CERTRAY_SCENES_DIR) + "/barth_sextic.vm"));
    return tape;
}

std::vector<Ray> barth_rays() {
    std::vector<Ray> rays;
    for (int j = 0; j < 8; ++j) {
        for (int i = 0; i < 8; ++i) {
            rays.push_back(Ray{{-3, -1.2 + 0.3 * i, -1.2 + 0.3 * j}, {1, 0.01, -0.02}, 0, 6});
        }
    }
    return rays;
}

/// Arguments: exact (1) or certified (0); time per ray over 64 rays.
void BM_Barth(benchmark::State& state) {
    const std::vector<Ray> rays = barth_rays();
    std::uint64_t evals = 0;
    for (auto _ : state) {
        evals = 0;
        for (const Ray& ray : rays) {
            const RayResult r = state.range(0) ? solvers::exact_first_root(barth(), ray)
                                               : solvers::certified_first_root(barth(), ray);
            evals += r.evals.total();
            benchmark::DoNotOptimize(r);
        }
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * rays.size()));
    state.counters["evals/ray"] = static_cast<double>(evals) / static_cast<double>(rays.size());
}
BENCHMARK(BM_Barth)->ArgName("exact")->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace certray

BENCHMARK_MAIN();
