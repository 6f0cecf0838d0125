// apps/query.cpp — `certray query`: load, solve every ray on a pool of threads, write the files.
#include "apps/query.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string_view>
#include <thread>

#include "apps/progress.h"
#include "certray/certray.h"
#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/ray.h"
#include "solvers/ray_io.h"
#include "tracers/methods.h"
#include "tracers/parallel.h"

namespace certray::apps {
namespace {

/// A file written to `PATH.tmp` and renamed to PATH by commit(); removed if never committed.
class AtomicOutput {
  public:
    explicit AtomicOutput(std::filesystem::path path)
        : path_(std::move(path)), tmp_(path_.string() + ".tmp") {
        out_.open(tmp_, std::ios::binary | std::ios::trunc);
        if (!out_) {
            throw std::runtime_error("cannot write '" + tmp_.string() +
                                     "': " + std::strerror(errno));
        }
        open_ = true;
    }
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;
    ~AtomicOutput() {
        if (!open_) return;
        out_.close();
        std::error_code ec;
        std::filesystem::remove(tmp_, ec);
    }

    std::ostream& stream() { return out_; }

    /// Closes the temporary file and renames it into place; throws when either fails.
    void commit() {
        out_.flush();
        out_.close();
        if (out_.fail()) {
            throw std::runtime_error("cannot write '" + tmp_.string() + "': write failed");
        }
        std::error_code ec;
        std::filesystem::rename(tmp_, path_, ec);
        if (ec) {
            throw std::runtime_error("cannot rename '" + tmp_.string() + "' to '" + path_.string() +
                                     "': " + ec.message());
        }
        open_ = false;
    }

