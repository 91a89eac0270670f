#include "svetlo/core/progress.h"

#include <unistd.h>

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

void Progress::finish() {
    if (!enabled_ || finished_) return;
    std::lock_guard lock(draw_mutex_);
    finished_ = true;
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
}

void Progress::draw(int64_t done, bool /*final*/) {
    constexpr int kWidth = 40;
    double fraction = static_cast<double>(done) / static_cast<double>(total_);
    double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    int filled = static_cast<int>(fraction * kWidth);
    char bar[kWidth + 1];
    for (int k = 0; k < kWidth; ++k) bar[k] = k < filled ? '#' : '.';
    bar[kWidth] = '\0';
    std::fprintf(stderr, "\r%s [%s] %5.1f%%  %.1fs elapsed, ETA %.1fs\033[K", label_.c_str(), bar,
                 100.0 * fraction, elapsed, eta);
    std::fflush(stderr);
}

}  // namespace svetlo
