// The rasterizer's one entry point for a pass: draw this list of triangles, through these
// camera matrices, with this pipeline state, into these targets. The frame's colour pass
// (raster_engine.cpp) and the passes of the shadow techniques (a depth pass from a light, a
// stencil pass over shadow volumes) and of radiosity (a hemicube's item buffer) are each a
// call or two of it. OpenGL's conventions: the state is that of glDepthFunc(GL_LESS),
// glDepthMask, glCullFace and glStencilFuncSeparate / glStencilOpSeparate.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "svetlo/geometry/triangle_list.h"
#include "svetlo/raster/alpha_test.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/stencil.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// Which faces a pass drops: the side is decided once, by the screen winding (front_facing in
/// edge_function.h), the same rule as shading_frame.h.
enum class CullMode { None, Back, Front };

struct PipelineState {
    bool depth_test = true;   // keep a sample only where it is nearer than the stored depth
    bool depth_write = true;  // store the depth of the samples kept
    CullMode cull = CullMode::None;
    StencilState stencil;  // the stencil test and its per-face operations (off by default)
    // glPolygonOffset's role: the depth tested is moved this fraction of itself farther (the
    // depth key's magnitude), so that a surface drawn again in a later pass, rasterized by
    // another path, is not nearer than itself. Taken by the stencil and no-depth-write path.
    float depth_bias = 0.0f;
    // The item buffer (RenderTargets::primitive) written where samples pass, as glColorMask
    // for the visibility buffer; a pass that writes neither it nor depth may skip samples that
    // would only pass.
    bool write_items = true;
    // The item buffer's number for the list's triangle t: first_item + t, or items[t] where
    // `items` is given (a frame drawn as several lists, instances drawn in place,
    // placed_draws.h, numbers every list's triangles apart). It is also the triangle in a
    // blend's coin, which is then the same in every list that draws the triangle.
    uint32_t first_item = 0;
    const uint32_t* items = nullptr;
    // Alpha's holes (alpha_test.h): a masked or blended triangle's samples are tested; null:
    // every covered sample is drawn.
    const raster::AlphaTest* alpha = nullptr;
};

/// Per-sample buffers that persist from pass to pass, samples x width x height, sample s of
/// pixel (i, j) at ((j * width + i) * samples + s). Depth holds the pipeline's depth key:
/// -1/w for a perspective camera (w the distance along the view axis), window z in [0, 1]
/// for an orthographic one; smaller is nearer, and +infinity is cleared.
struct RenderTargets {
    static constexpr uint32_t kNoPrimitive = ~0u;

    int width = 0, height = 0, samples = 1;
    std::vector<float> depth;
    std::vector<uint8_t> stencil;
    std::vector<uint32_t> primitive;  // the item buffer: the list's triangle per sample, or
                                      // kNoPrimitive

    /// Sizes and clears the buffers a pass will use (depth to +infinity, stencil to 0, the
    /// item buffer to kNoPrimitive). samples: 1 (the pixel centre) up to 16.
    void clear(int w, int h, int samples_per_pixel = 1, bool with_stencil = false,
               bool with_primitives = false);
    size_t index(int i, int j, int s = 0) const {
        return (static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)) *
                   static_cast<size_t>(samples) +
               static_cast<size_t>(s);
    }
};

/// The pipeline's working memory for passes (transformed vertices, set-up triangles), kept from
/// pass to pass as a GL context keeps its buffers: a pass given one reuses its pages instead
/// of faulting in new ones (for a million triangles, most of a depth pass's time). One pass
/// at a time per PassMemory.
class PassMemory {
public:
    PassMemory();
    ~PassMemory();
    PassMemory(PassMemory&&) noexcept;
    PassMemory& operator=(PassMemory&&) noexcept;

    struct Buffers;  // pipeline.h
    std::unique_ptr<Buffers> buffers;
};

/// Rasterizes `list` as `camera` sees it (camera.width x camera.height must match the
/// targets), with `state`, into `targets`: depth (tested and written as the state says),
/// stencil (when the state enables it), and the item buffer (when it is sized). Samples lie
/// at the pixel centre for one sample per pixel, else on the frame's stratified pattern of
/// `seed`. Parallel over 64 x 64 tiles: the result is the same on any thread count.
void draw_pass(const TriangleList& list, const CameraMatrices& camera, const PipelineState& state,
               RenderTargets& targets, int threads, uint64_t seed = 0,
               PassMemory* memory = nullptr);

}  // namespace svetlo