  private:
    std::filesystem::path path_;
    std::filesystem::path tmp_;
    std::ofstream out_;
    bool open_ = false;
};

nlohmann::json make_stats(const QueryOptions& options, const tracers::MethodOptions& knobs,
                          const expr::Tape& tape, const std::vector<RayResult>& results,
                          double seconds, unsigned threads) {
    EvalCounts sum;
    std::uint64_t max_total = 0;
    std::uint64_t counts[3] = {0, 0, 0};
    for (const RayResult& r : results) {
        sum += r.evals;
        max_total = std::max(max_total, r.evals.total());
        ++counts[static_cast<int>(r.status)];
    }
    const double mean =
        results.empty() ? 0.0
                        : static_cast<double>(sum.total()) / static_cast<double>(results.size());
    nlohmann::json j;
    j["method"] = options.method;
    j["certified"] = tracers::method_info(options.method).certified;
    // What the answers mean: the surface asked for, when the method is certified; the approximate
    // methods approximate the zero surface whatever was asked.
    j["surface"] = tracers::method_info(options.method).certified ? options.surface : "zero";
    j["scene"] = options.scene;
    j["rays_file"] = options.rays;
    j["rays"] = results.size();
    j["seconds"] = seconds;
    j["threads"] = threads;
    const auto& reads = tracers::method_info(options.method).knobs;
    if (std::find(reads.begin(), reads.end(), "budget") != reads.end()) j["budget"] = knobs.budget;
    nlohmann::json given = nlohmann::json::object();
    for (const auto& [name, value] : options.knobs.values) given[name] = value;
    if (options.knobs.bounds) given["bounds"] = *options.knobs.bounds;
    j["knobs"] = given;
    j["tape_size"] = tape.size();
    j["evaluations"] = {{"value", sum.value},
                        {"interval", sum.interval},
                        {"gradient", sum.gradient},
                        {"total", sum.total()}};
    j["evaluations_per_ray"] = {{"mean", mean}, {"max", max_total}};
    j["status"] = {{"hit", counts[static_cast<int>(Status::Hit)]},
                   {"miss", counts[static_cast<int>(Status::Miss)]},
                   {"unknown", counts[static_cast<int>(Status::Unknown)]}};
    return j;
}

}  // namespace

std::vector<std::string> query_methods() { return tracers::method_names(); }

int run_query(const QueryOptions& options) {
    const std::string_view* new_name = tracers::renamed_method(options.method);
    if (new_name && !options.quiet) {
        std::cerr << "certray query: method '" << options.method << "' is now called '" << *new_name
                  << "' (the old name still works)\n";
    }
    tracers::MethodOptions knobs;
    try {
        knobs = tracers::resolve_knobs(options.method, options.knobs);
    } catch (const std::invalid_argument& e) {
        std::cerr << "certray query: " << e.what() << "\n";
        return 2;
    }
    const Scene scene = Scene::load(options.scene);
    std::vector<Ray> rays;
    if (options.rays == "-") {
        rays = read_rays_csv(std::cin, "<stdin>");
    } else {
        rays = read_rays_csv_file(options.rays);
    }

    // Open the outputs before the long part, so an unwritable directory fails fast.
    std::unique_ptr<AtomicOutput> hits;
    if (options.out != "-") hits = std::make_unique<AtomicOutput>(options.out);
    std::unique_ptr<AtomicOutput> stats;
    if (!options.stats.empty()) stats = std::make_unique<AtomicOutput>(options.stats);

    certray::QueryOptions q;
    q.method = options.method;
    q.surface = tracers::parse_surface(options.surface);
    q.knobs = options.knobs;
    q.threads = options.threads;
    q.coherent = !options.per_ray;
    const bool tty = isatty(STDERR_FILENO) != 0;
    const auto start = std::chrono::steady_clock::now();
    bool printed = false;
    // A bar on a terminal; elsewhere a line every 5 s for runs longer than the threshold (2 s, or
    // CERTRAY_PROGRESS_SECONDS), as for render.
    const double threshold = tty ? 1.0 : progress_threshold_seconds();
    auto last = start;
    if (!options.quiet) {
        q.progress = [&](std::size_t done, std::size_t n) {
            const auto now = std::chrono::steady_clock::now();
            const double elapsed = std::chrono::duration<double>(now - start).count();
            if (elapsed < threshold || (done < n && !tty && now - last < std::chrono::seconds(5)))
                return;
            last = now;
            const double pct =
                n == 0 ? 100.0 : 100.0 * static_cast<double>(done) / static_cast<double>(n);
            const double rate = static_cast<double>(done) / elapsed;
            const double left = rate > 0 ? static_cast<double>(n - done) / rate : 0.0;
            std::fprintf(stderr,
                         tty ? "\rcertray query: %zu / %zu rays (%.0f%%), %.0f rays/s, %.0f s left"
                             : "certray query: %zu / %zu rays (%.0f%%), %.0f rays/s, %.0f s left\n",
                         done, n, std::floor(pct), rate, left);
            std::fflush(stderr);
            printed = true;
        };
    }
    const std::vector<RayResult> results = certray::query(scene, rays, q);
    if (printed && tty) std::fprintf(stderr, "\n");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const HitsKind kind = tracers::method_info(options.method).certified ? HitsKind::Certified
                                                                         : HitsKind::Approximate;
    if (hits) {
        write_hits_csv(hits->stream(), results, kind);
    } else {
        write_hits_csv(std::cout, results, kind);
        std::cout.flush();
    }
    if (stats) {
        stats->stream() << make_stats(options, knobs, scene.tape(), results, seconds,
                                      tracers::worker_count(options.threads))
                               .dump(2)
                        << "\n";
    }
    if (hits) hits->commit();
    if (stats) stats->commit();
    if (!options.quiet && !tracers::method_info(options.method).certified) {
        std::fprintf(stderr,
                     "certray query: '%s' is approximate: its answers are not proven (a hit's t "
                     "is an estimate; see docs/guide/semantics.md)\n",
                     options.method.c_str());
    }
    return 0;
}

}  // namespace certray::apps
