// apps/progress.h — the progress of a long computation on stderr: a bar on a terminal, periodic
// one-line reports otherwise (a log, a CI job), nothing with --quiet.
//
// Contract: a ProgressReport polls a tracers::WorkProgress from its own thread until finish() (or
// destruction). Bar: redrawn in place every 200 ms ("certray render [####    ] 45% 12/26 tiles,
// 3 s left"), the full bar and a newline at the end when it was drawn at all. Lines: nothing for a
// run shorter than the threshold (2 s, or the environment variable CERTRAY_PROGRESS_SECONDS), then
// one line at the threshold and at most one every 5 s ("certray render: 45% (12 of 26 tiles), 4.1
// tiles/s, about 3 s left"), and a final line ("certray render: 100% (26 tiles) in 6.3 s") when any
// was printed or the run reached the threshold. Off: nothing.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "tracers/progress.h"

namespace certray::apps {

/// How progress is shown.
enum class ProgressMode { Off, Bar, Lines };

/// Seconds before the first progress line off a terminal: CERTRAY_PROGRESS_SECONDS when it is a
/// number ≥ 0, else 2.
double progress_threshold_seconds();

/// Off when `quiet`, a bar when stderr is a terminal, lines otherwise.
ProgressMode progress_mode_for_stderr(bool quiet);

/// Draws `work` on stderr while it advances (see the file contract).
class ProgressReport {
  public:
    /// Starts polling; `label` names the command ("certray render").
    ProgressReport(std::string label, const tracers::WorkProgress& work, ProgressMode mode);
    ~ProgressReport();
    ProgressReport(const ProgressReport&) = delete;
    ProgressReport& operator=(const ProgressReport&) = delete;

    /// Stops polling and draws the end (the full bar, or the final line). Idempotent; call it
    /// only when the computation succeeded (the destructor stops without drawing the end).
    void finish();

  private:
    void loop();
    void stop();
    void draw_bar(bool final);
    void draw_line(bool final);
    double elapsed() const;

    std::string label_;
    const tracers::WorkProgress& work_;
    ProgressMode mode_;
    double threshold_;  ///< seconds before the first line (Lines)
    std::chrono::steady_clock::time_point start_;
    double last_line_ = -1;  ///< when the last line was printed (Lines), -1: never
    bool drawn_ = false;     ///< anything printed yet
    bool stopped_ = false;
    bool finished_ = false;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::thread thread_;
};

}  // namespace certray::apps
