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

#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/ray.h"
#include "solvers/ray_io.h"
#include "tracers/methods.h"

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

/// Runs `fn` over all rays on `threads` workers, results in input order. Prints a progress line on
/// stderr when it is a terminal and the run takes more than a second.
std::vector<RayResult> solve_all(const std::vector<Ray>& rays, const tracers::RayFunction& fn,
                                 unsigned threads) {
    constexpr std::size_t kChunk = 64;
    const std::size_t n = rays.size();
    std::vector<RayResult> results(n);
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> done{0};
    std::mutex mutex;
    std::condition_variable finished_cv;
    unsigned finished = 0;
    std::exception_ptr error;

    auto worker = [&] {
        try {
            for (;;) {
                const std::size_t begin = next.fetch_add(kChunk, std::memory_order_relaxed);
                if (begin >= n) break;
                const std::size_t end = std::min(n, begin + kChunk);
                for (std::size_t i = begin; i < end; ++i) results[i] = fn(rays[i]);
                done.fetch_add(end - begin, std::memory_order_relaxed);
            }
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!error) error = std::current_exception();
            next.store(n);  // stop the others early
        }
        std::lock_guard lock(mutex);
        ++finished;
        finished_cv.notify_all();
    };

    const unsigned workers =
        static_cast<unsigned>(std::clamp<std::size_t>((n + kChunk - 1) / kChunk, 1, threads));
    std::vector<std::thread> pool;
    pool.reserve(workers);
    for (unsigned i = 0; i < workers; ++i) pool.emplace_back(worker);

    const bool tty = isatty(STDERR_FILENO) != 0;
    const auto start = std::chrono::steady_clock::now();
    bool printed = false;
    {
        std::unique_lock lock(mutex);
        while (!finished_cv.wait_for(lock, std::chrono::milliseconds(200),
                                     [&] { return finished == workers; })) {
            if (!tty || std::chrono::steady_clock::now() - start < std::chrono::seconds(1)) {
                continue;
            }
            const std::size_t d = done.load(std::memory_order_relaxed);
            std::fprintf(stderr, "\rcertray query: %zu / %zu rays (%.0f%%)", d, n,
                         n == 0
                             ? 100.0
                             : std::floor(100.0 * static_cast<double>(d) / static_cast<double>(n)));
            std::fflush(stderr);
            printed = true;
        }
    }
    for (std::thread& t : pool) t.join();
    if (printed) std::fprintf(stderr, "\rcertray query: %zu / %zu rays (100%%)\n", n, n);
    if (error) std::rethrow_exception(error);
    return results;
}

nlohmann::json make_stats(const QueryOptions& options, const expr::Tape& tape,
                          const std::vector<RayResult>& results, double seconds, unsigned threads) {
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
    j["scene"] = options.scene;
    j["rays_file"] = options.rays;
    j["rays"] = results.size();
    j["seconds"] = seconds;
    j["threads"] = threads;
    j["budget"] = options.budget;
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
    const std::vector<std::string> names = query_methods();
    if (std::find(names.begin(), names.end(), options.method) == names.end()) {
        std::string list;
        for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
        std::cerr << "certray query: unknown method '" << options.method
                  << "'; available methods: " << list << "\n";
        return 2;
    }
    const expr::Tape tape(expr::load_graph_file(options.scene));
    tracers::MethodOptions method_options = options.knobs;
    method_options.budget = options.budget;
    const tracers::RayFunction fn = tracers::make_method(options.method, tape, method_options);
    const std::vector<Ray> rays = read_rays_csv_file(options.rays);

    // Open the outputs before the long part, so an unwritable directory fails fast.
    AtomicOutput hits(options.out);
    std::unique_ptr<AtomicOutput> stats;
    if (!options.stats.empty()) stats = std::make_unique<AtomicOutput>(options.stats);

    const unsigned threads =
        options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    const auto start = std::chrono::steady_clock::now();
    const std::vector<RayResult> results = solve_all(rays, fn, threads);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    write_hits_csv(hits.stream(), results);
    if (stats)
        stats->stream() << make_stats(options, tape, results, seconds, threads).dump(2) << "\n";
    hits.commit();
    if (stats) stats->commit();
    return 0;
}

}  // namespace certray::apps
