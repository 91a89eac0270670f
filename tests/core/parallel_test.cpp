// The seam under every parallel loop (core/parallel.h), on whichever backend the build has:
// oneTBB natively, std::threads in the browser's build and in the scalar build (make
// test-scalar, which runs these tests too).
#include "svetlo/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <mutex>
#include <set>
#include <stdexcept>
#include <vector>

using namespace svetlo;

// Every index exactly once, on one thread and on two; a worker's index lies in its call's range.
TEST(Parallel, EveryIndexOnceAndEachWorkerInItsRange) {
    for (int threads : {1, 2}) {
        std::vector<std::atomic<int>> seen(1000);
        std::atomic<bool> in_range{true};
        const int workers = resolve_threads(threads);
        parallel_indices(seen.size(), threads, [&](size_t i) {
            seen[i].fetch_add(1);
            const int k = worker_index();
            if (k < 0 || k >= workers) in_range = false;
        });
        for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i].load(), 1) << i;
        EXPECT_TRUE(in_range.load());
    }
}

// Ranges cover [0, count) without overlap, whatever the grain; tiles cover the image.
TEST(Parallel, RangesAndTilesCoverEverythingOnce) {
    for (int threads : {1, 2}) {
        std::vector<std::atomic<int>> seen(10007);
        parallel_ranges(
            seen.size(), threads,
            [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) seen[i].fetch_add(1);
            },
            100);
        for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << i;
        std::vector<std::atomic<int>> pixels(37 * 21);
        std::atomic<int> done{0};
        parallel_tiles(
            37, 21, 8, threads,
            [&](const Tile& t) {
                for (int y = t.y0; y < t.y1; ++y)
                    for (int x = t.x0; x < t.x1; ++x) pixels[static_cast<size_t>(y * 37 + x)]++;
            },
            [&](int n) { done += n; });
        for (auto& p : pixels) ASSERT_EQ(p.load(), 1);
        EXPECT_EQ(done.load(), 37 * 21);
    }
}

// A loop inside a loop, a task group inside with_threads: everything runs, and each thread's
// scratch (PerWorker) is its own.
TEST(Parallel, NestedLoopsTasksAndPerWorkerScratch) {
    for (int threads : {1, 2}) {
        std::atomic<int> inner{0};
        PerWorker<std::vector<int>> scratch(threads);
        parallel_indices(20, threads, [&](size_t i) {
            scratch.local().push_back(static_cast<int>(i));
            parallel_for_each(10, [&](size_t) { inner++; });
        });
        EXPECT_EQ(inner.load(), 200);
        std::multiset<int> all;
        for (const std::vector<int>& s : scratch) all.insert(s.begin(), s.end());
        EXPECT_EQ(all.size(), 20u);
        std::atomic<int> tasks{0};
        with_threads(threads, [&] {
            TaskGroup group;
            for (int k = 0; k < 8; ++k)
                group.run([&] { parallel_for_each(5, [&](size_t) { tasks++; }); });
            group.wait();
        });
        EXPECT_EQ(tasks.load(), 40);
    }
}

// An exception thrown by the body reaches the caller, on one thread and on two.
TEST(Parallel, TheLeastOverChunksIsTheSameOnAnyThreadCount) {
    // A value per index whose least lies in the middle of a chunk of the second half.
    auto value = [](size_t i) { return i == 70001 ? -3.5f : static_cast<float>(i % 977); };
    for (int threads : {1, 2}) {
        EXPECT_EQ(parallel_min(
                      100000, threads,
                      [&](size_t begin, size_t end) {
                          float m = std::numeric_limits<float>::infinity();
                          for (size_t i = begin; i < end; ++i) m = std::min(m, value(i));
                          return m;
                      },
                      1000),
                  -3.5f);
        EXPECT_EQ(parallel_min(0, threads, [](size_t, size_t) { return 0.0f; }),
                  std::numeric_limits<float>::infinity());
    }
}

TEST(Parallel, AnExceptionReachesTheCaller) {
    for (int threads : {1, 2}) {
        EXPECT_THROW(parallel_indices(100, threads,
                                      [&](size_t i) {
                                          if (i == 57) throw std::runtime_error("57");
                                      }),
                     std::runtime_error);
    }
}
