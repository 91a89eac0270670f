#include "svetlo/core/parallel.h"

#include <algorithm>

namespace svetlo {

void parallel_tiles(int width, int height, int threads,
                    const std::function<void(const Tile&)>& body,
                    const std::function<void(int)>& done) {
    parallel_tiles(width, height, kTileSize, threads, body, done);
}

void parallel_tiles(int width, int height, int tile_size, int threads,
                    const std::function<void(const Tile&)>& body,
                    const std::function<void(int)>& done) {
    const int tiles_x = (width + tile_size - 1) / tile_size;
    const int tiles_y = (height + tile_size - 1) / tile_size;
    const auto count = static_cast<size_t>(tiles_x) * static_cast<size_t>(tiles_y);
    parallel_indices(count, threads, [&](size_t k) {
        const int t = static_cast<int>(k);
        Tile tile;
        tile.x0 = (t % tiles_x) * tile_size;
        tile.y0 = (t / tiles_x) * tile_size;
        tile.x1 = std::min(tile.x0 + tile_size, width);
        tile.y1 = std::min(tile.y0 + tile_size, height);
        body(tile);
        if (done) done((tile.x1 - tile.x0) * (tile.y1 - tile.y0));
    });
}

}  // namespace svetlo
