// apps/bench_report.cpp — `certray bench`'s outputs: measurements.csv, summary.csv and the
// markdown report (docs/report.md), from the study's rows and summaries.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "apps/bench_study.h"
#include "expr/load.h"
#include "expr/prune.h"
#include "solvers/certified.h"
#include "tracers/camera.h"
#include "tracers/image2d.h"
#include "tracers/methods.h"

namespace certray::apps::study {
namespace {

/// The columns both CSV files start with: suite,method,knob,value,certified,scene, and a comma.
std::string key_columns(const Config& c, const Scene& scene) {
    return scene.suite + "," + c.method + "," + c.knob + "," + num(c.value) + "," +
           (c.certified ? "1" : "0") + "," + scene.name + ",";
}

}  // namespace

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
        s += key_columns(c, *r.scene) + std::to_string(r.ray) + "," +
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
        s += key_columns(c, *m.scene) + std::to_string(m.rays) + "," + fmt("%.3f", m.setup_ms) +
             "," + fmt("%.3f", m.mean_us) + "," + fmt("%.3f", m.median_us) + "," +
             fmt("%.2f", m.ev_value) + "," + fmt("%.2f", m.ev_interval) + "," +
             fmt("%.2f", m.ev_gradient) + "," + fmt("%.2f", m.ev_total);
        for (std::size_t k : m.counts) {
            s += ',';
            s += std::to_string(k);
        }
        // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on `"," + string&&`
        // in a profile-guided build.
        s += ',';
        s += std::to_string(m.ref_unknown);
        s += ',';
        s += num(m.max_error);
        s += ',';
        s += num(m.median_error);
        s += '\n';
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

/// "1 scene", "3 scenes".
std::string count(std::size_t n, const std::string& noun) {
    return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

/// What the study covers, for the report's opening: "gallery: 3 scenes (a, b, c), 32 rays
/// each; stress suite: 38 cases in 13 scenes", or "stress suite: not run (--stress none)".
std::string coverage(const BenchOptions& o, const Study& st) {
    std::string s = "gallery: ";
    if (st.gallery.empty()) {
        s += "not run (no scenes)";
    } else {
        std::size_t lo = st.gallery.front().rays.size(), hi = lo;
        s +=
            std::to_string(st.gallery.size()) + (st.gallery.size() == 1 ? " scene (" : " scenes (");
        for (std::size_t k = 0; k < st.gallery.size(); ++k) {
            s += (k ? ", " : "") + st.gallery[k].name;
            lo = std::min(lo, st.gallery[k].rays.size());
            hi = std::max(hi, st.gallery[k].rays.size());
        }
        s += "), " + std::to_string(lo) + (lo == hi ? "" : "–" + std::to_string(hi)) + " rays" +
             (st.gallery.size() == 1 ? "" : " each");
    }
    s += "; stress suite: ";
    if (st.stress.empty()) {
        s += o.stress == "none" ? "not run (--stress none)" : "not run (no cases; see Notes)";
    } else {
        std::size_t cases = 0;
        for (const Scene& sc : st.stress) cases += sc.rays.size();
        s += count(cases, "case") + " in " + count(st.stress.size(), "scene");
    }
    return s;
}

/// The stress table's column name: the method, and its setting when that is not the default.
std::string column_name(const Config& c) {
    if (c.knob == "default") return c.method;
    const tracers::MethodOptions def;
    for (const tracers::Knob& kn : tracers::knobs()) {
        if (kn.name == c.knob && kn.get(def) == c.value) return c.method;
    }
    return c.label();
}

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
    md += "Covers " + coverage(o, st) + ".\n\n";
    const bool gallery_ran = !st.gallery.empty(), stress_ran = !st.stress.empty();
    const std::string suites = gallery_ran && stress_ran ? "gallery and stress suite"
                               : gallery_ran             ? "gallery only"
                               : stress_ran              ? "stress suite only"
                                                         : "no suite";

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
                  " judged rays (" + suites + ", every setting).\n";
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

    // Who judged which rays: an oracle that shares no code with the certified solver where one
    // exists (exact rationals on polynomial scenes, mpmath brackets on the stress suite).
    md += "### The judges\n\n| ray set | scene | judge | rays |\n| --- | --- | --- | --- |\n";
    for (const std::vector<Scene>* suite : {&st.gallery, &st.stress}) {
        for (const Scene& sc : *suite) {
            for (const auto& [judge, count] : sc.judged_by) {
                md += "| " + sc.suite + " | " + sc.name + " | " + judge + " | " +
                      std::to_string(count) + " |\n";
            }
        }
    }
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
                std::string label = m->config->label();  // GCC 12: no `"`" + string&&` (-Wrestrict)
                label.insert(label.begin(), '`');
                label += '`';
                if (!m->config->certified) label += " (approx.)";
                return label;
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
        // A column for every method that ran on the suite (the ones the totals below list), in
        // the order of the configs: its default run, else (when it has none) its first setting.
        std::set<std::string> ran;
        for (const Summary& m : st.summaries) {
            if (m.scene->suite == "stress") ran.insert(m.config->method);
        }
        std::vector<const Config*> cols;
        std::map<std::string, std::size_t> col_of;
        for (const Config& c : st.stress_configs) {
            if (!ran.count(c.method)) continue;
            const auto [it, fresh] = col_of.emplace(c.method, cols.size());
            if (fresh) {
                cols.push_back(&c);
            } else if (c.is_default && !cols[it->second]->is_default) {
                cols[it->second] = &c;
            }
        }
        std::size_t cases = 0;
        for (const Scene& sc : st.stress) cases += sc.rays.size();
        md += "## The stiff-and-extreme suite (scenes/stress)\n\n" + count(cases, "case") + " in " +
              count(st.stress.size(), "scene") +
              ". Every method that ran on the suite, at its default setting (certified budget "
              "20,000; ε = 1e-6; march step 0.01) or, when that was not run, at the setting run "
              "nearest it, named in the column's header (hermite: 128 samples, the default being "
              "64; --quick runs only the ends of each sweep). Cell: class, |t − t*| when both "
              "hit, µs. Classes: ok "
              "correct, MISS missed hit, FALSE false hit, OVER overshoot (a later root, or an "
              "unknown past the root), unk unknown (the right answer of a certified method on "
              "tangent and hard cases). Truth: the exact brackets of cases.csv.\n\n| case | "
              "expect";
        for (const Config* c : cols) md += " | " + column_name(*c);
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

}  // namespace certray::apps::study
