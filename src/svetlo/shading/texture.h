// Evaluating a material colour at texture coordinates (u, v). Image rows follow OpenGL:
// v = 0 is the bottom row of the image file. Texel centres lie at ((i + 1/2)/W, (j + 1/2)/H).
#pragma once

#include <vector>

#include "svetlo/scene/scene.h"
#include "svetlo/shading/mipmap.h"

namespace svetlo {

/// Nearest texel: the value of the texel that contains (u, v).
Color sample_nearest(const TextureImage& image, vec2 uv, TextureWraps wrap);
/// Bilinear interpolation between the four texel centres around (u, v).
Color sample_bilinear(const TextureImage& image, vec2 uv, TextureWraps wrap);

/// The colour of `source` at a point: read at the point's texture coordinate set
/// `source.uv_set`, times its vertex colour where `source.vertex_color` says so. Ray-traced
/// engines have no footprint, so trilinear filtering samples the finest mip level, which is
/// bilinear filtering.
Color eval_color(const ColorSource& source, const Varyings& at,
                 const std::vector<TextureImage>& textures);

/// The same with a pixel footprint and mip chains (the rasterizer): trilinear filtering
/// then picks the mip level from the footprint of the set read.
Color eval_color(const ColorSource& source, const Varyings& at, const TextureLookup& lookup);

/// eval_color at `count` points of one surface for a source that reads set 0 and no vertex
/// colour (the rasterizer's fast path takes no other): uv[k] with the footprint duv_dx[k],
/// duv_dy[k] (`lookup`'s are not read), into out[k]. The same colours as one by one; a
/// trilinear image's levels of detail are made first for all the points, so that their
/// square roots and logarithms overlap instead of each waiting on the last lookup.
void eval_colors(const ColorSource& source, const vec2* uv, const vec2* duv_dx, const vec2* duv_dy,
                 size_t count, const TextureLookup& lookup, Color* out);

}  // namespace svetlo
