// bench/ray_bench.cpp — every registered method on the gallery's rays: time, evaluations and
// error against the MPFR reference (Google Benchmark).
//
// For each 3D scene of scenes/ (or the files given with --scenes=a,b,…) and the rays of
// scenes/rays.csv: first the reference answer of every ray
// (solvers::certified_first_root_reference, 256-bit MPFR intervals: enclosures of adjacent
// doubles); then one benchmark `<method>/<scene>` per method of the registry (tracers/methods.h)
// that applies to the scene, each iteration answering every ray. After the runs, one table: per
// method and scene, µs and evaluations per ray, and against the reference: correct (hit within the
// reference enclosure widened by `tolerance`, or both miss), missed hits, false hits, overshoots (a
// later root), unknowns, the largest |t − t*| and, for certified methods, the median enclosure
// width in ulps. Results and the command: docs/benchmarks.md, "Ray queries by method".
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "solvers/ray.h"
#include "solvers/ray_io.h"
#include "tracers/methods.h"
#include "tracers/octree.h"

namespace certray {
namespace {

struct Scene {
    std::string name;
    expr::Tape tape;
    std::vector<RayResult> reference;
};

std::vector<Scene> g_scenes;
std::vector<Ray> g_rays;

struct MethodRun {
    std::string method;
    const Scene* scene;
    tracers::RayFunction fn;
    std::vector<RayResult> results;
    double seconds_per_pass = 0;
};
std::vector<MethodRun> g_runs;

void bm_method(benchmark::State& state, MethodRun* run) {
    for (auto _ : state) {
        for (std::size_t i = 0; i < g_rays.size(); ++i) run->results[i] = run->fn(g_rays[i]);
        benchmark::ClobberMemory();
    }
}

double ulps(double lo, double hi) {
    double n = 0;
    for (double x = lo; x < hi && n < 1e6; x = std::nextafter(x, 1e300)) ++n;
    return n;
}

/// The table of errors against the reference, one line per run.
void print_table(const std::map<std::string, double>& seconds) {
    std::printf("\n%-18s %-16s %9s %9s %7s %6s %6s %6s %6s %6s %10s %8s\n", "method", "scene",
                "us/ray", "evals/ray", "correct", "missed", "false", "over", "unknwn", "refunk",
                "max|t-t*|", "med ulps");
    for (const MethodRun& r : g_runs) {
        const auto it = seconds.find(r.method + "/" + r.scene->name);
        const double us = it == seconds.end()
                              ? std::numeric_limits<double>::quiet_NaN()
                              : it->second * 1e6 / static_cast<double>(g_rays.size());
        std::uint64_t evals = 0;
        int correct = 0, missed = 0, false_hit = 0, over = 0, unknown = 0, ref_unknown = 0;
        double max_err = 0;
        std::vector<double> widths;
        for (std::size_t i = 0; i < g_rays.size(); ++i) {
            const RayResult& m = r.results[i];
            const RayResult& ref = r.scene->reference[i];
            evals += m.evals.total();
            if (ref.status == Status::Unknown) {
                ++ref_unknown;
                continue;
            }
            if (m.status == Status::Unknown) {
                ++unknown;
                continue;
            }
            if (ref.status == Status::Miss) {
                if (m.status == Status::Miss) {
                    ++correct;
                } else {
                    ++false_hit;
                }
                continue;
            }
            if (m.status == Status::Miss) {
                ++missed;
                continue;
            }
            // Both hit: the error of t against the reference enclosure [t_lo*, t_hi*].
            const double err =
                m.t < ref.t_lo ? ref.t_lo - m.t : (m.t > ref.t_hi ? m.t - ref.t_hi : 0.0);
            const double tol = 1e-6 * std::max(1.0, std::fabs(ref.t));
            max_err = std::max(max_err, err);
            if (m.t > ref.t_hi + tol) {
                ++over;
            } else if (m.t < ref.t_lo - tol) {
                ++false_hit;  // a hit before the first root: a root that is not there
            } else {
                ++correct;
            }
            if (m.t_lo < m.t_hi) widths.push_back(ulps(m.t_lo, m.t_hi));
        }
        double med = std::numeric_limits<double>::quiet_NaN();
        if (!widths.empty()) {
            std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
            med = widths[widths.size() / 2];
        }
        std::printf("%-18s %-16s %9.2f %9.1f %7d %6d %6d %6d %6d %6d %10.3g %8.0f\n",
                    r.method.c_str(), r.scene->name.c_str(), us,
                    static_cast<double>(evals) / static_cast<double>(g_rays.size()), correct,
                    missed, false_hit, over, unknown, ref_unknown, max_err, med);
    }
}

/// Collects the CPU time per pass of each benchmark.
class Collector : public benchmark::ConsoleReporter {
  public:
    std::map<std::string, double> seconds;
    void ReportRuns(const std::vector<benchmark::BenchmarkReporter::Run>& runs) override {
        for (const auto& run : runs) {
            seconds[run.benchmark_name()] =
                run.GetAdjustedCPUTime() / 1e9;  // default time unit: ns
        }
        ConsoleReporter::ReportRuns(runs);
    }
};

}  // namespace
}  // namespace certray

