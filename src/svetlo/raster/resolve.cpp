// Stage 7: the resolve (the mean of a pixel's samples, accumulated over the sample passes)
// and the wireframe overlay (Bresenham's or Wu's lines, lines.h) on the resolved colours.
#include <algorithm>

#include "svetlo/raster/fragment.h"
#include "svetlo/raster/lines.h"

namespace svetlo::raster {

void draw_wireframe(const FrameState& f, const Tile& tile, TileBuffers& buf, int S) {
    const WireframeMode algo = f.scene->render.raster.wireframe;
    Color wire = f.scene->render.raster.wireframe_color;
    int tw = tile.x1 - tile.x0;
    size_t ti = static_cast<size_t>(tile.y0 / kTile) * f.tiles_x + tile.x0 / kTile;
    for (const PassGeometry::Bins& bins : f.bins) {
        for (uint32_t n = bins.start[ti]; n < bins.start[ti + 1]; ++n) {
            const SetupTriangle& t = f.tri(bins.ids[n]);
            for (int e = 0; e < 3; ++e) {
                int a = e, b = (e + 1) % 3;
                vec2 pa = vec2(t.x[a], t.y[a]) / static_cast<float>(kSubpixel);
                vec2 pb = vec2(t.x[b], t.y[b]) / static_cast<float>(kSubpixel);
                auto plot = [&](int i, int j, float coverage, float s) {
                    if (i < tile.x0 || i >= tile.x1 || j < tile.y0 || j >= tile.y1) return;
                    size_t pixel = static_cast<size_t>(j - tile.y0) * tw + (i - tile.x0);
                    float z = t.z[a] + s * (t.z[b] - t.z[a]), deepest = -kInfinity;
                    for (int k = 0; k < S; ++k)
                        deepest = std::max(deepest, buf.depth[pixel * S + k]);
                    if (z > deepest + 1e-4f * std::abs(deepest)) return;
                    buf.color[pixel] += std::min(coverage, 1.0f) * (wire - buf.color[pixel]);
                };
                if (algo == WireframeMode::Wu)
                    draw_line_wu(pa, pb, plot);
                else
                    draw_line_bresenham(pa, pb, plot);
            }
        }
    }
}

void accumulate_samples(const TileBuffers& buf, size_t pixels, int samples, Color* out) {
    for (size_t pixel = 0; pixel < pixels; ++pixel) {
        Color sum(0.0f);
        for (int s = 0; s < samples; ++s)
            sum += buf.sample_color[pixel * static_cast<size_t>(samples) + static_cast<size_t>(s)];
        out[pixel] += sum;
    }
}

void resolve_tile(const FrameState& f, const Tile& tile, int spp, int last_pass_samples,
                  const AovTargets& targets, TileBuffers& buf, Image& color) {
    const int tw = tile.x1 - tile.x0;
    const size_t pixels = static_cast<size_t>(tw) * (tile.y1 - tile.y0);
    float inv = 1.0f / static_cast<float>(spp);
    for (size_t pixel = 0; pixel < pixels && spp > 1; ++pixel) buf.color[pixel] *= inv;
    if (f.scene->render.raster.wireframe != WireframeMode::None)
        draw_wireframe(f, tile, buf, last_pass_samples);
    for (int j = tile.y0; j < tile.y1; ++j) {
        auto row = static_cast<std::ptrdiff_t>(j - tile.y0) * tw;
        std::copy_n(buf.color.begin() + row, tw, &color.at(tile.x0, j));
        for (int i = 0; targets.any && i < tw; ++i)
            targets.write(tile.x0 + i, j, buf.aov[static_cast<size_t>(row + i)].mean(spp));
    }
}

}  // namespace svetlo::raster
