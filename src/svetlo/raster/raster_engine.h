// The rasterization pipeline in software (`"engine": "raster"`), model to pixel, one file per
// stage (pipeline.h lists them):
//
//   1. tessellate every object in its own space (geometry/tessellate.h; raster_engine.cpp);
//   2. vertex stage (vertex_stage.cpp): model, view and projection matrices to clip space,
//      normals by the inverse transpose, Gouraud lighting at the vertices; vertices inside the
//      clip volume are divided by w, put through the viewport and snapped to 1/256 pixel;
//   3. primitive assembly (setup_binning.cpp): clipping in homogeneous coordinates
//      (clipper.h) of triangles with a vertex outside, screen area, the side the camera sees
//      and culling, bounds;
//   4. binning (setup_binning.cpp): each triangle is listed in the 64 x 64 pixel tiles its
//      bounds touch, in submission order (or back to front for the painter's algorithm);
//   5. per tile, in parallel (rasterize.cpp): edge-function rasterization with the top-left
//      rule (edge_function.h) of every sample, the stencil test when a pass uses it
//      (stencil.h), the depth test, and a visibility buffer (the nearest triangle per sample;
//      Burns and Hunt, "The Visibility Buffer", JCGT 2013);
//   6. shading of the visible samples only (fragment.cpp, fast_shading.cpp): flat, Gouraud,
//      Phong, the depth and normal views, or the overdraw count; perspective-correct
//      interpolation; filtered textures; MSAA shades once per pixel and triangle;
//   7. resolve (resolve.cpp): the mean of the samples and the wireframe overlay.
//
// A frame is a sequence of passes through one entry point (draw_pass.h): the shadow
// technique's passes (shadow_masks.h: depth maps, a depth pass and stencil volumes, planar
// projections), then the colour pass, whose tiles fill each light's mask after their
// rasterization. The lighting is shading/'s, as in the ray tracer, each light's term times its
// mask. docs/raster.md and docs/shadows.md have the details and pictures.
#pragma once

#include <memory>

#include "svetlo/geometry/triangle_list.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/scene/renderer.h"

namespace svetlo {

namespace raster {
struct FrameState;
class PlacedDraws;
}  // namespace raster

/// Keeps its pipeline's large buffers (vertices, set-up triangles) from one frame to the next,
/// as a GL context keeps its buffers: one frame at a time per renderer.
class RasterRenderer final : public Renderer {
public:
    RasterRenderer();
    ~RasterRenderer() override;
    Capabilities capabilities() const override {
        return {.name = "raster",
                .whole_frame = true,
                .debug_aovs = {"shadow_map", "stencil", "planar"}};
    }
    RenderResult render(const Scene& scene, const RenderOptions& options) override;

    struct Buffers;

private:
    /// The frame drawn once, and each of options.windows cut from it.
    RenderResult render_cut_into_windows(const Scene& scene, const RenderOptions& options);
    /// A frame's state made (stage 1 and the shading), in the buffers of the last frame;
    /// returns its triangle list. end_frame keeps the buffers for the next.
    std::shared_ptr<const TriangleList> begin_frame(const Scene& scene,
                                                    const RenderOptions& options,
                                                    raster::FrameState& f);
    void end_frame(raster::FrameState& f);

    std::unique_ptr<Buffers> buffers_;
};

/// The camera matrices the rasterizer uses for `scene` (near and far around what it draws).
CameraMatrices raster_camera(const Scene& scene);
/// The same for the scene's triangle list `list`, already made, and its instances drawn in
/// place (`placed`, when there are: placed_draws.h): the near plane at half the distance from
/// the eye to the nearest plane of a triangle not wholly behind it (or, for a placed part
/// wholly in front, to its box), found on `threads` threads (0: all cores).
CameraMatrices frame_camera(const Scene& scene, const TriangleList& list, int threads = 0,
                            const raster::PlacedDraws* placed = nullptr);

}  // namespace svetlo
