// apps/bench.cpp — the error-against-run-time study (`certray bench`, issue 6): measurement,
// classification against the MPFR reference and the stress brackets, CSV outputs and the report.
//
// Contract: apps/bench.h. Timing: rays run in parallel on `threads` std::threads, each ray timed
// alone (steady_clock around one call) on the thread that answers it; each thread first answers
// one ray untimed (its scratch space is allocated then). Reference: docs/theory/bench.md.
#include "apps/bench.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "expr/input_error.h"
#include "expr/load.h"
#include "expr/prune.h"
#include "solvers/certified.h"
#include "solvers/ray_io.h"
#include "tracers/camera.h"
#include "tracers/image2d.h"

namespace certray::apps {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double bench_tolerance(double epsilon, double t_star) {
    return std::max(10 * epsilon, 1e-9 * std::max(1.0, std::fabs(t_star)));
}

double bench_error(const RayResult& a, const Truth& truth) {
    const bool truth_root = truth.kind == Truth::Hit || truth.kind == Truth::Tangent;
    if (a.status != Status::Hit || !truth_root || std::isnan(a.t)) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    return a.t < truth.lo ? truth.lo - a.t : (a.t > truth.hi ? a.t - truth.hi : 0.0);
}

BenchClass classify(const RayResult& a, const Truth& truth, bool certified, double tol) {
    if (truth.kind == Truth::Unknown) return BenchClass::Unknown;
    const bool root = truth.kind == Truth::Hit || truth.kind == Truth::Tangent;
    if (a.status == Status::Unknown) {
        // An unknown still claims "no root in [tmin, t_lo)".
        if (root && std::isfinite(a.t_lo) && a.t_lo > truth.hi + (certified ? 0.0 : tol)) {
            return BenchClass::Overshoot;
        }
        return BenchClass::Unknown;
    }
    if (a.status == Status::Miss) return root ? BenchClass::Missed : BenchClass::Correct;
    if (!root) return BenchClass::FalseHit;  // Miss or NoHit truth, a hit answered
    // The answer's claim: its enclosure (certified), or t widened by the tolerance.
    const double claim_lo = certified ? a.t_lo : a.t - tol;
    const double claim_hi = certified ? a.t_hi : a.t + tol;
    if (std::isnan(a.t) || std::isnan(claim_lo) || std::isnan(claim_hi)) {
        return BenchClass::FalseHit;  // a hit without a place
    }
    if (claim_hi < truth.lo) return BenchClass::FalseHit;   // a root before the first one
    if (claim_lo > truth.hi) return BenchClass::Overshoot;  // a later root
    return BenchClass::Correct;
}

namespace {

constexpr const char* kClassNames[] = {"correct", "missed", "false_hit", "overshoot", "unknown"};
constexpr const char* kTruthNames[] = {"hit", "miss", "tangent", "nohit", "unknown"};

/// One method at one knob setting.
struct Config {
    std::string method;
    std::string knob = "default";
    double value = 0;
    tracers::MethodOptions opts;
    bool certified = false;
    MethodFactory factory;  ///< set for extra methods
    double tol_epsilon = 1e-6;
    bool is_default = true;  ///< the knob value is MethodOptions' default (stress table column)
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

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string num(double v) {
    std::string s;
    append_double(s, v);
    return s;
}

double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

void write_atomic(const fs::path& path, const std::string& text) {
    const fs::path tmp = path.string() + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.flush();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw std::runtime_error("cannot write " + tmp.string());
        }
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw std::runtime_error("cannot rename " + tmp.string() + " to " + path.string());
    }
}

/// `path` as given when it exists; else, for a relative path, the same path under the source tree
/// (so that `certray bench` finds scenes/, scripts/ and ../shared/models from any directory).
std::string resolve(const std::string& path) {
#ifdef CERTRAY_SOURCE_DIR
    if (!path.empty() && !fs::exists(path) && fs::path(path).is_relative()) {
        const fs::path alt = fs::path(CERTRAY_SOURCE_DIR) / path;
        if (fs::exists(alt)) return alt.string();
    }
#endif
    return path;
}

/// Runs f(i, first) for i in [0, n) on `threads` threads; `first` is true on each thread's first
/// call (its warm-up).
template <class F>
void parallel_for(unsigned threads, std::size_t n, F&& f) {
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        bool first = true;
        for (std::size_t i; (i = next.fetch_add(1)) < n; first = false) f(i, first);
    };
    const unsigned t = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(n)));
    std::vector<std::thread> pool;
    for (unsigned k = 1; k < t; ++k) pool.emplace_back(work);
    work();
    for (std::thread& th : pool) th.join();
}

/// The progress bar on stderr.
class Progress {
  public:
    Progress(bool on, std::size_t total) : on_(on), total_(std::max<std::size_t>(1, total)) {}
    void add(std::size_t n, const std::string& what) {
        done_ += n;
        if (!on_) return;
        const double f = std::min(1.0, static_cast<double>(done_) / static_cast<double>(total_));
        const int w = 30, k = static_cast<int>(f * w);
        std::fprintf(stderr, "\r[%s%s] %3.0f%% %-40.40s", std::string(k, '#').c_str(),
                     std::string(w - k, '.').c_str(), 100 * f, what.c_str());
        std::fflush(stderr);
    }
    void finish() {
        if (on_) std::fprintf(stderr, "\n");
    }

  private:
    bool on_;
    std::size_t total_, done_ = 0;
};

bool registry_certified(const std::string& name) {
    std::istringstream in(tracers::describe_methods());
    for (std::string line; std::getline(in, line);) {
        if (line.rfind(name + ":", 0) == 0) {
            return line.find("approximate") == std::string::npos &&
                   line.find("certified") != std::string::npos;
        }
    }
    return false;
}

