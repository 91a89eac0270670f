// The watertight ray-triangle test of Woop, Benthin and Wald (JCGT 2013): edge functions in a
// ray-aligned sheared space, with a double-precision fallback on edges, so that rays through
// a shared edge or vertex hit exactly one of the triangles that meet there.
#pragma once

#include "svetlo/geometry/ray.h"

namespace svetlo {

/// Returns true and fills t, b1, b2 (barycentrics of v1 and v2) when the ray hits the
/// triangle at 0 < t < tmax.
inline bool intersect_triangle(const Ray& ray, const RayPrecomputed& pre, vec3 v0, vec3 v1, vec3 v2,
                               float tmax, float& t, float& b1, float& b2) {
    const vec3 a = v0 - ray.o, b = v1 - ray.o, c = v2 - ray.o;
    const float ax = a[pre.kx] - pre.sx * a[pre.kz], ay = a[pre.ky] - pre.sy * a[pre.kz];
    const float bx = b[pre.kx] - pre.sx * b[pre.kz], by = b[pre.ky] - pre.sy * b[pre.kz];
    const float cx = c[pre.kx] - pre.sx * c[pre.kz], cy = c[pre.ky] - pre.sy * c[pre.kz];
    float u = cx * by - cy * bx;                // edge function of edge (v1, v2): weight of v0
    float v = ax * cy - ay * cx;                // weight of v1
    float w = bx * ay - by * ax;                // weight of v2
    if (u == 0.0f || v == 0.0f || w == 0.0f) {  // on an edge: decide in double precision
        u = static_cast<float>(static_cast<double>(cx) * by - static_cast<double>(cy) * bx);
        v = static_cast<float>(static_cast<double>(ax) * cy - static_cast<double>(ay) * cx);
        w = static_cast<float>(static_cast<double>(bx) * ay - static_cast<double>(by) * ax);
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
    float det = u + v + w;
    if (det == 0.0f) return false;
    const float az = pre.sz * a[pre.kz], bz = pre.sz * b[pre.kz], cz = pre.sz * c[pre.kz];
    float tt = (u * az + v * bz + w * cz) / det;
    if (!(tt > 0.0f && tt < tmax)) return false;
    t = tt;
    b1 = v / det;
    b2 = w / det;
    return true;
}

}  // namespace svetlo
