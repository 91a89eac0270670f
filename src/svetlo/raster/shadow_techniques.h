// The four shadow techniques' factories (shadow_masks.h says what each is). Internal to the
// rasterizer.
#pragma once

#include <memory>
#include <vector>

#include "svetlo/raster/shadow_masks.h"

namespace svetlo::raster {

/// Shadow rays from each sample to each caster (the VPLs of lights with area), through the
/// BVH and occluder cubes of `caches` when an earlier frame made them.
std::unique_ptr<ShadowTechniqueState> make_raytraced_shadows(const Scene& scene,
                                                             const TriangleList& list,
                                                             const FrameShading& f,
                                                             const FrameCaches& caches, int threads,
                                                             PassMemory* memory);
/// Depth maps from each caster, made now (one depth pass per map).
std::unique_ptr<ShadowTechniqueState> make_shadow_maps(const Scene& scene, const TriangleList& list,
                                                       const FrameState& f, int threads,
                                                       PassMemory* memory);
/// Stencil shadow volumes: per sample pass, a depth pass, then per caster a stencil pass.
std::unique_ptr<ShadowTechniqueState> make_shadow_volumes(const Scene& scene,
                                                          const TriangleList& list,
                                                          const FrameState& f,
                                                          const std::vector<SamplePattern>& passes,
                                                          int threads, PassMemory* memory);
/// Projected shadows: per sample pass and caster, a stencil pass per planar receiver.
std::unique_ptr<ShadowTechniqueState> make_planar_shadows(const Scene& scene,
                                                          const TriangleList& list,
                                                          const FrameState& f,
                                                          const std::vector<SamplePattern>& passes,
                                                          int threads, PassMemory* memory);

}  // namespace svetlo::raster