/// The knob sweep of each method (docs/theory/bench.md).
std::vector<Config> make_configs(const BenchOptions& o, bool stress) {
    std::vector<std::string> names = o.methods;
    if (names.empty()) names = tracers::method_names();
    const std::vector<std::string> registered = tracers::method_names();
    const std::set<std::string> known(registered.begin(), registered.end());
    std::vector<Config> out;
    auto pick = [&](std::vector<double> v) {
        if (o.quick && v.size() > 2) return std::vector<double>{v.front(), v.back()};
        return v;
    };
    const tracers::MethodOptions def;
    for (const std::string& m : names) {
        if (!known.count(m)) {
            if (!stress) {
                std::fprintf(stderr, "bench: method '%s' is not registered; skipped\n", m.c_str());
            }
            continue;
        }
        if (m == "reference" && (!stress || o.quick)) continue;  // the truth itself; slow
        Config base;
        base.method = m;
        base.certified = registry_certified(m);
        auto sweep = [&](const std::string& knob, std::vector<double> values, auto set) {
            for (double v : pick(values)) {
                Config c = base;
                c.knob = knob;
                c.value = v;
                set(c.opts, v);
                c.is_default = false;
                out.push_back(c);
            }
        };
        if (m.rfind("certified", 0) == 0) {
            sweep("budget", {30, 100, 1000, 20000}, [](tracers::MethodOptions& p, double v) {
                p.budget = static_cast<std::uint64_t>(v);
            });
            if (m == "certified-octree" && !o.quick) {
                sweep("depth", {3, 7},
                      [](tracers::MethodOptions& p, double v) { p.depth = static_cast<int>(v); });
            }
        } else if (m == "approx" || m == "approx-plain") {
            sweep("depth", o.quick ? std::vector<double>{5} : std::vector<double>{3, 5, 7},
                  [](tracers::MethodOptions& p, double v) { p.depth = static_cast<int>(v); });
        } else if (m == "march") {
            sweep("step", {0.1, 0.03, 0.01, 0.003},
                  [](tracers::MethodOptions& p, double v) { p.step = v; });
        } else if (m == "sphere" || m == "enhanced" || m == "segment" || m == "octree" ||
                   m == "bvh") {
            sweep("epsilon", {1e-2, 1e-4, 1e-6, 1e-9},
                  [](tracers::MethodOptions& p, double v) { p.epsilon = v; });
            if (m == "octree" && !o.quick) {
                sweep("depth", {3, 7},
                      [](tracers::MethodOptions& p, double v) { p.depth = static_cast<int>(v); });
            }
            if (m == "enhanced") {
                sweep("kappa", o.quick ? std::vector<double>{0.5} : std::vector<double>{0.2, 0.5},
                      [](tracers::MethodOptions& p, double v) { p.kappa = v; });
            }
        } else if (m == "hermite") {
            sweep("samples", {8, 32, 128}, [](tracers::MethodOptions& p, double v) {
                p.samples = static_cast<unsigned>(v);
            });
        } else {
            out.push_back(base);
        }
    }
    for (Config& c : out) {
        c.is_default =
            c.knob == "default" ||
            (c.knob == "budget" && c.value == static_cast<double>(def.budget)) ||
            (c.knob == "epsilon" && c.value == def.epsilon) ||
            (c.knob == "step" && c.value == def.step) ||
            (c.knob == "depth" && c.value == def.depth && c.method.starts_with("approx"));
        if (c.knob == "samples" && c.value == 128) c.is_default = true;  // closest to 64
        c.tol_epsilon =
            c.method == "march" ? std::max(c.opts.epsilon, c.opts.step) : c.opts.epsilon;
    }
    for (const ExtraMethod& e : o.extra_methods) {
        Config c;
        c.method = e.name;
        c.certified = e.certified;
        c.factory = e.factory;
        c.opts.epsilon = e.epsilon;
        c.tol_epsilon = e.epsilon;
        out.push_back(c);
    }
    return out;
}

std::vector<std::string> split_csv(const std::string& line) {
    std::vector<std::string> f;
    std::string cur;
    for (char ch : line) {
        if (ch == ',') {
            f.push_back(cur);
            cur.clear();
        } else if (ch != '\r') {
            cur += ch;
        }
    }
    f.push_back(cur);
    return f;
}

/// The stress suite: one Scene per scene file of cases.csv, with the exact brackets as truth.
std::vector<Scene> load_stress(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path, 0, 0, "cannot open the stress cases");
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> head = split_csv(line);
    if (head.size() < 13 || head[0] != "case" || head[10] != "expect") {
        throw InputError(path, 1, 1, "expected the header case,scene,ox,...,expect,root_lo,...");
    }
    std::vector<Scene> scenes;
    std::map<std::string, std::size_t> index;
    const fs::path dir = fs::path(path).parent_path();
    for (int n = 2; std::getline(in, line); ++n) {
        if (line.empty() || line == "\r") continue;
        const std::vector<std::string> f = split_csv(line);
        if (f.size() < 13) throw InputError(path, n, 1, "expected at least 13 fields");
        double v[8];
        for (int k = 0; k < 8; ++k) {
            char* end = nullptr;
            v[k] = std::strtod(f[2 + k].c_str(), &end);
            if (end == f[2 + k].c_str()) throw InputError(path, n, 3 + k, "expected a number");
        }
        Truth t;
        const std::string& e = f[10];
        t.kind = e == "hit"       ? Truth::Hit
                 : e == "miss"    ? Truth::Miss
                 : e == "nohit"   ? Truth::NoHit
                 : e == "tangent" ? Truth::Tangent
                 : e == "hard"    ? Truth::Tangent
                                  : Truth::Unknown;
        if (t.kind == Truth::Unknown) throw InputError(path, n, 11, "unknown expect '" + e + "'");
        t.lo = std::strtod(f[11].c_str(), nullptr);
        t.hi = std::strtod(f[12].c_str(), nullptr);
        auto it = index.find(f[1]);
        if (it == index.end()) {
            const fs::path file = dir / f[1];
            Scene s{f[1], "stress", expr::Tape(expr::load_graph_file(file.string())), {}, {},
                    {},   {}};
            it = index.emplace(f[1], scenes.size()).first;
            scenes.push_back(std::move(s));
        }
        Scene& s = scenes[it->second];
        s.rays.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6], v[7]});
        s.truth.push_back(t);
        s.cases.push_back(f[0]);
    }
    return scenes;
}

