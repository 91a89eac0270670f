#include "svetlo/raster/draw_pass.h"

#include <algorithm>

#include "svetlo/core/parallel.h"
#include "svetlo/raster/pipeline.h"
#include "svetlo/raster/rasterize_kernels.h"

namespace svetlo {

void RenderTargets::clear(int w, int h, int samples_per_pixel, bool with_stencil,
                          bool with_primitives) {
    width = w;
    height = h;
    samples = std::clamp(samples_per_pixel, 1, raster::kMaxSamplesPerPass);
    size_t n = static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(samples);
    depth.assign(n, kInfinity);
    stencil.assign(with_stencil ? n : 0, 0);
    primitive.assign(with_primitives ? n : 0, kNoPrimitive);
}

namespace raster {

void prepare_pass(const TriangleList& list, const CameraMatrices& camera,
                  const PipelineState& state, FrameState& f, int threads) {
    f.cam = camera;
    f.cull = state.cull;
    vertex_stage(list, f, threads);
    assemble(list, f, threads);
}

/// The tight bounds of a pattern's sample offsets in their pixel (setup_triangle's bounds).
void fit_sample_bounds(PassGeometry& f, const std::vector<SamplePattern>& passes) {
    auto& b = f.sample_bounds;
    b = {glm::ivec2(kSubpixel), glm::ivec2(-1), 0};
    for (const SamplePattern& sp : passes) {
        for (int k = 0; k < sp.count; ++k) {
            b.lo = glm::min(b.lo, glm::ivec2(sp.ox[k], sp.oy[k]));
            b.hi = glm::max(b.hi, glm::ivec2(sp.ox[k], sp.oy[k]));
        }
    }
}

}  // namespace raster

PassMemory::PassMemory() : buffers(std::make_unique<Buffers>()) {}
PassMemory::~PassMemory() = default;
PassMemory::PassMemory(PassMemory&&) noexcept = default;
PassMemory& PassMemory::operator=(PassMemory&&) noexcept = default;

namespace raster {

void draw_samples(const TriangleList& list, const CameraMatrices& camera,
                  const PipelineState& state, RenderTargets& targets, int threads,
                  const SamplePattern& sp, PassMemory* memory) {
    const int S = targets.samples;
    FrameState f;
    if (memory) {  // the last pass's memory, given back below
        f.vertices = std::move(memory->buffers->vertices);
        f.screen = std::move(memory->buffers->screen);
        f.tris = std::move(memory->buffers->tris);
        f.depth_tris = std::move(memory->buffers->depth_tris);
    }
    fit_sample_bounds(f, {sp});
    const bool stencil = state.stencil.enabled && !targets.stencil.empty();
    const bool items = !targets.primitive.empty() && state.write_items;
    // (Not with alpha: the depth-only road draws whole triangles.)
    f.depth_only = S == 1 && state.depth_test && state.depth_write && !stencil && !items &&
                   !(state.alpha && state.alpha->any());
    prepare_pass(list, camera, state, f, threads);
    PerWorker<TileBuffers> buffers(threads);
    parallel_tiles(
        targets.width, targets.height, kTile, threads,
        [&](const Tile& tile) {
            TileBuffers& buf = buffers.local();
            const int tw = tile.x1 - tile.x0;
            const size_t pixels = static_cast<size_t>(tw) * (tile.y1 - tile.y0);
            buf.reset(pixels * static_cast<size_t>(S), pixels, false, stencil);
            // The tile's part of the targets in, rasterized, and out (rows of tw x S samples).
            const size_t row = static_cast<size_t>(tw) * S;
            for (int j = tile.y0; j < tile.y1; ++j) {
                size_t from = targets.index(tile.x0, j),
                       to = static_cast<size_t>(j - tile.y0) * row;
                std::copy_n(targets.depth.begin() + from, row, buf.depth.begin() + to);
                if (stencil)
                    std::copy_n(targets.stencil.begin() + from, row, buf.stencil.begin() + to);
            }
            // The nearest stored depth per 8 x 8 block, for a pass that tests depth without
            // writing it (rasterize_stencil skips blocks its triangles are wholly in front of).
            buf.block_near.clear();
            if (state.depth_test && !state.depth_write) {
                constexpr int kB = TileBuffers::kBlock;
                const size_t blocks = static_cast<size_t>(kTile / kB) * (kTile / kB);
                buf.block_near.assign(blocks, kInfinity);
                buf.block_far.assign(blocks, -kInfinity);
                // Each block's rows are runs of kB x S samples.
                const size_t run = static_cast<size_t>(kB) * S;
                for (int j = tile.y0; j < tile.y1; ++j) {
                    const float* d = buf.depth.data() + static_cast<size_t>(j - tile.y0) * row;
                    for (int i = 0; i < tw; i += kB) {
                        const size_t b = static_cast<size_t>((j - tile.y0) / kB) * (kTile / kB) +
                                         static_cast<size_t>(i / kB);
                        const float* z = d + static_cast<size_t>(i) * S;
                        const size_t n = std::min(run, row - static_cast<size_t>(i) * S);
                        raster::kernel::depth_range(z, n, buf.block_near[b], buf.block_far[b]);
                    }
                }
                buf.tile_near = *std::min_element(buf.block_near.begin(), buf.block_near.end());
                buf.tile_far = *std::max_element(buf.block_far.begin(), buf.block_far.end());
            }
            PipelineState tile_state = state;
            tile_state.stencil.enabled = stencil;
            // Without an item buffer, a pass that writes depth keeps no triangle ids or
            // barycentrics either (a shadow map's depth pass). The stencil and no-write path
            // keeps its own reading of write_items.
            if (!stencil && state.depth_write) tile_state.write_items = items;
            rasterize_tile(f, tile, sp, tile_state, buf);
            for (int j = tile.y0; j < tile.y1; ++j) {
                size_t to = targets.index(tile.x0, j),
                       from = static_cast<size_t>(j - tile.y0) * row;
                if (state.depth_write)
                    std::copy_n(buf.depth.begin() + from, row, targets.depth.begin() + to);
                if (stencil)
                    std::copy_n(buf.stencil.begin() + from, row, targets.stencil.begin() + to);
                for (size_t k = 0; k < row && items; ++k) {
                    uint32_t id = buf.tri[from + k];
                    if (id == kNone) continue;
                    const uint32_t t = f.source(id);
                    targets.primitive[to + k] = state.items ? state.items[t] : state.first_item + t;
                }
            }
        },
        {});
    if (memory) {
        memory->buffers->vertices = std::move(f.vertices);
        memory->buffers->screen = std::move(f.screen);
        memory->buffers->tris = std::move(f.tris);
        memory->buffers->depth_tris = std::move(f.depth_tris);
    }
}

}  // namespace raster

void draw_pass(const TriangleList& list, const CameraMatrices& camera, const PipelineState& state,
               RenderTargets& targets, int threads, uint64_t seed, PassMemory* memory) {
    const int S = targets.samples;
    raster::draw_samples(list, camera, state, targets, threads,
                         raster::sample_pattern(S, seed, 0, S), memory);
}

}  // namespace svetlo
