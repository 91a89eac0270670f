// The parallel loops every module runs on: the one seam between svetlo and its threads.
// parallel_tbb.cpp runs them on oneTBB; parallel_threads.cpp, where oneTBB is not built (the
// browser's WebAssembly), on plain std::threads: the outermost loop in parallel, a loop or a
// task inside it on the thread that meets it. A tile is the unit of work and of determinism:
// its result depends only on its pixels, never on which thread ran it.
#pragma once

#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace svetlo {

struct Tile {
    int x0, y0, x1, y1;  // pixel range [x0, x1) x [y0, y1)
};

inline constexpr int kTileSize = 16;

/// Calls `body(tile)` for every tile of a width x height image on `threads` threads
/// (0 = all cores), then `done(pixels_in_tile)` after each, for progress reporting.
void parallel_tiles(int width, int height, int threads,
                    const std::function<void(const Tile&)>& body,
                    const std::function<void(int)>& done = {});
/// The same with square tiles of `tile_size` pixels.
void parallel_tiles(int width, int height, int tile_size, int threads,
                    const std::function<void(const Tile&)>& body,
                    const std::function<void(int)>& done);

/// Calls body(i) for every i in [0, count), one index per task (for coarse work items whose
/// boundaries must not depend on the thread count).
void parallel_indices(size_t count, int threads, const std::function<void(size_t)>& body);

/// Runs body(begin, end) over [0, count) in chunks of at least `grain` on `threads` threads
/// (0 = all cores).
void parallel_ranges(size_t count, int threads, const std::function<void(size_t, size_t)>& body,
                     size_t grain = 4096);

/// The least of least(begin, end) over the chunks of parallel_ranges (infinity for none): the
/// same on any thread count, whichever order the chunks come in.
inline float parallel_min(size_t count, int threads,
                          const std::function<float(size_t, size_t)>& least, size_t grain = 4096) {
    std::mutex mutex;
    float out = std::numeric_limits<float>::infinity();
    parallel_ranges(
        count, threads,
        [&](size_t begin, size_t end) {
            const float m = least(begin, end);
            std::lock_guard lock(mutex);
            out = std::min(out, m);
        },
        grain);
    return out;
}

/// The number of threads that `threads` (0 = all cores) resolves to: at most the cores.
int resolve_threads(int threads);

/// Runs `body` with the parallel calls inside it (parallel_for_each, TaskGroup) on at most
/// `threads` threads (0 = all cores).
void with_threads(int threads, const std::function<void()>& body);

/// Calls body(i) for every i in [0, count) on the threads of the enclosing with_threads (all
/// cores outside one); the work is split as the scheduler chooses.
void parallel_for_each(size_t count, const std::function<void(size_t)>& body);

/// Tasks run beside the caller (a recursive build's subtrees); wait() returns when all have.
class TaskGroup {
public:
    TaskGroup();
    ~TaskGroup();
    TaskGroup(const TaskGroup&) = delete;
    TaskGroup& operator=(const TaskGroup&) = delete;
    void run(std::function<void()> task);
    void wait();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The index of the calling thread among those of the parallel call it runs in, in
/// [0, resolve_threads(threads)) for a call given `threads`.
int worker_index();

/// One T per thread of a parallel call on `threads` threads (scratch buffers kept from one
/// tile to the next): local() is the calling thread's.
template <class T>
class PerWorker {
public:
    explicit PerWorker(int threads) : slots_(static_cast<size_t>(resolve_threads(threads))) {}
    T& local() {
        const int k = worker_index();
        if (k < 0 || static_cast<size_t>(k) >= slots_.size())
            throw std::logic_error("PerWorker::local outside its parallel call");
        return slots_[static_cast<size_t>(k)];
    }
    /// Every thread's T (after the call: to sum what each kept).
    auto begin() { return slots_.begin(); }
    auto end() { return slots_.end(); }

private:
    std::vector<T> slots_;
};

}  // namespace svetlo