/// The gallery: the 3D scenes (or the given ones) with the chosen rays.
std::vector<Scene> load_gallery(const BenchOptions& o) {
    std::vector<fs::path> files;
    if (!o.scenes.empty()) {
        for (const std::string& s : o.scenes) files.emplace_back(s);
    } else {
        if (!fs::is_directory(o.scenes_dir)) {
            throw InputError(o.scenes_dir, 0, 0, "the scene directory does not exist");
        }
        for (const auto& e : fs::directory_iterator(o.scenes_dir)) {
            const std::string ext = e.path().extension().string();
            if (ext == ".expr" || ext == ".vm") files.push_back(e.path());
        }
        std::sort(files.begin(), files.end());
        if (o.quick) {
            std::vector<fs::path> keep;
            for (const char* want : {"sphere.expr", "torus.expr", "clebsch_cubic.vm"}) {
                for (const fs::path& p : files) {
                    if (p.filename() == want) keep.push_back(p);
                }
            }
            if (!keep.empty()) files = keep;
        }
    }
    const std::string rays_path =
        o.rays.empty() ? (fs::path(o.scenes_dir) / "rays.csv").string() : o.rays;
    std::vector<Ray> all = read_rays_csv_file(rays_path);
    const std::size_t want = o.max_rays ? o.max_rays : (o.quick ? 32 : all.size());
    std::vector<Ray> rays;
    if (want >= all.size()) {
        rays = all;
    } else {  // evenly spaced, so that a prefix of a raster is not all one corner
        for (std::size_t k = 0; k < want; ++k) rays.push_back(all[k * all.size() / want]);
    }
    std::vector<Scene> out;
    for (const fs::path& p : files) {
        expr::Tape tape(expr::load_graph_file(p.string()));
        if (!tape.uses_var(2) && o.scenes.empty()) continue;  // 2D: images, not ray queries
        out.push_back({p.filename().string(), "gallery", std::move(tape), rays, {}, {}, {}});
    }
    return out;
}

/// Everything the study measured.
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

Truth truth_of(const RayResult& r) {
    if (r.status == Status::Hit) return {Truth::Hit, r.t_lo, r.t_hi};
    if (r.status == Status::Miss) return {Truth::Miss, 0, 0};
    return {};
}

void compute_references(Scene& s, unsigned threads, Progress& progress) {
    const std::size_t n = s.rays.size();
    s.truth.assign(n, Truth{});
    s.ref_us.assign(n, 0);
    parallel_for(threads, n, [&](std::size_t i, bool) {
        const auto t0 = Clock::now();
        const RayResult r = solvers::certified_first_root_reference(s.tape, s.rays[i]);
        s.ref_us[i] = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
        s.truth[i] = truth_of(r);
    });
    progress.add(n, "reference " + s.name);
}

/// Measures one config on one scene; false (with the reason) when the method does not apply.
bool measure(const Config& c, const Scene& s, const BenchOptions& o, unsigned threads,
             std::vector<Row>& rows, Summary& sum, std::string& why) {
    const auto t0 = Clock::now();
    tracers::RayFunction fn;
    try {
        fn = c.factory ? c.factory(s.tape, c.opts) : tracers::make_method(c.method, s.tape, c.opts);
    } catch (const std::invalid_argument& e) {
        why = e.what();
        return false;
    }
    sum = Summary{&c, &s};
    sum.setup_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const std::size_t n = s.rays.size();
    std::vector<RayResult> res(n);
    std::vector<double> us(n, std::numeric_limits<double>::infinity());
    const bool warm = c.method != "reference";
    const unsigned repeats = std::max(1u, o.repeats);
    parallel_for(threads, n, [&](std::size_t i, bool first) {
        if (first && warm) res[i] = fn(s.rays[i]);  // allocates this thread's scratch
        for (unsigned r = 0; r < repeats; ++r) {
            const auto a = Clock::now();
            res[i] = fn(s.rays[i]);
            const auto b = Clock::now();
            us[i] = std::min(us[i], std::chrono::duration<double, std::micro>(b - a).count());
        }
    });
    std::vector<double> errors;
    sum.rays = n;
    for (std::size_t i = 0; i < n; ++i) {
        const Truth& t = s.truth[i];
        const double t_star = 0.5 * (t.lo + t.hi);
        const double tol = bench_tolerance(c.tol_epsilon, std::isfinite(t_star) ? t_star : 0.0);
        Row row{&c,
                &s,
                i,
                res[i],
                us[i],
                classify(res[i], t, c.certified, tol),
                bench_error(res[i], t)};
        if (t.kind == Truth::Unknown) {
            ++sum.ref_unknown;
        } else {
            ++sum.counts[static_cast<int>(row.cls)];
        }
        if (!std::isnan(row.error)) errors.push_back(row.error);
        sum.mean_us += us[i];
        sum.ev_value += static_cast<double>(res[i].evals.value);
        sum.ev_interval += static_cast<double>(res[i].evals.interval);
        sum.ev_gradient += static_cast<double>(res[i].evals.gradient);
        rows.push_back(row);
    }
    const double dn = static_cast<double>(std::max<std::size_t>(1, n));
    sum.median_us = median(us);
    sum.mean_us /= dn;
    sum.ev_value /= dn;
    sum.ev_interval /= dn;
    sum.ev_gradient /= dn;
    sum.ev_total = sum.ev_value + sum.ev_interval + sum.ev_gradient;
    if (!errors.empty()) {
        sum.max_error = *std::max_element(errors.begin(), errors.end());
        sum.median_error = median(errors);
    }
    return true;
}

void run_suite(const std::vector<Config>& configs, const std::vector<Scene>& scenes,
               const BenchOptions& o, unsigned threads, Study& st, Progress& progress) {
    for (const Config& c : configs) {
        for (const Scene& s : scenes) {
            Summary sum;
            std::string why;
            if (measure(c, s, o, threads, st.rows, sum, why)) {
                st.summaries.push_back(sum);
            } else {
                auto& [where, reason] = st.skipped[c.method];
                if (std::find(where.begin(), where.end(), s.name) == where.end()) {
                    where.push_back(s.name);
                }
                if (reason.empty()) reason = why.substr(0, why.find(';'));
            }
            progress.add(s.rays.size(), c.label() + " " + s.name);
        }
    }
}

