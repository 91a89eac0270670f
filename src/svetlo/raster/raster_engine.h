// The rasterization pipeline in software (`"engine": "raster"`), model to pixel:
//
//   1. tessellate every object in its own space (geometry/tessellate.h);
//   2. vertex stage: model, view and projection matrices to clip space, normals by the
//      inverse transpose, Gouraud lighting at the vertices; vertices inside the clip volume
//      are divided by w, put through the viewport and snapped to 1/256 pixel once here;
//   3. primitive assembly: clipping in homogeneous coordinates (clipper.h) of triangles
//      with a vertex outside (their pieces projected the same way), screen area and
//      back-face culling (render.cull), bounds;
//   4. binning: each triangle is listed in the 64 x 64 pixel tiles its bounds touch, in
//      submission order (or back to front for the painter's algorithm), chunk by chunk right
//      after the chunk's setup;
//   5. per tile, in parallel: edge-function rasterization with the top-left rule
//      (edge_function.h) of every sample, the stencil test when a pass uses it (stencil.h),
//      the depth test, and a visibility buffer (the nearest triangle per sample, and for
//      small triangles its screen barycentrics; Burns and Hunt, "The Visibility Buffer",
//      JCGT 2013);
//   6. shading of the visible samples only: flat (one colour per face), Gouraud (vertex
//      colours, interpolated), Phong (normals interpolated, lit per sample), the depth and
//      normal views, or the overdraw count; perspective-correct interpolation of every
//      attribute; textures with nearest, bilinear or trilinear (mipmapped) filtering; MSAA
//      shades once per pixel and triangle, supersampling once per sample;
//   7. resolve (the mean of the samples) and the wireframe overlay (Bresenham or Wu lines).
//
// The same lighting code as the ray tracer, without occlusion: visibility is 1 until the
// shadow techniques arrive. docs/raster.md has the details and pictures.
#pragma once

#include <memory>

#include "svetlo/raster/camera_matrices.h"
#include "svetlo/scene/renderer.h"

namespace svetlo {

/// Keeps its pipeline's large buffers (vertices, set-up triangles) from one frame to the next,
/// as a GL context keeps its buffers: one frame at a time per renderer.
class RasterRenderer final : public Renderer {
public:
    RasterRenderer();
    ~RasterRenderer() override;
    RenderResult render(const Scene& scene, const RenderOptions& options) override;

    struct Buffers;

private:
    std::unique_ptr<Buffers> buffers_;
};

/// The camera matrices the rasterizer uses for `scene` (near and far around what it draws).
CameraMatrices raster_camera(const Scene& scene);

}  // namespace svetlo
