#include "svetlo/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace svetlo {

int resolve_threads(int threads) {
    return threads > 0 ? threads : std::max(1, tbb::info::default_concurrency());
}

void parallel_tiles(int width, int height, int threads,
                    const std::function<void(const Tile&)>& body,
                    const std::function<void(int)>& done) {
    int tiles_x = (width + kTileSize - 1) / kTileSize;
    int tiles_y = (height + kTileSize - 1) / kTileSize;
    int count = tiles_x * tiles_y;
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, count, 1), [&](const tbb::blocked_range<int>& r) {
            for (int t = r.begin(); t != r.end(); ++t) {
                Tile tile;
                tile.x0 = (t % tiles_x) * kTileSize;
                tile.y0 = (t / tiles_x) * kTileSize;
                tile.x1 = std::min(tile.x0 + kTileSize, width);
                tile.y1 = std::min(tile.y0 + kTileSize, height);
                body(tile);
                if (done) done((tile.x1 - tile.x0) * (tile.y1 - tile.y0));
            }
        });
    });
}

void parallel_ranges(size_t count, int threads, const std::function<void(size_t, size_t)>& body) {
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 4096),
                          [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
    });
}

}  // namespace svetlo
