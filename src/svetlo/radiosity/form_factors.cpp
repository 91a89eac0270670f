#include "svetlo/radiosity/form_factors.h"

#include <cmath>

#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/geometry/ray.h"

namespace svetlo {

float point_triangle_form_factor(vec3 x, vec3 n, const vec3 v[3]) {
    // Clip the triangle to the half-space above x's tangent plane (Sutherland-Hodgman): what
    // lies below it sends nothing to this side.
    vec3 poly[4];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
        const vec3 a = v[k], b = v[(k + 1) % 3];
        const float da = glm::dot(n, a - x), db = glm::dot(n, b - x);
        if (da >= 0.0f) poly[count++] = a;
        if ((da >= 0.0f) != (db >= 0.0f) && count < 4) {
            poly[count++] = a + (da / (da - db)) * (b - a);
        }
    }
    if (count < 3) return 0.0f;
    double sum = 0.0;
    for (int k = 0; k < count; ++k) {
        vec3 r0 = glm::normalize(poly[k] - x), r1 = glm::normalize(poly[(k + 1) % count] - x);
        vec3 c = glm::cross(r0, r1);
        float len = glm::length(c);
        if (!(len > 1e-12f)) continue;
        float gamma = std::atan2(len, glm::dot(r0, r1));
        sum += static_cast<double>(gamma) * glm::dot(n, c) / len;
    }
    return static_cast<float>(std::abs(sum) / (2.0 * kPi));
}

bool segment_visible(const Accel& accel, vec3 x, vec3 nx, vec3 y, vec3 ny) {
    vec3 d = y - x;
    vec3 o = offset_ray_origin(x, nx, d);
    vec3 e = offset_ray_origin(y, ny, -d);
    Ray ray{o, e - o, 1.0f};
    return !accel.occluded(ray);
}

FormFactor form_factor(const FormFactorContext& ctx, uint32_t r, uint32_t s, uint64_t seed,
                       uint64_t& rays) {
    const ElementTree& tree = ctx.tree;
    const ElementNode& rn = tree.node(r);
    const ElementNode& sn = tree.node(s);
    FormFactor out;
    if (!(rn.area > 0.0f) || !(sn.area > 0.0f)) return out;
    const vec3 x = rn.centroid;
    const vec3 n = tree.normal(r);
    const vec3 ns = facing_normal(tree, s, x);
    Rng rng(mix64(seed), mix64((uint64_t{r} << 32) ^ s));
    const int count = ctx.samples;
    const float piece = sn.area / static_cast<float>(count);
    int free[2] = {0, 0}, facing[2] = {0, 0};
    double sum[2] = {0.0, 0.0};
    for (int k = 0; k < count; ++k) {
        vec2 b = sample_triangle(stratified_sample(k, count, rng.next_2d()));
        vec3 y = b.x * sn.p[0] + b.y * sn.p[1] + (1.0f - b.x - b.y) * sn.p[2];
        vec3 d = y - x;
        float d2 = glm::dot(d, d);
        if (!(d2 > 0.0f)) continue;
        vec3 w = d / std::sqrt(d2);
        float cos_n = glm::dot(n, w), cos_s = -glm::dot(ns, w);
        if (cos_n == 0.0f || cos_s <= 0.0f) continue;  // the sides do not face here
        const int side = cos_n > 0.0f ? 0 : 1;
        ++facing[side];
        ++rays;
        if (!segment_visible(ctx.accel, x, side == 0 ? n : -n, y, ns)) continue;
        ++free[side];
        sum[side] += std::abs(cos_n) * cos_s * piece / (kPi * d2 + piece);
    }
    const int all_facing = facing[0] + facing[1], all_free = free[0] + free[1];
    out.visibility = all_facing == 0 ? 0.0f : static_cast<float>(all_free) / all_facing;
    for (int side = 0; side < 2; ++side) {
        if (ctx.method == FormFactorMethod::Raycast) {
            out.F[side] = static_cast<float>(sum[side]);
            continue;
        }
        // The side's own visibility, or all rays' where none went to this side.
        float v = facing[side] > 0 ? static_cast<float>(free[side]) / facing[side] : out.visibility;
        if (v > 0.0f) out.F[side] = point_triangle_form_factor(x, side == 0 ? n : -n, sn.p) * v;
    }
    return out;
}

}  // namespace svetlo
