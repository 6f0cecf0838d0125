// apps/bench.h — `certray bench`: the error-against-run-time study of every ray method.
//
// Contract: for each method × knob setting × scene × ray, run_bench measures the wall time of the
// call (std::chrono::steady_clock around one call, on the worker thread that makes it), the
// whole-tape evaluations by kind, the status and t, and compares the answer with the truth: the
// MPFR reference (solvers::certified_first_root_reference, cached once per scene and ray) on the
// gallery, the exact brackets of scenes/stress/cases.csv on the stress suite. Each answer gets a
// class (correct, missed, false hit, overshoot, unknown; see classify() and docs/theory/bench.md).
// Writes OUT/measurements.csv, OUT/summary.csv, OUT/stress.csv, OUT/peers.csv, OUT/report.md
// (and a copy at `report` when set), then runs `python3 scripts/bench_plot.py OUT` for the PNG
// plots (skipped with a note when python3 or matplotlib is missing). Every file is written to
// PATH.tmp and renamed into place when complete.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "expr/tape.h"
#include "solvers/ray.h"
#include "tracers/camera.h"
#include "tracers/methods.h"

namespace certray::apps {

/// Makes a method's per-ray function for a scene (as tracers::make_method, for methods that are
/// not in the registry). May throw std::invalid_argument when the method does not apply.
using MethodFactory =
    std::function<tracers::RayFunction(const expr::Tape&, const tracers::MethodOptions&)>;

/// A method given by the caller (tests, experiments): measured like the registered ones.
struct ExtraMethod {
    std::string name;        ///< its name in the outputs (must not contain commas)
    MethodFactory factory;   ///< builds the per-ray function once per scene and knob setting
    bool certified = false;  ///< classified as certified: any wrong answer is reported loudly
    double epsilon = 1e-6;   ///< the ε used for its tolerance (MethodOptions::epsilon is set too)
};

/// The options of `certray bench` (the command line of apps/certray.cpp sets them).
struct BenchOptions {
    std::string out_dir = "bench-out";  ///< --out: the output directory (created)
    std::string report;                 ///< --report: also write report.md here (docs/report.md)
    std::string scenes_dir = "scenes";  ///< --scenes-dir: the gallery (3D *.expr, *.vm, rays.csv)
    std::vector<std::string> scenes;    ///< --scene: scene files instead of the gallery's 3D ones
    std::string rays;                   ///< --rays: RAYS.csv; empty: SCENES_DIR/rays.csv
    std::string stress;  ///< --stress: cases.csv; empty: SCENES_DIR/stress/cases.csv; "none": skip
    std::string models_dir;  ///< --models: extra peer models (prospero.vm, segment-tracing/…)
    std::vector<std::string> methods;        ///< --methods: registry names to run; empty: all
    std::vector<ExtraMethod> extra_methods;  ///< methods given in code (no CLI flag)
    bool quick = false;  ///< --quick: 3 scenes, 32 rays, 2 knob values, no peers (CI, seconds)
    bool peers = true;   ///< --no-peers clears it: skip the peer benchmarks
    bool plots = true;   ///< --no-plots clears it: do not run scripts/bench_plot.py
    std::string plot_script = "scripts/bench_plot.py";  ///< --plot-script
    std::size_t max_rays = 0;  ///< --max-rays: use the first N rays of RAYS.csv (0: all; quick 32)
    unsigned threads = 0;      ///< --threads: workers (0: one per hardware thread)
    unsigned repeats = 1;      ///< --repeats: time each ray this many times, keep the fastest
    int progress = -1;         ///< --progress/--no-progress; -1: a bar when stderr is a terminal
};

/// What an answer is, measured against the truth (docs/theory/bench.md).
enum class BenchClass : std::uint8_t { Correct, Missed, FalseHit, Overshoot, Unknown };

/// The truth for one ray: the first root lies in [lo, hi] (hit), or there is none (miss), or a
/// double root / an unprovable root lies in [lo, hi] (tangent: hit or unknown are both right),
/// or a near miss where hit is wrong and miss or unknown are right (nohit), or unknown.
struct Truth {
    enum Kind : std::uint8_t { Hit, Miss, Tangent, NoHit, Unknown } kind = Unknown;
    double lo = 0;
    double hi = 0;
};

/// The tolerance of an approximate hit: max(10·epsilon, 1e-9·max(1, |t*|)). The factor 10: a
/// tracer stops when |f|/λ < ε, and the distance along the ray to the root exceeds that by
/// λ/|g′(t)| (1/cos of the incidence angle), so rays up to 84° from the normal are judged fairly.
double bench_tolerance(double epsilon, double t_star);

/// The class of `answer` against `truth`. A certified method is judged by its enclosure
/// [t_lo, t_hi] (right when it meets [lo, hi]); an approximate one by its point t, right within
/// `tolerance` of [lo, hi]. An unknown whose t_lo lies past the root by more than the tolerance
/// claims "no root before t_lo" wrongly and is an overshoot. Truth::Unknown gives Unknown.
BenchClass classify(const RayResult& answer, const Truth& truth, bool certified, double tolerance);

/// |t − t*|: the distance from the answer's t to [lo, hi] (0 inside); NaN unless both hit.
double bench_error(const RayResult& answer, const Truth& truth);

/// Runs the study and writes its outputs. Returns 0 on success, 3 when a certified method gave a
/// wrong answer (the outputs are still written and the report says so loudly). Throws
/// certray::InputError for bad scene, ray or case files, std::invalid_argument for bad options
/// (repeats 0) and std::runtime_error when an output cannot be written. Relative paths that do
/// not exist (scenes_dir, models_dir, plot_script) are also looked up under the source tree.
int run_bench(const BenchOptions& options);

/// The view of the segment-tracing peer comparison, which `certray bench` and
/// bench/segment_bench.cpp must trace alike: from (0, −80, 0) at the origin, z up, fov 35°,
/// kSegmentPeerSide × kSegmentPeerSide pixels.
inline constexpr unsigned kSegmentPeerSide = 100;
tracers::Camera segment_peer_camera();

}  // namespace certray::apps
