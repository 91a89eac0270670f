#include "svetlo/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace svetlo {

int resolve_threads(int threads) {
    // More threads than cores would only wait for one another (and TBB warns that it cannot
    // start them): the machine's cores are the most that run. Results do not depend on it.
    const int cores = std::max(1, tbb::info::default_concurrency());
    return threads > 0 ? std::min(threads, cores) : cores;
}

void parallel_tiles(int width, int height, int threads,
                    const std::function<void(const Tile&)>& body,
                    const std::function<void(int)>& done) {
    parallel_tiles(width, height, kTileSize, threads, body, done);
}

void parallel_tiles(int width, int height, int tile_size, int threads,
                    const std::function<void(const Tile&)>& body,
                    const std::function<void(int)>& done) {
    int tiles_x = (width + tile_size - 1) / tile_size;
    int tiles_y = (height + tile_size - 1) / tile_size;
    int count = tiles_x * tiles_y;
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, count, 1),
                          [&](const tbb::blocked_range<int>& r) {
                              for (int t = r.begin(); t != r.end(); ++t) {
                                  Tile tile;
                                  tile.x0 = (t % tiles_x) * tile_size;
                                  tile.y0 = (t / tiles_x) * tile_size;
                                  tile.x1 = std::min(tile.x0 + tile_size, width);
                                  tile.y1 = std::min(tile.y0 + tile_size, height);
                                  body(tile);
                                  if (done) done((tile.x1 - tile.x0) * (tile.y1 - tile.y0));
                              }
                          });
    });
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

}  // namespace svetlo
