#include "svetlo/core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace svetlo {

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::string label, int64_t total, bool enabled)
    : label_(std::move(label)),
      total_(total > 0 ? total : 1),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() { finish(); }

void Progress::advance(int64_t units) {
    int64_t done = done_.fetch_add(units) + units;
    if (!enabled_) return;
    auto now = std::chrono::steady_clock::now();
    std::unique_lock lock(draw_mutex_, std::try_to_lock);
    if (!lock.owns_lock() || now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    draw(done, false);
}

void Progress::show_rate(std::string unit) {
    std::lock_guard lock(draw_mutex_);
    unit_ = std::move(unit);
}

void Progress::set_budget(double seconds) {
    std::lock_guard lock(draw_mutex_);
    budget_ = seconds;
}

void Progress::set_status(std::string status) {
    std::lock_guard lock(draw_mutex_);
    status_ = std::move(status);
}

void Progress::finish() {
    if (!enabled_ || finished_) return;
    std::lock_guard lock(draw_mutex_);
    finished_ = true;
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
}

void Progress::draw(int64_t done, bool /*final*/) {
    constexpr int kWidth = 40;
    double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    double fraction = static_cast<double>(done) / static_cast<double>(total_);
    if (budget_ > 0.0) fraction = std::min(1.0, std::max(fraction, elapsed / budget_));
    double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    int filled = static_cast<int>(fraction * kWidth);
    char bar[kWidth + 1];
    for (int k = 0; k < kWidth; ++k) bar[k] = k < filled ? '#' : '.';
    bar[kWidth] = '\0';
    std::string rate;
    if (!unit_.empty() && elapsed > 0.0) {
        char text[64];
        std::snprintf(text, sizeof text, ", %.2f M%s/s", 1e-6 * static_cast<double>(done) / elapsed,
                      unit_.c_str());
        rate = text;
    }
    std::fprintf(stderr, "\r%s [%s] %5.1f%%  %s%s%.1fs elapsed, ETA %.1fs%s\033[K", label_.c_str(),
                 bar, 100.0 * fraction, status_.c_str(), status_.empty() ? "" : ", ", elapsed, eta,
                 rate.c_str());
    std::fflush(stderr);
}

}  // namespace svetlo
