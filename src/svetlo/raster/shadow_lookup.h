// Where a receiver's sample looks a shadow map up (docs/shadows.md, docs/kernels.md): the
// pixel it falls on, its distance in the map's terms (DepthMap::receiver), the slope-scaled
// bias there, and whether it falls on the map at all. The normal offset moves the lookup point
// off the surface by `normal_offset` texels first. Two forms of one rule: twin::shadow_lookup
// states it one sample at a time; sse::shadow_lookup4 (SVETLO_SIMD) makes the same answers
// for four samples at once (tests/raster/kernel_twins_test.cpp).
#pragma once

#include "svetlo/raster/shadow_casters.h"
#include "svetlo/raster/shadow_map_filters.h"
#include "svetlo/raster/shadow_masks.h"
#include "svetlo/scene/scene.h"

namespace svetlo::raster {

struct ShadowLookup {
    float x = 0.0f, y = 0.0f;  // the map's pixel position (continuous)
    float receiver = 0.0f;     // the sample's distance, as the map stores distances (m)
    float slope = 0.0f;        // the slope-scaled bias there (m)
    bool on_map = false;       // false outside a spot's cone or beyond the fitted view
};

namespace twin {
/// The lookup of sample s on map m of caster c.
ShadowLookup shadow_lookup(const ShadowMapSettings& settings, const ShadowCaster& c,
                           const DepthMap& m, const ShadowSample& s);
}  // namespace twin

#if SVETLO_SIMD
namespace sse {
/// twin::shadow_lookup of s[0..3], four lanes.
void shadow_lookup4(const ShadowMapSettings& settings, const ShadowCaster& c, const DepthMap& m,
                    const ShadowSample* const s[4], ShadowLookup out[4]);
}  // namespace sse
#endif

}  // namespace svetlo::raster
