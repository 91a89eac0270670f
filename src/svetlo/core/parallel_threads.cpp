// The parallel loops (parallel.h) on plain std::threads, where oneTBB is not built (the
// browser's WebAssembly, whose threads are the page's web workers). The outermost call hands
// its work to threads kept from one call to the next (a page cannot start a worker while its
// thread waits) and shares it out one index at a time from a counter; a loop or a task met
// inside it runs on the thread that meets it. The first exception thrown on any thread is
// thrown to the caller once all have stopped.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include "svetlo/core/parallel.h"

namespace svetlo {

namespace {

// Each thread's part in the parallel call it runs in (the caller's own thread is worker 0).
thread_local int t_worker = 0;
thread_local bool t_inside = false;  // inside a parallel call: run nested work here
thread_local int t_threads = 0;      // set by with_threads; 0: all cores

/// The threads a call may use: the machine's cores, or one where the build has no threads
/// (the browser's module for pages that are not cross-origin isolated).
int cores() {
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
    return 1;
#else
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#endif
}

/// Threads that wait for work: run(n, work) calls work(k) for k in [0, n), work(0) on the
/// caller. One call at a time; the threads live as long as the program.
class WorkerThreads {
public:
    ~WorkerThreads() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : threads_) t.join();
    }

    void run(int n, const std::function<void(int)>& work) {
        std::lock_guard<std::mutex> one_call(call_mutex_);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            while (static_cast<int>(threads_.size()) < n - 1) {
                const int k = static_cast<int>(threads_.size()) + 1;
                threads_.emplace_back([this, k] { wait_for_work(k); });
            }
            work_ = &work;
            wanted_ = n;
            running_ = n - 1;
            ++generation_;
        }
        wake_.notify_all();
        work(0);
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [&] { return running_ == 0; });
        work_ = nullptr;
    }

private:
    void wait_for_work(int k) {
        uint64_t seen = 0;
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            if (k >= wanted_) continue;  // not needed this time
            const std::function<void(int)>* work = work_;
            lock.unlock();
            (*work)(k);
            lock.lock();
            if (--running_ == 0) finished_.notify_all();
        }
    }

    std::mutex call_mutex_;  // one call at a time
    std::mutex mutex_;       // the fields below
    std::condition_variable wake_, finished_;
    std::vector<std::thread> threads_;  // worker k is threads_[k - 1]
    const std::function<void(int)>* work_ = nullptr;
    int wanted_ = 0, running_ = 0;
    uint64_t generation_ = 0;
    bool stop_ = false;
};

WorkerThreads& worker_threads() {
    static WorkerThreads threads;  // the process's threads, as oneTBB keeps its own
    return threads;
}

/// Runs work(k) on `n` threads, k in [0, n), the caller as worker 0; inside a parallel call,
/// work(0) alone on this thread.
void run_workers(int n, const std::function<void()>& work) {
    const int saved_worker = t_worker;
    const bool saved_inside = t_inside;
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const std::function<void(int)> guarded = [&](int k) {
        t_worker = k;
        t_inside = true;
        try {
            work();
        } catch (...) {
            std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
        }
    };
    if (n <= 1 || saved_inside) {
        guarded(saved_inside ? saved_worker : 0);
    } else {
        worker_threads().run(n, guarded);
    }
    t_worker = saved_worker;
    t_inside = saved_inside;
    if (failure) std::rethrow_exception(failure);
}

/// Calls body(i) for every i in [0, count) on `n` threads, one index at a time.
void spread(size_t count, int n, const std::function<void(size_t)>& body) {
    if (count == 0) return;
    std::atomic<size_t> next{0};
    const int used = static_cast<int>(std::min<size_t>(static_cast<size_t>(n), count));
    run_workers(used, [&] {
        for (size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) body(i);
    });
}

}  // namespace

int resolve_threads(int threads) {
    const int all = cores();
    return threads > 0 ? std::min(threads, all) : all;
}

void parallel_indices(size_t count, int threads, const std::function<void(size_t)>& body) {
    spread(count, resolve_threads(threads), body);
}

void parallel_ranges(size_t count, int threads, const std::function<void(size_t, size_t)>& body,
                     size_t grain) {
    grain = std::max<size_t>(grain, 1);
    const size_t chunks = (count + grain - 1) / grain;
    spread(chunks, resolve_threads(threads),
           [&](size_t c) { body(c * grain, std::min(count, (c + 1) * grain)); });
}

void with_threads(int threads, const std::function<void()>& body) {
    const int saved = t_threads;
    t_threads = resolve_threads(threads);
    try {
        body();
    } catch (...) {
        t_threads = saved;
        throw;
    }
    t_threads = saved;
}

void parallel_for_each(size_t count, const std::function<void(size_t)>& body) {
    spread(count, t_threads > 0 ? t_threads : cores(), body);
}

// A task runs at once, on the thread that gives it: a task group here is the recursion itself.
struct TaskGroup::Impl {};

TaskGroup::TaskGroup() = default;
TaskGroup::~TaskGroup() = default;
void TaskGroup::run(std::function<void()> task) { task(); }
void TaskGroup::wait() {}

int worker_index() { return t_worker; }

}  // namespace svetlo
