// The parallel loops (parallel.h) on oneTBB: each call its own task arena of the threads it
// is given, work stealing inside it.
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>

#include "svetlo/core/parallel.h"

namespace svetlo {

int resolve_threads(int threads) {
    // More threads than cores would only wait for one another (and TBB warns that it cannot
    // start them): the machine's cores are the most that run. Results do not depend on it.
    const int cores = std::max(1, tbb::info::default_concurrency());
    return threads > 0 ? std::min(threads, cores) : cores;
}

void parallel_indices(size_t count, int threads, const std::function<void(size_t)>& body) {
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t i = r.begin(); i != r.end(); ++i) body(i);
                          });
    });
}

void parallel_ranges(size_t count, int threads, const std::function<void(size_t, size_t)>& body,
                     size_t grain) {
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, std::max<size_t>(grain, 1)),
                          [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
    });
}

void with_threads(int threads, const std::function<void()>& body) {
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] { body(); });
}

void parallel_for_each(size_t count, const std::function<void(size_t)>& body) {
    tbb::parallel_for(size_t{0}, count, [&](size_t i) { body(i); });
}

struct TaskGroup::Impl {
    tbb::task_group group;
};

TaskGroup::TaskGroup() : impl_(std::make_unique<Impl>()) {}
TaskGroup::~TaskGroup() { impl_->group.wait(); }
void TaskGroup::run(std::function<void()> task) { impl_->group.run(std::move(task)); }
void TaskGroup::wait() { impl_->group.wait(); }

int worker_index() { return tbb::this_task_arena::current_thread_index(); }

}  // namespace svetlo
