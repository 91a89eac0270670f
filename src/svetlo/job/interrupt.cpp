#include "svetlo/job/interrupt.h"

#include <csignal>

namespace svetlo {

namespace {

// A signal handler can only reach state with static storage; these two are the program's
// only such state, and lock-free atomics are safe to set from a handler.
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" void on_signal(int sig) {
    g_signal.store(sig);
    g_interrupted.store(true);
}

struct sigaction g_previous[2];

}  // namespace

InterruptGuard::InterruptGuard() {
    g_interrupted = false;
    g_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &g_previous[0]);
    sigaction(SIGTERM, &action, &g_previous[1]);
}

InterruptGuard::~InterruptGuard() {
    sigaction(SIGINT, &g_previous[0], nullptr);
    sigaction(SIGTERM, &g_previous[1], nullptr);
}

const std::atomic<bool>& InterruptGuard::flag() const { return g_interrupted; }
int InterruptGuard::signal() const { return g_signal.load(); }

}  // namespace svetlo