// ---- peers ------------------------------------------------------------------------------------

void peer_prospero(const BenchOptions& o, Study& st) {
    fs::path p = fs::path(o.scenes_dir) / "prospero.vm";
    if (!fs::exists(p)) p = fs::path(o.models_dir) / "prospero.vm";
    std::string& md = st.peer_md;
    md += "### Prospero 1024×1024 (2D quadtree, tracers/image2d.h)\n\n";
    if (!fs::exists(p)) {
        md +=
            "TODO (lead): prospero.vm not found (looked in the scenes and models directories).\n\n";
        return;
    }
    const expr::Tape tape(expr::load_graph_file(p.string()));
    md +=
        "| threads | best of 3 (ms) | pixels with f < 0 | expected |\n| --- | --- | --- | --- |\n";
    for (unsigned th : {1u, 2u}) {
        tracers::Image2dOptions io;
        io.threads = th;
        double best = std::numeric_limits<double>::infinity();
        std::uint64_t inside = 0;
        for (int r = 0; r < 3; ++r) {
            const tracers::Image2d img = tracers::render_2d(tape, io);
            best = std::min(best, img.seconds * 1e3);
            inside = img.inside;
        }
        md += "| " + std::to_string(th) + " | " + fmt("%.1f", best) + " | " +
              std::to_string(inside) + " | 132816" + (inside == 132816 ? " ✓" : " **✗**") + " |\n";
        st.peers.push_back({"prospero", "ms_threads_" + std::to_string(th), fmt("%.3f", best),
                            "best of 3, 1024x1024, pixel centres"});
        st.peers.push_back({"prospero", "inside_threads_" + std::to_string(th),
                            std::to_string(inside), "expected 132816"});
    }
    md +=
        "\nPublished (other machines, for orientation; ../shared/models/README.md): Fidget "
        "4.6–10.8 ms (JIT/VM, several cores), libfive about 80–100 ms on 2 cores, a brute-force "
        "scalar interpreter about 23 s on 2 cores, the fastest published CPU renderer 0.28 ms on "
        "4 cores of an M1.\n\n";
}

void peer_segment(const BenchOptions& o, Study& st) {
    std::string& md = st.peer_md;
    md += "### Segment tracing on particles.txt (Galin et al. 2020)\n\n";
    const fs::path p = fs::path(o.models_dir) / "segment-tracing" / "particles.txt";
    std::unique_ptr<expr::Tape> tape;
    try {
        tape = std::make_unique<expr::Tape>(expr::load_graph_file(p.string()));
    } catch (const std::exception& e) {
        md += p.string() + " cannot be loaded (" + e.what() +
              "): the segment-tracing peer is skipped. Published: the authors' segment tracing "
              "about 5.4 evaluations per ray, sphere tracing with the global Lipschitz constant "
              "about 26,000.\n\n";
        st.notes.push_back("segment-tracing peer: particles.txt not loadable");
        return;
    }
    tracers::Camera cam;
    cam.eye = {0, -80, 0};
    cam.target = {0, 0, 0};
    cam.up = {0, 0, 1};
    cam.fov_degrees = 35;
    const unsigned side = 100;
    const tracers::CameraFrame frame(cam, side, side);
    md +=
        "Camera (0, −80, 0) looking at the origin, fov 35°, 100×100 rays (sphere tracing: "
        "every 10th row and column, 10×10 rays, budget 20,000).\n\n"
        "| method | rays | evaluations per ray | hits | µs per ray | published |\n"
        "| --- | --- | --- | --- | --- | --- |\n";
    const std::vector<std::string> registered = tracers::method_names();
    const std::set<std::string> known(registered.begin(), registered.end());
    for (const char* m : {"segment", "sphere", "certified"}) {
        if (!known.count(m)) {
            md += std::string("| ") + m + " | — | not registered | | | |\n";
            continue;
        }
        const unsigned stride = std::string(m) == "segment" ? 1 : 10;
        std::vector<Ray> rays;
        for (unsigned j = 0; j < side; j += stride) {
            for (unsigned i = 0; i < side; i += stride) {
                Ray r = frame.ray(i + 0.5, j + 0.5);
                r.tmax = 200;
                rays.push_back(r);
            }
        }
        tracers::RayFunction fn;
        try {
            fn = tracers::make_method(m, *tape, tracers::MethodOptions{});
        } catch (const std::invalid_argument& e) {
            md += std::string("| ") + m + " | — | does not apply | | | |\n";
            continue;
        }
        std::vector<RayResult> res(rays.size());
        const auto t0 = Clock::now();
        const unsigned nt =
            std::max(1u, o.threads ? o.threads : std::thread::hardware_concurrency());
        parallel_for(nt, rays.size(), [&](std::size_t i, bool) { res[i] = fn(rays[i]); });
        const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
        double ev = 0;
        std::size_t hits = 0;
        for (const RayResult& r : res) {
            ev += static_cast<double>(r.evals.total());
            hits += r.status == Status::Hit;
        }
        ev /= static_cast<double>(rays.size());
        const std::string pub = std::string(m) == "segment"  ? "5.4"
                                : std::string(m) == "sphere" ? "26,000"
                                                             : "—";
        md += std::string("| ") + m + " | " + std::to_string(rays.size()) + " | " +
              fmt("%.1f", ev) + " | " + std::to_string(hits) + " | " +
              fmt("%.1f", secs * 1e6 * nt / static_cast<double>(rays.size())) + " | " + pub +
              " |\n";
        st.peers.push_back({"segment-tracing", std::string(m) + "_evals_per_ray", fmt("%.2f", ev),
                            "particles.txt, camera (0,-80,0)"});
    }
    md += "\n(µs per ray: wall time × threads / rays.)\n\n";
}

