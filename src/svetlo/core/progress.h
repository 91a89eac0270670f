// A progress bar with an ETA on stderr, drawn only when stderr is a terminal and the user
// did not ask for --quiet. Thread-safe: workers call advance() as tiles finish.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace svetlo {

class Progress {
public:
    /// `total` units of work (pixels); `enabled` false makes every call a no-op.
    Progress(std::string label, int64_t total, bool enabled);
    ~Progress();

    void advance(int64_t units);
    /// Also shows units per second, e.g. "1.25 Msamples/s" for unit "samples".
    void show_rate(std::string unit);
    /// A time budget (seconds): the bar then shows the larger of the work and time fractions.
    void set_budget(double seconds);
    /// Text after the bar, such as "pass 3/16"; set between units of work.
    void set_status(std::string status);
    /// Clears the bar; call before printing a summary.
    void finish();

private:
    void draw(int64_t done, bool final);

    std::string label_;
    std::string unit_, status_;
    double budget_ = 0.0;
    int64_t total_;
    bool enabled_;
    std::atomic<int64_t> done_{0};
    std::mutex draw_mutex_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_draw_;
    bool finished_ = false;
};

/// True when stderr is a terminal.
bool stderr_is_terminal();

}  // namespace svetlo