int main(int argc, char** argv) {
    using namespace certray;
    namespace fs = std::filesystem;
    const fs::path dir = CERTRAY_SCENES_DIR;
    g_rays = read_rays_csv_file((dir / "rays.csv").string());
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".expr" || ext == ".vm") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
        expr::Tape tape(expr::load_graph_file(f.string()));
        if (!tape.uses_var(2)) continue;  // 2D scenes are images, not ray queries
        g_scenes.push_back({f.stem().string(), std::move(tape), {}});
    }
    std::fprintf(stderr, "ray_bench: references (MPFR) for %zu scenes x %zu rays\n",
                 g_scenes.size(), g_rays.size());
    for (Scene& s : g_scenes) {
        for (const Ray& r : g_rays) {
            s.reference.push_back(solvers::certified_first_root_reference(s.tape, r));
        }
    }
    g_runs.reserve(64 * g_scenes.size());
    for (const std::string& m : tracers::method_names()) {
        if (m == "reference") continue;
        for (const Scene& s : g_scenes) {
            tracers::RayFunction fn;
            try {
                fn = tracers::make_method(m, s.tape, tracers::MethodOptions{});
            } catch (const std::invalid_argument& e) {
                std::fprintf(stderr, "ray_bench: %s/%s skipped: %s\n", m.c_str(), s.name.c_str(),
                             e.what());
                continue;
            }
            g_runs.push_back({m, &s, std::move(fn), std::vector<RayResult>(g_rays.size()), 0});
        }
    }
    for (MethodRun& r : g_runs) {
        benchmark::RegisterBenchmark((r.method + "/" + r.scene->name).c_str(), bm_method, &r);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    Collector reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    print_table(reporter.seconds);
    // The octree of the octree methods (depth 5 over [−2, 2]³): build time and memory.
    std::printf("\n%-16s %8s %8s %8s %8s %10s %12s %10s\n", "octree", "nodes", "empty", "full",
                "ambig", "tapes", "KiB", "build ms");
    const std::array<Interval, 3> cube{Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};
    for (const Scene& s : g_scenes) {
        const tracers::Octree tree(s.tape, cube, {5, std::size_t{1} << 20});
        const tracers::OctreeStats& st = tree.stats();
        std::printf("%-16s %8zu %8zu %8zu %8zu %10zu %12.0f %10.1f\n", s.name.c_str(), st.nodes,
                    st.empty, st.full, st.ambiguous, st.distinct_tapes,
                    static_cast<double>(st.bytes) / 1024, st.build_seconds * 1e3);
    }
    benchmark::Shutdown();
    return 0;
}