void peer_enhanced(Study& st) {
    std::string& md = st.peer_md;
    md += "### Enhanced against plain sphere tracing (gallery, ε = 1e-6)\n\n";
    std::map<std::string, std::array<double, 3>> per;  // scene → sphere, enhanced κ .2, κ .5
    for (const Summary& s : st.summaries) {
        if (s.scene->suite != "gallery") continue;
        const Config& c = *s.config;
        if (c.method == "sphere" && c.knob == "epsilon" && c.value == 1e-6) {
            per[s.scene->name][0] = s.ev_total;
        }
        if (c.method == "enhanced" && c.knob == "kappa") {
            per[s.scene->name][c.value == 0.5 ? 2 : 1] = s.ev_total;
        }
    }
    if (per.empty()) {
        md += "Not measured: `sphere` or `enhanced` is not registered (or not selected).\n\n";
        return;
    }
    md +=
        "| scene | sphere evals/ray | enhanced κ=0.2 | reduction | enhanced κ=0.5 | reduction |\n"
        "| --- | --- | --- | --- | --- | --- |\n";
    for (const auto& [scene, v] : per) {
        auto red = [&](double e) {
            return v[0] > 0 && e > 0 ? fmt("%.0f%%", 100 * (1 - e / v[0])) : std::string("—");
        };
        md += "| " + scene + " | " + fmt("%.1f", v[0]) + " | " + fmt("%.1f", v[1]) + " | " +
              red(v[1]) + " | " + fmt("%.1f", v[2]) + " | " + red(v[2]) + " |\n";
        st.peers.push_back({"enhanced-vs-sphere", scene + "_reduction_kappa_0.5",
                            v[0] > 0 ? fmt("%.4f", 1 - v[2] / v[0]) : "nan", "evals per ray"});
    }
    md +=
        "\nReduction = 1 − (enhanced evaluations per ray) / (sphere evaluations per ray); "
        "Keinert et al. 2014 report about 30% fewer steps with over-relaxation.\n\n";
}

/// Tape length per octree level over the cells that may hold the surface (hierarchical: each
/// cell's tape is pruned from its parent's pruned tape).
void peer_pruning(const std::vector<const Scene*>& scenes, const std::vector<expr::Tape>& extra2d,
                  const std::vector<std::string>& extra_names, Study& st) {
    std::string& md = st.peer_md;
    md +=
        "### Tape pruning: leave out what a region does not need\n\n"
        "For each level L (2^L cells per axis over [-2, 2]³; 2D scenes over [-1, 1]²), the cells "
        "whose interval value may be zero or undefined (the cells that may hold the surface), "
        "each with the tape pruned to it (expr/prune.h, from its parent's pruned tape): their "
        "count, and the mean and shortest tape length, against the full tape.\n\n"
        "| scene | full | L0 | L1 | L2 | L3 | L4 | L5 |\n| --- | --- | --- | --- | --- | --- "
        "| --- | --- |\n";
    st.pruning.push_back("scene,level,cells,full_length,mean_length,min_length");
    auto one = [&](const std::string& name, const expr::Tape& tape) {
        const bool is3d = tape.uses_var(2);
        const double lo = is3d ? -2 : -1, hi = is3d ? 2 : 1;
        struct Cell {
            std::array<Interval, 3> box;
            expr::Tape tape;
        };
        std::vector<Cell> level{
            {{Interval(lo, hi), Interval(lo, hi), is3d ? Interval(lo, hi) : Interval(0.0)}, tape}};
        std::string line = "| " + name + " | " + std::to_string(tape.size());
        for (int L = 0; L <= 5; ++L) {
            std::vector<Cell> keep;
            double sum = 0;
            std::size_t mn = std::numeric_limits<std::size_t>::max();
            for (Cell& c : level) {
                expr::PruneResult p = expr::prune(c.tape, c.box);
                const bool maybe = !p.value.defined || p.value.is_empty() ||
                                   (p.value.lower() <= 0 && p.value.upper() >= 0);
                if (!maybe) continue;
                sum += static_cast<double>(p.after);
                mn = std::min(mn, p.after);
                keep.push_back({c.box, std::move(p.tape)});
            }
            const std::size_t n = keep.size();
            st.pruning.push_back(name + "," + std::to_string(L) + "," + std::to_string(n) + "," +
                                 std::to_string(tape.size()) + "," +
                                 (n ? fmt("%.2f", sum / static_cast<double>(n)) : "nan") + "," +
                                 (n ? std::to_string(mn) : "nan"));
            line += n ? " | " + std::to_string(n) + ": " + fmt("%.0f", sum / n) + " (" +
                            std::to_string(mn) + ")"
                      : " | 0";
            if (L == 5 || n == 0 || n > 20000) {
                for (int k = L + 1; k <= 5; ++k) line += " | —";
                break;
            }
            level.clear();
            for (const Cell& c : keep) {  // split in 8 (3D) or 4 (2D)
                for (int m = 0; m < (is3d ? 8 : 4); ++m) {
                    Cell ch{c.box, c.tape};
                    for (int a = 0; a < (is3d ? 3 : 2); ++a) {
                        const double l = c.box[a].lower(), u = c.box[a].upper();
                        const double mid = 0.5 * (l + u);
                        ch.box[a] = (m >> a) & 1 ? Interval(mid, u) : Interval(l, mid);
                    }
                    level.push_back(std::move(ch));
                }
            }
        }
        md += line + " |\n";
    };
    for (const Scene* s : scenes) one(s->name, s->tape);
    for (std::size_t k = 0; k < extra2d.size(); ++k) one(extra_names[k], extra2d[k]);
    md +=
        "\nCell entries: `count: mean (shortest)` tape length; — where the subdivision stopped "
        "(more than 20,000 cells).\n\n";
}

// ---- outputs ----------------------------------------------------------------------------------

