// The rasterizer's shadow techniques (render.shadows; docs/shadows.md). Each gives every
// light of the light set its own mask, the visibility V of each of its samples, and the
// shading multiplies that light's term by it: L = Le + ka Ia + sum f E cos V (direct_light.h).
// The finished image is never darkened afterwards, which would be wrong wherever two lights
// overlap.
//
//   raytraced  shadow rays from each visible sample through a BVH of the drawn triangles
//              (shadow_raytraced.cpp): the ground truth inside the rasterizer
//   map        depth maps from each caster, with bias, PCF and PCSS (shadow_maps.cpp)
//   volume     stencil shadow volumes, z-fail (shadow_volumes.cpp)
//   planar     projected shadows on planar receivers, through the stencil (planar_shadows.cpp)
//
// Every technique answers one question, whether caster k (shadow_casters.h) lights a sample,
// and fill_masks turns the answers into the masks, the same way for all of them.
#pragma once

#include <memory>
#include <vector>

#include "svetlo/core/image.h"
#include "svetlo/geometry/occluder_cube.h"
#include "svetlo/raster/pipeline.h"
#include "svetlo/raster/shadow_casters.h"

namespace svetlo::raster {

/// A visible sample as the shadow techniques see it: its world position, the unit geometric
/// normal of the side the camera sees, and where it lies in the frame.
struct ShadowSample {
    vec3 p{0.0f}, n{0.0f};
    int pass = 0;      // the frame's sample pass
    int i = 0, j = 0;  // the pixel
    int s = 0;         // the sample within the pass
    // The triangle of the draw list it lies on (FrameState::source), or kUnknown.
    static constexpr uint32_t kUnknown = ~0u;
    uint32_t triangle = kUnknown;
};

/// Where sample s of pixel (i, j) lies in a mask of a frame `width` pixels wide, `samples`
/// samples a pixel, pixel after pixel along the rows (StencilMasks' masks, screen_mask()).
inline size_t frame_sample(int width, int samples, int i, int j, int s) {
    return (static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)) *
               static_cast<size_t>(samples) +
           static_cast<size_t>(s);
}

class ShadowTechniqueState {
public:
    virtual ~ShadowTechniqueState() = default;
    const std::vector<ShadowCaster>& casters() const { return casters_; }
    /// How much of caster k's light reaches the sample, from 0 (shadowed) to 1 (lit). Called
    /// only for casters the sample faces; concurrently from many tiles.
    virtual float lit(size_t k, const ShadowSample& sample) const = 0;
    /// lit() of caster k for samples[at[m]], m < count, into out[m]: one sample after the
    /// other, or faster where a technique overrides it (independent lookups in flight
    /// together).
    virtual void lit_many(size_t k, const ShadowSample* samples, const uint32_t* at, size_t count,
                          float* out) const {
        for (size_t m = 0; m < count; ++m) out[m] = lit(k, samples[at[m]]);
    }
    /// An occluder cube of caster k (geometry/occluder_cube.h), or null: a sample it calls
    /// clear is lit (1) by caster k, and fill_masks asks lit_many only for the others.
    virtual const OccluderCube* occluders(size_t /*k*/) const { return nullptr; }
    /// Whether lit() reads the sample's position and normal (false: only where it lies in the
    /// frame, as the stencil techniques' masks).
    virtual bool needs_surface() const { return true; }
    /// A screen-space technique's answers for caster k over sample pass `pass`: one byte per
    /// sample (1 lit, 0 shadowed), pixel after pixel along the rows of the frame; null for a
    /// technique that needs the surface.
    virtual const uint8_t* screen_mask(size_t /*k*/, int /*pass*/) const { return nullptr; }
    /// The debug AOVs (docs/shadows.md): light 0's depth map, with a cube map unfolded, and
    /// the shadow-volume count per pixel; empty images where the technique has none.
    virtual Image shadow_map_image() const { return {}; }
    virtual Image stencil_image() const { return {}; }
    /// A stencil technique's mask of light 0's first caster: per pixel, the fraction of its
    /// samples in shadow (the planar AOV: where the projected shadows land).
    virtual Image mask_image() const { return {}; }

protected:
    std::vector<ShadowCaster> casters_;
};

/// The stencil techniques' state (volumes, planar projection): one byte per caster and sample
/// of each sample pass of a width x height frame, 1 where the caster lights the sample, read
/// back by the sample's place in the frame.
class StencilMasks : public ShadowTechniqueState {
public:
    bool needs_surface() const override { return false; }
    float lit(size_t k, const ShadowSample& at) const override;
    const uint8_t* screen_mask(size_t k, int pass) const override {
        return lit_[k][static_cast<size_t>(pass)].data();
    }
    Image mask_image() const override;

protected:
    /// For casters_ (set before) over `passes`: refuses with an Error naming
    /// render.area_shadow_points what would pass the memory limit, counting `working` more
    /// bytes per sample for the passes themselves. `what` names the technique's masks.
    void reserve(const Scene& scene, int width, int height,
                 const std::vector<SamplePattern>& passes, uint64_t working, const char* what);

    int width_ = 0, height_ = 0;
    std::vector<int> samples_per_pass_;
    std::vector<std::vector<std::vector<uint8_t>>> lit_;  // per caster, per pass, per sample
};

/// The length of the diagonal of a scene's bounds (1 when they are empty), m: the scale of the
/// techniques' small offsets.
float scene_diameter(const Bounds3& bounds);

/// The state of the scene's technique for this frame (its maps, volumes or stencil masks),
/// made after the colour pass's setup (f.cam, f.lights); null for `none`. `passes`: the
/// frame's sample passes; `memory`: the pipeline memory its passes reuse. Throws Error for
/// settings it cannot honour (a memory limit).
std::unique_ptr<ShadowTechniqueState> make_shadow_technique(
    const Scene& scene, const TriangleList& list, const FrameState& f,
    const std::vector<SamplePattern>& passes, int threads, PassMemory* memory);

/// fill_masks' working memory, kept by each thread from tile to tile.
struct MaskScratch {
    std::vector<ShadowSample> samples;  // the tile's samples that need a mask
    std::vector<uint32_t> index;        // each one's index in the tile
    std::vector<uint32_t> facing;       // those that face the caster at hand
    std::vector<float> lit;             // its answers for them
    std::vector<float> sum, count;      // per sample, for one source: the answers' sum, number
    std::vector<const uint8_t*> masks;  // a screen-space technique's, per caster
};

/// Fills buf.visibility (one row of the tile's samples per source of the light set) for the
/// tile's samples of sample pass `pass`, after its rasterization: for each visible sample and
/// light, the mean of `lit` over the light's casters that the sample faces; 1 where it faces
/// none and where no surface was drawn. `small_left_weights`: the rasterization kept the
/// screen barycentrics of small triangles' samples (buf.l1, buf.l2; one sample per pixel).
void fill_masks(const ShadowTechniqueState& technique, const FrameState& f, const Tile& tile,
                const SamplePattern& sp, int pass, bool small_left_weights, TileBuffers& buf,
                MaskScratch& scratch);

}  // namespace svetlo::raster
