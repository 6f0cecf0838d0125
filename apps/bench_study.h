// apps/bench_study.h — internal to `certray bench`: the study's data and what its three parts
// share (apps/bench.cpp measures, apps/bench_peers.cpp compares with the literature's own
// numbers, apps/bench_report.cpp writes the CSV files and the report).
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "apps/bench.h"
#include "expr/tape.h"
#include "solvers/ray.h"
#include "solvers/ray_io.h"
#include "tracers/methods.h"
#include "tracers/parallel.h"

namespace certray::apps::study {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

inline constexpr const char* kClassNames[] = {"correct", "missed", "false_hit", "overshoot",
                                              "unknown"};
inline constexpr const char* kTruthNames[] = {"hit", "miss", "tangent", "nohit", "unknown"};

/// One method at one knob setting.
struct Config {
    std::string method;
    std::string knob = "default";
    double value = 0;
    tracers::MethodOptions opts;
    bool certified = false;
    MethodFactory factory;  ///< set for extra methods
    double tol_epsilon = 1e-6;
    /// The knob value run nearest MethodOptions' default (the stress table's column; with
    /// --quick it may differ from the default, and the column is then named by its label()).
    bool is_default = true;
    std::string label() const {
        if (knob == "default") return method;
        char buf[64];
        std::snprintf(buf, sizeof buf, " %s=%g", knob.c_str(), value);
        return method + buf;
    }
};

/// A scene with its rays and the truth of each ray.
struct Scene {
    std::string name;
    std::string suite;  ///< "gallery" or "stress"
    expr::Tape tape;
    std::vector<Ray> rays;
    std::vector<Truth> truth;
    std::vector<std::string> cases;  ///< stress case names (empty for the gallery)
    std::vector<double> ref_us;      ///< reference time per ray (gallery)
    /// Rays judged by each judge ("exact rational (Sturm)", "MPFR reference", "mpmath brackets").
    std::map<std::string, std::size_t> judged_by;
};

/// One measurement.
struct Row {
    const Config* config;
    const Scene* scene;
    std::size_t ray;
    RayResult result;
    double us;
    BenchClass cls;
    double error;
};

/// The per (config, scene) aggregate.
struct Summary {
    const Config* config;
    const Scene* scene;
    double setup_ms = 0;
    std::size_t rays = 0;
    double mean_us = 0, median_us = 0;
    double ev_value = 0, ev_interval = 0, ev_gradient = 0, ev_total = 0;
    std::array<std::size_t, 5> counts{};
    std::size_t ref_unknown = 0;
    double max_error = std::numeric_limits<double>::quiet_NaN();
    double median_error = std::numeric_limits<double>::quiet_NaN();
    std::size_t wrong() const { return counts[1] + counts[2] + counts[3]; }
};

struct Study {
    std::vector<Config> gallery_configs, stress_configs;
    std::vector<Scene> gallery, stress;
    std::vector<Row> rows;
    std::vector<Summary> summaries;
    std::vector<std::string> notes;  ///< missing tools, TODOs
    /// method → scenes where it does not apply, and the first reason given
    std::map<std::string, std::pair<std::vector<std::string>, std::string>> skipped;
    std::vector<std::array<std::string, 4>> peers;  ///< peer, item, value, note
    std::vector<std::string> pruning;               ///< pruning.csv lines
    std::string peer_md;                            ///< the peers section of the report
};

inline std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

inline std::string num(double v) {
    std::string s;
    append_double(s, v);
    return s;
}

inline double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

/// Writes `text` to `path` through a temporary file and a rename: never a half-written file.
void write_atomic(const fs::path& path, const std::string& text);

/// `path` as given when it exists; else, for a relative path, the same path under the source tree
/// (so that `certray bench` finds scenes/ and scripts/ from any directory).
std::string resolve(const std::string& path);

/// Runs f(i, first) for i in [0, n) on `threads` threads; `first` is true on each thread's first
/// call (its warm-up).
template <class F>
void parallel_for(unsigned threads, std::size_t n, F&& f) {
    // The library's parallel loop (tracers/parallel.h), one index at a time; `first` is true for
    // the first index a worker takes.
    std::vector<char> started(std::max(1u, threads), 0);
    tracers::ParallelOptions po;
    po.threads = std::max(1u, threads);
    po.chunk = 1;
    tracers::parallel_for(n, po, [&](std::size_t i, std::size_t, unsigned worker) {
        const bool first = !started[worker];
        started[worker] = 1;
        f(i, first);
    });
}

/// Progress on stderr: a bar on a terminal; elsewhere (a file, a pipe, CI) a line with the
/// percentage, the rate and the time left at most every 5 s; nothing when off.
class Progress {
  public:
    enum class Mode { Off, Bar, Lines };
    Progress(Mode mode, std::size_t total)
        : mode_(mode),
          total_(std::max<std::size_t>(1, total)),
          start_(std::chrono::steady_clock::now()),
          last_(start_) {}
    void add(std::size_t n, const std::string& what) {
        done_ += n;
        const double f = std::min(1.0, static_cast<double>(done_) / static_cast<double>(total_));
        if (mode_ == Mode::Bar) {
            const int w = 30, k = static_cast<int>(f * w);
            std::fprintf(stderr, "\r[%s%s] %3.0f%% %-40.40s", std::string(k, '#').c_str(),
                         std::string(w - k, '.').c_str(), 100 * f, what.c_str());
            std::fflush(stderr);
        } else if (mode_ == Mode::Lines) {
            const auto now = std::chrono::steady_clock::now();
            if (now - last_ < std::chrono::seconds(5) && done_ < total_) return;
            last_ = now;
            const double s = std::chrono::duration<double>(now - start_).count();
            const double left = f > 0 ? s * (1 - f) / f : 0.0;
            std::fprintf(stderr,
                         "certray bench: %3.0f%% (%zu of %zu ray runs, %.0f/s), %.0f s left: %s\n",
                         100 * f, done_, total_, s > 0 ? static_cast<double>(done_) / s : 0.0, left,
                         what.c_str());
        }
    }
    void finish() {
        if (mode_ == Mode::Bar) std::fprintf(stderr, "\n");
    }

  private:
    Mode mode_;
    std::size_t total_, done_ = 0;
    std::chrono::steady_clock::time_point start_, last_;
};

// ---- the peers (apps/bench_peers.cpp): the literature's numbers beside ours ------------------
void peer_prospero(const BenchOptions& o, Study& st);
void peer_segment(const BenchOptions& o, Study& st);
void peer_enhanced(Study& st);
/// Tape length per octree level over the cells that may hold the surface.
void peer_pruning(const std::vector<const Scene*>& scenes, const std::vector<expr::Tape>& extra2d,
                  const std::vector<std::string>& extra_names, Study& st);

// ---- the outputs (apps/bench_report.cpp) -----------------------------------------------------
std::string measurements_csv(const Study& st);
std::string summary_csv(const Study& st);
/// The markdown report; counts the wrong answers of certified methods into certified_wrong.
std::string make_report(const BenchOptions& o, const Study& st, unsigned threads,
                        std::size_t& certified_wrong);

}  // namespace certray::apps::study
