#include "svetlo/shading/texture.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace svetlo {

namespace {

int wrap_index(int i, int n, TextureWrap wrap) {
    if (wrap == TextureWrap::Clamp) return std::clamp(i, 0, n - 1);
    if (wrap == TextureWrap::Mirror) {
        // Period 2n: the texels in order, then in reverse (the edge texel twice, as GL does).
        const int period = 2 * n;
        int m = i % period;
        if (m < 0) m += period;
        return m < n ? m : period - 1 - m;
    }
    // A power of two (most textures, every mip level of one): the low bits, which two's
    // complement makes i mod n for negative i too; no division.
    if ((n & (n - 1)) == 0) return i & (n - 1);
    int m = i % n;
    return m < 0 ? m + n : m;
}

/// Texel (i, j) with j counted from the bottom row.
Color texel(const TextureImage& image, int i, int j, TextureWraps wrap) {
    int x = wrap_index(i, image.width(), wrap.u);
    int y = wrap_index(j, image.height(), wrap.v);
    return image.texel(x, image.height() - 1 - y);
}

/// Keeps huge texture coordinates from overflowing int when converted to texel indices: under
/// 1024 in magnitude, times at most 65536 texels a side (image_io.h), they stay below 2^26.
/// fmod is exact and 1024 an even number of periods, so every wrap mode reads the same texel
/// (fmod only where it changes x: it is a library call, and this runs per lookup).
float tame(float x) {
    if (std::abs(x) < 1024.0f) return x;
    return std::isfinite(x) ? std::fmod(x, 1024.0f) : 0.0f;
}

/// Along an axis of n texels: texel i and the next, wrapped (one division for the two where
/// the texture repeats).
std::pair<int, int> wrap_pair(int i, int n, TextureWrap wrap) {
    if (wrap == TextureWrap::Clamp) return {std::clamp(i, 0, n - 1), std::clamp(i + 1, 0, n - 1)};
    if (wrap == TextureWrap::Mirror) return {wrap_index(i, n, wrap), wrap_index(i + 1, n, wrap)};
    const int a = wrap_index(i, n, wrap);
    return {a, a + 1 == n ? 0 : a + 1};
}

}  // namespace

Color sample_nearest(const TextureImage& image, vec2 uv, TextureWraps wrap) {
    float x = tame(uv.x) * static_cast<float>(image.width());
    float y = tame(uv.y) * static_cast<float>(image.height());
    return texel(image, static_cast<int>(std::floor(x)), static_cast<int>(std::floor(y)), wrap);
}

Color sample_bilinear(const TextureImage& image, vec2 uv, TextureWraps wrap) {
    float x = tame(uv.x) * static_cast<float>(image.width()) - 0.5f;
    float y = tame(uv.y) * static_cast<float>(image.height()) - 0.5f;
    float x0 = std::floor(x), y0 = std::floor(y);
    float fx = x - x0, fy = y - y0;
    // The four texels around (x, y), as texel() finds them, rows counted from the bottom.
    const auto [i0, i1] = wrap_pair(static_cast<int>(x0), image.width(), wrap.u);
    const auto [j0, j1] = wrap_pair(static_cast<int>(y0), image.height(), wrap.v);
    const int top = image.height() - 1;
    return (1.0f - fx) * (1.0f - fy) * image.texel(i0, top - j0) +
           fx * (1.0f - fy) * image.texel(i1, top - j0) +
           (1.0f - fx) * fy * image.texel(i0, top - j1) + fx * fy * image.texel(i1, top - j1);
}

namespace {

/// The source's colour at uv with the footprint of `lookup`, before the vertex colour.
Color colour_at(const ColorSource& source, vec2 uv, const TextureLookup& lookup) {
    const std::vector<TextureImage>& textures = lookup.images;
    switch (source.kind) {
        case ColorSource::Kind::Constant:
            return source.value;
        case ColorSource::Kind::Checker: {
            float s = source.scale;
            auto parity = static_cast<long long>(std::floor(tame(uv.x * s))) +
                          static_cast<long long>(std::floor(tame(uv.y * s)));
            return (parity & 1) == 0 ? source.a : source.b;
        }
        case ColorSource::Kind::Image: {
            if (source.transformed) {  // KHR_texture_transform: the lookup in mapped coordinates
                TextureLookup mapped = lookup;
                const mat2 linear(source.uv_transform);
                mapped.duv_dx = linear * lookup.duv_dx;
                mapped.duv_dy = linear * lookup.duv_dy;
                ColorSource plain = source;
                plain.transformed = false;
                return colour_at(plain, vec2(source.uv_transform * vec3(uv, 1.0f)), mapped);
            }
            const TextureImage& image = textures[static_cast<size_t>(source.texture)];
            if (source.filter == TextureFilter::Nearest)
                return sample_nearest(image, uv, source.wrap) * source.factor;
            if (source.filter == TextureFilter::Trilinear && lookup.mips) {
                const MipChain& chain = (*lookup.mips)[static_cast<size_t>(source.texture)];
                return sample_trilinear(chain, uv, mip_level(chain, lookup.duv_dx, lookup.duv_dy),
                                        source.wrap) *
                       source.factor;
            }
            if (source.filter == TextureFilter::Anisotropic && lookup.mips) {
                const MipChain& chain = (*lookup.mips)[static_cast<size_t>(source.texture)];
                return sample_anisotropic(chain, uv, lookup.duv_dx, lookup.duv_dy,
                                          source.max_anisotropy, source.wrap) *
                       source.factor;
            }
            return sample_bilinear(image, uv, source.wrap) * source.factor;
        }
    }
    return source.value;
}

}  // namespace

Color eval_color(const ColorSource& source, const Varyings& at,
                 const std::vector<TextureImage>& textures) {
    return eval_color(source, at, TextureLookup{textures});
}

Color eval_color(const ColorSource& source, const Varyings& at, const TextureLookup& lookup) {
    Color c;
    if (source.uv_set == 0) {
        c = colour_at(source, at.uv[0], lookup);
    } else {
        TextureLookup second = lookup;
        second.duv_dx = lookup.duv1_dx;
        second.duv_dy = lookup.duv1_dy;
        c = colour_at(source, at.uv[1], second);
    }
    switch (source.vertex_color) {
        case VertexColor::None:
            return c;
        case VertexColor::Rgb:
            return c * Color(at.color);
        case VertexColor::Alpha:
            return c * at.color.a;
    }
    return c;
}

void eval_colors(const ColorSource& source, const vec2* uv, const vec2* duv_dx, const vec2* duv_dy,
                 size_t count, const TextureLookup& lookup, Color* out) {
    if (source.kind == ColorSource::Kind::Image && source.filter == TextureFilter::Trilinear &&
        lookup.mips && !source.transformed) {
        const MipChain& chain = (*lookup.mips)[static_cast<size_t>(source.texture)];
        constexpr size_t kChunk = 64;
        float lod[kChunk];
        for (size_t first = 0; first < count; first += kChunk) {
            const size_t n = std::min(kChunk, count - first);
            for (size_t k = 0; k < n; ++k)
                lod[k] = mip_level(chain, duv_dx[first + k], duv_dy[first + k]);
            for (size_t k = 0; k < n; ++k)
                out[first + k] =
                    sample_trilinear(chain, uv[first + k], lod[k], source.wrap) * source.factor;
        }
        return;
    }
    for (size_t k = 0; k < count; ++k) {
        TextureLookup at = lookup;
        at.duv_dx = duv_dx[k];
        at.duv_dy = duv_dy[k];
        out[k] = colour_at(source, uv[k], at);
    }
}

}  // namespace svetlo
