// Tile-parallel loops over an image, on oneTBB. A tile is the unit of work and of
// determinism: its result depends only on its pixels, never on which thread ran it.
#pragma once

#include <functional>

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

/// The number of threads that `threads` (0 = all cores) resolves to: at most the cores.
int resolve_threads(int threads);

}  // namespace svetlo
