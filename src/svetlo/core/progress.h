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
    /// Clears the bar; call before printing a summary.
    void finish();

private:
    void draw(int64_t done, bool final);

    std::string label_;
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
