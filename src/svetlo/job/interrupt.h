// SIGINT and SIGTERM during a render (docs/cli.md: the current pass ends, the image of the
// passes done is written, its provenance says so, and the program exits 130 or 143).
#pragma once

#include <atomic>

namespace svetlo {

/// While alive, SIGINT and SIGTERM set `flag()` instead of killing the process; the previous
/// handlers come back when it is destroyed. One at a time.
class InterruptGuard {
public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// Set once a signal arrived: the engines stop after the pass in progress.
    const std::atomic<bool>& flag() const;
    /// The signal that arrived (0: none), and the exit status it asks for (128 + signal).
    int signal() const;
    int exit_status() const { return signal() == 0 ? 0 : 128 + signal(); }
};

}  // namespace svetlo