std::string measurements_csv(const Study& st) {
    std::string s =
        "suite,method,knob,value,certified,scene,ray,case,expect,status,t_lo,t_hi,t,truth_lo,"
        "truth_hi,us,evals_value,evals_interval,evals_gradient,evals_total,class,error,"
        "rel_error\n";
    for (const Row& r : st.rows) {
        const Config& c = *r.config;
        const Truth& t = r.scene->truth[r.ray];
        const bool has_root = t.kind == Truth::Hit || t.kind == Truth::Tangent;
        const double t_star = 0.5 * (t.lo + t.hi);
        const double rel = std::isnan(r.error) ? r.error
                           : t_star != 0       ? r.error / std::fabs(t_star)
                                               : r.error;
        s += r.scene->suite + "," + c.method + "," + c.knob + "," + num(c.value) + "," +
             (c.certified ? "1" : "0") + "," + r.scene->name + "," + std::to_string(r.ray) + "," +
             (r.scene->cases.empty() ? "" : r.scene->cases[r.ray]) + "," + kTruthNames[t.kind] +
             "," + std::string(name(r.result.status)) + "," + num(r.result.t_lo) + "," +
             num(r.result.t_hi) + "," + num(r.result.t) + "," + (has_root ? num(t.lo) : "nan") +
             "," + (has_root ? num(t.hi) : "nan") + "," + fmt("%.3f", r.us) + "," +
             std::to_string(r.result.evals.value) + "," + std::to_string(r.result.evals.interval) +
             "," + std::to_string(r.result.evals.gradient) + "," +
             std::to_string(r.result.evals.total()) + "," + kClassNames[static_cast<int>(r.cls)] +
             "," + num(r.error) + "," + num(rel) + "\n";
    }
    return s;
}

std::string summary_csv(const Study& st) {
    std::string s =
        "suite,method,knob,value,certified,scene,rays,setup_ms,mean_us,median_us,evals_value,"
        "evals_interval,evals_gradient,evals_total,correct,missed,false_hit,overshoot,unknown,"
        "ref_unknown,max_error,median_error\n";
    for (const Summary& m : st.summaries) {
        const Config& c = *m.config;
        s += m.scene->suite + "," + c.method + "," + c.knob + "," + num(c.value) + "," +
             (c.certified ? "1" : "0") + "," + m.scene->name + "," + std::to_string(m.rays) + "," +
             fmt("%.3f", m.setup_ms) + "," + fmt("%.3f", m.mean_us) + "," +
             fmt("%.3f", m.median_us) + "," + fmt("%.2f", m.ev_value) + "," +
             fmt("%.2f", m.ev_interval) + "," + fmt("%.2f", m.ev_gradient) + "," +
             fmt("%.2f", m.ev_total);
        for (std::size_t k : m.counts) {
            s += ',';
            s += std::to_string(k);
        }
        s += "," + std::to_string(m.ref_unknown) + "," + num(m.max_error) + "," +
             num(m.median_error) + "\n";
    }
    return s;
}

/// A config's totals over the gallery scenes it ran on.
struct Aggregate {
    const Config* config = nullptr;
    std::size_t scenes = 0, rays = 0;
    double us = 0, evals = 0;
    std::array<std::size_t, 5> counts{};
    double max_error = 0;
    std::size_t wrong() const { return counts[1] + counts[2] + counts[3]; }
    double mean_us() const { return rays ? us / static_cast<double>(rays) : 0; }
};

/// The CPU model from /proc/cpuinfo ("unknown CPU" elsewhere).
std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) return line.substr(colon + 2);
        }
    }
    return "unknown CPU";
}

std::string cell_error(double e) { return std::isnan(e) ? "—" : fmt("%.2g", e); }

