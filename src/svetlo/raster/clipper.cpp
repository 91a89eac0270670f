#include "svetlo/raster/clipper.h"

namespace svetlo {

namespace {

ClipVertex lerp(const ClipVertex& a, const ClipVertex& b, float t) {
    ClipVertex r;
    r.clip = a.clip + t * (b.clip - a.clip);
    r.world = a.world + t * (b.world - a.world);
    r.normal = a.normal + t * (b.normal - a.normal);
    r.uv = a.uv + t * (b.uv - a.uv);
    r.uv1 = a.uv1 + t * (b.uv1 - a.uv1);
    r.vertex_color = a.vertex_color + t * (b.vertex_color - a.vertex_color);
    r.tangent = vec4(vec3(a.tangent) + t * (vec3(b.tangent) - vec3(a.tangent)), a.tangent.w);
    r.color = a.color + t * (b.color - a.color);
    r.wh = a.wh + t * (b.wh - a.wh);
    return r;
}

/// Keeps the part of `in` where dist(v) >= 0 (dist linear in clip space).
template <class Dist>
void clip_plane(const ClipPolygon& in, ClipPolygon& out, Dist&& dist) {
    out.count = 0;
    for (int k = 0; k < in.count; ++k) {
        const ClipVertex& a = in.v[static_cast<size_t>(k)];
        const ClipVertex& b = in.v[static_cast<size_t>((k + 1) % in.count)];
        float da = dist(a.clip), db = dist(b.clip);
        if (da >= 0.0f) out.v[static_cast<size_t>(out.count++)] = a;
        if ((da >= 0.0f) != (db >= 0.0f)) {
            // Always interpolate from the inside vertex, so both triangles sharing an edge
            // compute the same new vertex.
            ClipVertex v = da >= 0.0f ? lerp(a, b, da / (da - db)) : lerp(b, a, db / (db - da));
            out.v[static_cast<size_t>(out.count++)] = v;
        }
    }
}

}  // namespace

ClipPolygon clip_triangle(const ClipVertex& a, const ClipVertex& b, const ClipVertex& c, float gx,
                          float gy) {
    ClipPolygon p, q;
    p.v[0] = a;
    p.v[1] = b;
    p.v[2] = c;
    p.count = 3;
    clip_plane(p, q, [](const vec4& v) { return v.z + v.w; });  // near
    clip_plane(q, p, [](const vec4& v) { return v.w - v.z; });  // far
    clip_plane(p, q, [gx](const vec4& v) { return gx * v.w - v.x; });
    clip_plane(q, p, [gx](const vec4& v) { return gx * v.w + v.x; });
    clip_plane(p, q, [gy](const vec4& v) { return gy * v.w - v.y; });
    clip_plane(q, p, [gy](const vec4& v) { return gy * v.w + v.y; });
    for (int k = 0; k < p.count; ++k) {
        ClipVertex& v = p.v[static_cast<size_t>(k)];
        v.invw = 1.0f / v.clip.w;
    }
    return p;
}

}  // namespace svetlo
