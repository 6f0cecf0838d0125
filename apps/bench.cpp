// apps/bench.cpp — the error-against-run-time study (`certray bench`): measurement,
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

#include "apps/bench_study.h"
#include "expr/input_error.h"
#include "expr/load.h"
#include "expr/prune.h"
#include "solvers/certified.h"
#include "solvers/exact.h"
#include "solvers/ray_io.h"
#include "tracers/camera.h"
#include "tracers/image2d.h"

namespace certray::apps {

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

namespace study {

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

std::string resolve(const std::string& path) {
#ifdef CERTRAY_SOURCE_DIR
    if (!path.empty() && !fs::exists(path) && fs::path(path).is_relative()) {
        const fs::path alt = fs::path(CERTRAY_SOURCE_DIR) / path;
        if (fs::exists(alt)) return alt.string();
    }
#endif
    return path;
}

}  // namespace study

using namespace study;  // NOLINT(google-build-using-namespace): the study's own parts

namespace {

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
        const tracers::MethodInfo& info = tracers::method_info(m);
        Config base;
        base.method = m;
        base.certified = info.certified;
        if (info.sweep.empty()) out.push_back(base);
        // Each knob of the registry's sweep (quick: the first knob only, at both ends).
        for (std::size_t k = 0; k < info.sweep.size() && !(o.quick && k > 0); ++k) {
            const tracers::Sweep& sw = info.sweep[k];
            const tracers::Knob* knob = nullptr;
            for (const tracers::Knob& kn : tracers::knobs()) {
                if (kn.name == sw.knob) knob = &kn;
            }
            // The default run is the value run nearest the knob's default (--quick runs only the
            // sweep's ends, which need not include the default itself).
            const double d = knob->get(def);
            const std::vector<double> run = pick(sw.values);
            double nearest = run.front();
            for (double v : run) {
                if (std::abs(std::log(v / d)) <= std::abs(std::log(nearest / d))) nearest = v;
            }
            for (double v : run) {
                Config c = base;
                c.knob = std::string(sw.knob);
                c.value = v;
                knob->set(c.opts, v);
                c.is_default = v == nearest && k == 0;
                out.push_back(c);
            }
        }
    }
    for (Config& c : out) {
        if (c.knob == "default") c.is_default = true;
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
            Scene s{f[1], "stress", expr::Tape(expr::load_graph_file(file.string())), {}, {}, {},
                    {},   {}};
            it = index.emplace(f[1], scenes.size()).first;
            scenes.push_back(std::move(s));
        }
        Scene& s = scenes[it->second];
        s.rays.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6], v[7]});
        s.truth.push_back(t);
        s.cases.push_back(f[0]);
        ++s.judged_by["mpmath brackets (scenes/stress/make_stress.py)"];
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
        out.push_back({p.filename().string(), "gallery", std::move(tape), rays, {}, {}, {}, {}});
    }
    return out;
}

/// Everything the study measured.
Truth truth_of(const RayResult& r) {
    if (r.status == Status::Hit) return {Truth::Hit, r.t_lo, r.t_hi};
    if (r.status == Status::Miss) return {Truth::Miss, 0, 0};
    return {};
}

void compute_references(Scene& s, unsigned threads, Progress& progress) {
    const std::size_t n = s.rays.size();
    s.truth.assign(n, Truth{});
    s.ref_us.assign(n, 0);
    // The judge shares no code with the certified solver where it can: on polynomial scenes the
    // exact rational oracle (solvers/exact.h: Sturm sequences on g's rational coefficients); else
    // (or when the oracle gives up) the MPFR reference, which is the certified solver's logic run
    // in 256-bit MPFR intervals.
    const bool polynomial = solvers::is_polynomial(s.tape);
    std::vector<char> exact(n, 0);
    parallel_for(threads, n, [&](std::size_t i, bool) {
        const auto t0 = Clock::now();
        RayResult r;
        if (polynomial) {
            r = solvers::exact_first_root(s.tape, s.rays[i]);
            exact[i] = r.status != Status::Unknown;
        }
        if (!exact[i]) r = solvers::certified_first_root_reference(s.tape, s.rays[i]);
        s.ref_us[i] = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
        s.truth[i] = truth_of(r);
    });
    for (std::size_t i = 0; i < n; ++i) {
        ++s.judged_by[exact[i] ? "exact rational (Sturm)" : "MPFR reference"];
    }
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
    // --progress: a bar; --no-progress: nothing; else a bar on a terminal, lines elsewhere.
    const Progress::Mode mode = o.progress == 0  ? Progress::Mode::Off
                                : o.progress > 0 ? Progress::Mode::Bar
                                : isatty(2) != 0 ? Progress::Mode::Bar
                                                 : Progress::Mode::Lines;
    Progress progress(mode, total);
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