std::string make_report(const BenchOptions& o, const Study& st, unsigned threads,
                        std::size_t& certified_wrong) {
    std::string md;
    const std::time_t now = std::time(nullptr);
    char date[64];
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    md += "# certray: error against run time\n\n";
    md += std::string("Generated by `certray bench") + (o.quick ? " --quick" : "") +
          (o.report.empty() ? "" : " --report " + o.report) + "` on " + date + ", " + cpu_model() +
          " (" + std::to_string(threads) + " worker threads, each ray timed alone on its thread; " +
          std::to_string(std::max(1u, o.repeats)) +
          " timing(s) per ray, the fastest kept). What is measured and how answers are classified: "
          "docs/theory/bench.md. Data: measurements.csv, summary.csv, peers.csv, pruning.csv and "
          "the plots (*.png) in the output directory `" +
          o.out_dir + "`.\n\n";

    // Soundness of the certified methods.
    std::map<std::string, std::array<std::size_t, 2>> cert;  // method → rays judged, wrong
    for (const Summary& m : st.summaries) {
        if (!m.config->certified) continue;
        auto& v = cert[m.config->method];
        v[0] += m.rays - m.ref_unknown;
        v[1] += m.wrong();
    }
    md += "## Certified methods: wrong answers\n\n";
    certified_wrong = 0;
    for (const auto& [name, v] : cert) {
        certified_wrong += v[1];
        if (v[1] == 0) {
            md += "- `" + name + "`: **zero wrong answers** in " + std::to_string(v[0]) +
                  " judged rays (gallery and stress suite, every budget).\n";
        } else {
            md +=
                "- ⚠️ **`" + name + "`: " + std::to_string(v[1]) + " WRONG ANSWERS in " +
                std::to_string(v[0]) +
                " judged rays. A certified method must never be wrong: this is a soundness "
                "bug; see the rows with class missed/false_hit/overshoot in measurements.csv.**\n";
        }
    }
    if (cert.empty()) md += "No certified method was run.\n";
    md += "\n";

    // Winners per gallery scene.
    std::map<std::string, std::vector<const Summary*>> by_scene;
    for (const Summary& m : st.summaries) {
        if (m.scene->suite == "gallery") by_scene[m.scene->name].push_back(&m);
    }
    if (!by_scene.empty()) {
        md += "## Which method wins where (gallery, " +
              std::to_string(st.gallery.front().rays.size()) + " rays per scene)\n\n";
        md +=
            "Winner: among the settings with zero wrong answers and the fewest unknowns, the "
            "fastest (mean µs per ray); (approx.) marks an approximate method, right on these rays "
            "but "
            "not proven. Rays whose reference is unknown are left out.\n\n"
            "| scene | winner | µs/ray | unknowns | fastest certified | µs/ray | fastest overall "
            "| µs/ray | its wrong answers |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- "
            "|\n";
        for (const auto& [scene, v] : by_scene) {
            const Summary* win = nullptr;
            const Summary* cert_best = nullptr;
            const Summary* fast = nullptr;
            for (const Summary* m : v) {
                if (!fast || m->mean_us < fast->mean_us) fast = m;
                if (m->wrong() == 0) {
                    if (!win || m->counts[4] < win->counts[4] ||
                        (m->counts[4] == win->counts[4] && m->mean_us < win->mean_us)) {
                        win = m;
                    }
                }
                if (m->config->certified && m->counts[4] == 0 &&
                    (!cert_best || m->mean_us < cert_best->mean_us)) {
                    cert_best = m;
                }
            }
            auto lab = [](const Summary* m) {
                if (!m) return std::string("—");
                return "`" + m->config->label() + "`" + (m->config->certified ? "" : " (approx.)");
            };
            auto us = [](const Summary* m) { return m ? fmt("%.1f", m->mean_us) : "—"; };
            md += "| " + scene + " | " + lab(win) + " | " + us(win) + " | " +
                  (win ? std::to_string(win->counts[4]) : "—") + " | " + lab(cert_best) + " | " +
                  us(cert_best) + " | " + lab(fast) + " | " + us(fast) + " | " +
                  (fast ? std::to_string(fast->wrong()) : "—") + " |\n";
        }
        md += "\n(Fastest certified: the fastest certified setting with no unknown answer.)\n\n";
    }

    // Aggregates and the Pareto front.
    std::vector<Aggregate> agg;
    std::map<const Config*, std::size_t> at;
    for (const Summary& m : st.summaries) {
        if (m.scene->suite != "gallery") continue;
        auto it = at.find(m.config);
        if (it == at.end()) {
            it = at.emplace(m.config, agg.size()).first;
            agg.push_back({m.config});
        }
        Aggregate& a = agg[it->second];
        ++a.scenes;
        a.rays += m.rays;
        a.us += m.mean_us * static_cast<double>(m.rays);
        a.evals += m.ev_total * static_cast<double>(m.rays);
        for (int k = 0; k < 5; ++k) a.counts[k] += m.counts[k];
        if (!std::isnan(m.max_error)) a.max_error = std::max(a.max_error, m.max_error);
    }
    if (!agg.empty()) {
        auto dominated = [&](const Aggregate& a) {
            for (const Aggregate& b : agg) {
                if (b.scenes != a.scenes) continue;
                const bool le = b.mean_us() <= a.mean_us() && b.wrong() <= a.wrong() &&
                                b.counts[4] <= a.counts[4] && b.max_error <= a.max_error;
                const bool lt = b.mean_us() < a.mean_us() || b.wrong() < a.wrong() ||
                                b.counts[4] < a.counts[4] || b.max_error < a.max_error;
                if (le && lt) return true;
            }
            return false;
        };
        md +=
            "## All settings over the gallery, and the Pareto front\n\n"
            "Pareto-optimal (★): no other setting run on as many scenes is at least as good in "
            "all of mean µs per ray, wrong answers, unknowns and max |t − t*|, and better in "
            "one.\n\n"
            "| method | knob | scenes | µs/ray | evals/ray | correct | missed | false hit | "
            "overshoot | unknown | max \\|t − t*\\| | Pareto |\n"
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
        for (const Aggregate& a : agg) {
            const Config& c = *a.config;
            md += "| " + c.method + (c.certified ? " (certified)" : "") + " | " +
                  (c.knob == "default" ? "—" : c.knob + " = " + fmt("%g", c.value)) + " | " +
                  std::to_string(a.scenes) + " | " + fmt("%.1f", a.mean_us()) + " | " +
                  fmt("%.1f", a.evals / static_cast<double>(std::max<std::size_t>(1, a.rays)));
            for (std::size_t k : a.counts) {
                md += " | ";
                md += std::to_string(k);
            }
            md += " | " + cell_error(a.max_error) + " | " + (dominated(a) ? "" : "★") + " |\n";
        }
        md += "\n";
    }

    // The stress table.
    if (!st.stress.empty()) {
        std::vector<const Config*> cols;
        for (const Config& c : st.stress_configs) {
            if (c.is_default) cols.push_back(&c);
        }
        md +=
            "## The stiff-and-extreme suite (scenes/stress)\n\n"
            "Each method at its default setting (certified budget 20,000; ε = 1e-6; march step "
            "0.01; hermite 128 samples). Cell: class, |t − t*| when both hit, µs. Classes: ok "
            "correct, MISS missed hit, FALSE false hit, OVER overshoot (a later root, or an "
            "unknown past the root), unk unknown (the right answer of a certified method on "
            "tangent and hard cases). Truth: the exact brackets of cases.csv.\n\n| case | "
            "expect";
        for (const Config* c : cols) md += " | " + c->method;
        md += " |\n| --- | ---";
        for (std::size_t k = 0; k < cols.size(); ++k) md += " | ---";
        md += " |\n";
        std::map<std::pair<const Config*, std::string>, const Row*> cell;
        for (const Row& r : st.rows) {
            if (r.scene->suite == "stress") cell[{r.config, r.scene->cases[r.ray]}] = &r;
        }
        static const char* kShort[] = {"ok", "MISS", "FALSE", "OVER", "unk"};
        for (const Scene& s : st.stress) {
            for (std::size_t i = 0; i < s.rays.size(); ++i) {
                md += "| " + s.cases[i] + " | " + kTruthNames[s.truth[i].kind];
                for (const Config* c : cols) {
                    auto it = cell.find({c, s.cases[i]});
                    if (it == cell.end()) {
                        md += " | n/a";
                        continue;
                    }
                    const Row& r = *it->second;
                    const int k = static_cast<int>(r.cls);
                    const char* bold = k >= 1 && k <= 3 ? "**" : "";
                    md += " | ";
                    md += bold;
                    md += kShort[k];
                    md += bold;
                    if (!std::isnan(r.error) && r.error != 0) {
                        md += ' ';
                        md += cell_error(r.error);
                    }
                    md += ' ';
                    md += fmt("%.3g", r.us);
                    md += "µs";
                }
                md += " |\n";
            }
        }
        md +=
            "\nStress totals over every setting of each method:\n\n| method | correct | missed "
            "| false hit | overshoot | unknown |\n| --- | --- | --- | --- | --- | --- |\n";
        std::map<std::string, std::array<std::size_t, 5>> tot;
        for (const Summary& m : st.summaries) {
            if (m.scene->suite != "stress") continue;
            auto& t = tot[m.config->method];
            for (int k = 0; k < 5; ++k) t[k] += m.counts[k];
        }
        for (const auto& [name, t] : tot) {
            md += "| " + name;
            for (std::size_t k : t) {
                md += " | ";
                md += std::to_string(k);
            }
            md += " |\n";
        }
        md += "\n";
    }

    if (!st.peer_md.empty()) md += "## Peers, side by side\n\n" + st.peer_md;
    md += "## Plots\n\n";
    for (const char* f : {"pareto.png", "evals_per_ray.png"}) {
        md += std::string("- [") + f + "](" + f + ")\n";
    }
    md +=
        "- error_time_SCENE.png: error against time per scene (log–log, one curve per method "
        "over its knob sweep)\n\n(Paths relative to the output directory; not committed.)\n\n";
    if (!st.notes.empty() || !st.skipped.empty()) {
        md += "## Notes\n\n";
        for (const auto& [method, v] : st.skipped) {
            md += "- `" + method + "` does not apply to " + std::to_string(v.first.size()) +
                  " scene(s) (skipped there): ";
            for (std::size_t k = 0; k < v.first.size(); ++k) {
                md += (k ? ", " : "") + v.first[k];
            }
            md += ". First reason: " + v.second + "\n";
        }
        for (const std::string& n : st.notes) md += "- " + n + "\n";
        md += "\n";
    }
    return md;
}

}  // namespace

