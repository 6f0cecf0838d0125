// apps/progress.cpp — the progress bar and progress lines of apps/progress.h.
#include "apps/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace certray::apps {
namespace {

constexpr double kLineEvery = 5.0;  ///< seconds between two progress lines
constexpr auto kTick = std::chrono::milliseconds(200);

}  // namespace

double progress_threshold_seconds() {
    const char* env = std::getenv("CERTRAY_PROGRESS_SECONDS");
    if (env == nullptr || *env == '\0') return 2.0;
    char* end = nullptr;
    const double v = std::strtod(env, &end);
    return (*end == '\0' && v >= 0 && std::isfinite(v)) ? v : 2.0;
}

ProgressMode progress_mode_for_stderr(bool quiet) {
    if (quiet) return ProgressMode::Off;
    return isatty(STDERR_FILENO) != 0 ? ProgressMode::Bar : ProgressMode::Lines;
}

ProgressReport::ProgressReport(std::string label, const tracers::WorkProgress& work,
                               ProgressMode mode)
    : label_(std::move(label)),
      work_(work),
      mode_(mode),
      threshold_(progress_threshold_seconds()),
      start_(std::chrono::steady_clock::now()) {
    if (mode_ != ProgressMode::Off) thread_ = std::thread([this] { loop(); });
}

ProgressReport::~ProgressReport() { stop(); }

double ProgressReport::elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressReport::loop() {
    std::unique_lock lock(mutex_);
    for (;;) {
        const bool started = work_.total.load() > 0;  // not while the computation is set up
        if (started && mode_ == ProgressMode::Lines && elapsed() >= threshold_ &&
            (last_line_ < 0 || elapsed() - last_line_ >= kLineEvery)) {
            draw_line(false);
        }
        if (cv_.wait_for(lock, kTick, [this] { return stopped_; })) return;
        if (started && mode_ == ProgressMode::Bar) draw_bar(false);
    }
}

void ProgressReport::stop() {
    {
        std::lock_guard lock(mutex_);
        stopped_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void ProgressReport::finish() {
    if (finished_) return;
    finished_ = true;
    stop();
    if (mode_ == ProgressMode::Bar && drawn_) draw_bar(true);
    if (mode_ == ProgressMode::Lines && (drawn_ || elapsed() >= threshold_)) draw_line(true);
}

void ProgressReport::draw_bar(bool final) {
    const std::uint64_t total = std::max<std::uint64_t>(1, work_.total.load());
    const std::uint64_t done = final ? total : std::min(total, work_.done.load());
    const int filled = static_cast<int>(40 * done / total);
    const double t = elapsed();
    std::string left;
    if (!final && done > 0) {
        left = ", " + std::to_string(static_cast<long long>(std::ceil(t * (total - done) / done))) +
               " s left";
    }
    std::fprintf(stderr, "\r%s [%-40.*s] %3d%% %llu/%llu tiles%s%s", label_.c_str(), filled,
                 "########################################", static_cast<int>(100 * done / total),
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total),
                 left.c_str(), final ? "\n" : "\033[K");
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressReport::draw_line(bool final) {
    const std::uint64_t total = std::max<std::uint64_t>(1, work_.total.load());
    const double t = elapsed();
    if (final) {
        std::fprintf(stderr, "%s: 100%% (%llu tiles) in %.1f s\n", label_.c_str(),
                     static_cast<unsigned long long>(total), t);
    } else {
        const std::uint64_t done = std::min(total, work_.done.load());
        const double rate = t > 0 ? done / t : 0;
        std::string left = "time left unknown";
        if (rate > 0) {
            left = "about " +
                   std::to_string(static_cast<long long>(std::ceil((total - done) / rate))) +
                   " s left";
        }
        std::fprintf(stderr, "%s: %d%% (%llu of %llu tiles), %.1f tiles/s, %s\n", label_.c_str(),
                     static_cast<int>(100 * done / total), static_cast<unsigned long long>(done),
                     static_cast<unsigned long long>(total), rate, left.c_str());
        last_line_ = t;
    }
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace certray::apps