int run_bench(const BenchOptions& options) {
    BenchOptions o = options;
    o.scenes_dir = resolve(o.scenes_dir);
    o.models_dir = resolve(o.models_dir);
    o.plot_script = resolve(o.plot_script);
    if (o.repeats == 0) throw std::invalid_argument("--repeats must be at least 1");
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    const unsigned threads = o.threads ? o.threads : hw;
    Study st;
    st.gallery = load_gallery(o);
    std::string stress_path = o.stress;
    if (stress_path.empty()) {
        stress_path = (fs::path(o.scenes_dir) / "stress" / "cases.csv").string();
        if (!fs::exists(stress_path)) {
            st.notes.push_back("stress suite not found at " + stress_path + "; skipped");
            stress_path = "none";
        }
    }
    if (stress_path != "none") st.stress = load_stress(stress_path);
    if (o.quick) {  // the 10^4-primitive CSG takes seconds per octree: not in the CI run
        std::erase_if(st.stress, [&](const Scene& s) {
            if (s.tape.size() <= 10000) return false;
            st.notes.push_back("--quick: stress scene " + s.name + " (tape length " +
                               std::to_string(s.tape.size()) + ") left out");
            return true;
        });
    }
    st.gallery_configs = make_configs(o, false);
    st.stress_configs = make_configs(o, true);
    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    if (!fs::is_directory(o.out_dir)) {
        throw std::runtime_error("cannot create the output directory " + o.out_dir);
    }

    std::size_t total = 0;
    for (const Scene& s : st.gallery) total += s.rays.size() * (1 + st.gallery_configs.size());
    for (const Scene& s : st.stress) total += s.rays.size() * st.stress_configs.size();
    const bool bar = o.progress < 0 ? isatty(2) != 0 : o.progress > 0;
    Progress progress(bar, total);
    for (Scene& s : st.gallery) compute_references(s, threads, progress);
    run_suite(st.gallery_configs, st.gallery, o, threads, st, progress);
    run_suite(st.stress_configs, st.stress, o, threads, st, progress);
    progress.finish();

    if (o.peers && !o.quick) {
        std::fprintf(stderr, "bench: peers (prospero, segment tracing, pruning)\n");
        peer_prospero(o, st);
        peer_segment(o, st);
        peer_enhanced(st);
        std::vector<const Scene*> ps;
        for (const Scene& s : st.gallery) ps.push_back(&s);
        std::vector<expr::Tape> extra;
        std::vector<std::string> names;
        const fs::path pro = fs::path(o.scenes_dir) / "prospero.vm";
        if (fs::exists(pro)) {
            extra.emplace_back(expr::load_graph_file(pro.string()));
            names.push_back("prospero.vm");
        }
        peer_pruning(ps, extra, names, st);
    }

    const fs::path out = o.out_dir;
    write_atomic(out / "measurements.csv", measurements_csv(st));
    write_atomic(out / "summary.csv", summary_csv(st));
    std::string peers = "peer,item,value,note\n";
    for (const auto& p : st.peers) peers += p[0] + "," + p[1] + "," + p[2] + "," + p[3] + "\n";
    write_atomic(out / "peers.csv", peers);
    std::string pruning;
    for (const std::string& l : st.pruning) pruning += l + "\n";
    write_atomic(out / "pruning.csv", pruning.empty() ? "scene,level,cells,full_length,"
                                                        "mean_length,min_length\n"
                                                      : pruning);

    if (o.plots) {
        if (!fs::exists(o.plot_script)) {
            st.notes.push_back("plots skipped: " + o.plot_script + " not found");
        } else {
            const std::string cmd = "python3 '" + o.plot_script + "' '" + o.out_dir + "'";
            const int rc = std::system(cmd.c_str());
            if (rc != 0) {
                st.notes.push_back("plots skipped: `" + cmd +
                                   "` failed (python3 or python3-matplotlib missing?)");
                std::fprintf(stderr, "bench: plots skipped (python3/matplotlib missing?)\n");
            }
        }
    } else {
        st.notes.push_back("plots not requested (--no-plots)");
    }

    std::size_t certified_wrong = 0;
    const std::string md = make_report(o, st, threads, certified_wrong);
    write_atomic(out / "report.md", md);
    if (!o.report.empty()) write_atomic(o.report, md);
    std::fprintf(stderr, "bench: %zu measurements in %s\n", st.rows.size(), o.out_dir.c_str());
    if (certified_wrong) {
        std::fprintf(stderr, "bench: WARNING: certified methods gave %zu WRONG ANSWERS\n",
                     certified_wrong);
        return 3;
    }
    return 0;
}

}  // namespace certray::apps
