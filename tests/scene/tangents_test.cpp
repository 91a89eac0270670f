// Made tangents (scene/tangents.h) against the closed form: on a sphere whose u runs along
// the parallels and v up the meridians, the tangent is the parallel's direction and the
// bitangent the meridian's; mirroring u turns the tangent and its sign.
#include "svetlo/scene/tangents.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace svetlo {
namespace {

/// A uv sphere of radius 2: rows of latitude, columns of longitude; u = phi / 2 pi with
/// position (sin phi cos lat, sin lat, cos phi cos lat), v = 1/2 + lat / pi.
Mesh uv_sphere(bool mirror_u, bool clockwise) {
    Mesh m;
    const int rows = 48, cols = 96;
    for (int j = 0; j <= rows; ++j) {
        const float lat = kPi * (static_cast<float>(j) / rows - 0.5f);
        for (int i = 0; i <= cols; ++i) {
            const float phi = 2.0f * kPi * static_cast<float>(i) / cols;
            const vec3 n(std::sin(phi) * std::cos(lat), std::sin(lat),
                         std::cos(phi) * std::cos(lat));
            m.positions.push_back(2.0f * n);
            m.normals.push_back(n);
            const float u = static_cast<float>(i) / cols;
            m.uvs.emplace_back(mirror_u ? 1.0f - u : u, static_cast<float>(j) / rows);
        }
    }
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i) {
            const uint32_t a = static_cast<uint32_t>(j * (cols + 1) + i), b = a + 1,
                           c = a + static_cast<uint32_t>(cols + 1), d = c + 1;
            // Counter-clockwise seen from outside: a, b, d then a, d, c.
            const std::array<uint32_t, 6> ccw{a, b, d, a, d, c}, cw{a, d, b, a, c, d};
            for (uint32_t v : clockwise ? cw : ccw) m.indices.push_back(v);
            m.face_material.push_back(0);
            m.face_material.push_back(0);
        }
    return m;
}

TEST(Tangents, FollowTheSpheresParallelsWithTheMeridianOnTheirSide) {
    for (bool mirror : {false, true}) {
        for (bool clockwise : {false, true}) {
            const Mesh m = uv_sphere(mirror, clockwise);
            const std::vector<vec4> t = mesh_tangents(m);
            ASSERT_EQ(t.size(), m.positions.size());
            int checked = 0;
            for (size_t k = 0; k < t.size(); ++k) {
                const vec3 n = m.normals[k];
                if (std::abs(n.y) > 0.95f) continue;  // near the poles the parallels turn fast
                // d/dphi of the position: (cos phi, 0, -sin phi), along increasing u.
                vec3 along_u = glm::normalize(vec3(n.z, 0.0f, -n.x));
                if (mirror) along_u = -along_u;
                const vec3 up = glm::cross(n, glm::normalize(vec3(n.z, 0.0f, -n.x)));
                // A triangle's gradients are the faceted sphere's, not the round one's: off by
                // up to 2 degrees on this grid (and by 3.5 on one of half its resolution).
                EXPECT_GT(glm::dot(vec3(t[k]), along_u), 0.9994f) << k;
                EXPECT_NEAR(glm::dot(vec3(t[k]), n), 0.0f, 1e-5f) << k;
                // The bitangent w cross(n, t) points up the meridian, the way v increases.
                const vec3 bitangent = t[k].w * glm::cross(n, vec3(t[k]));
                EXPECT_GT(glm::dot(bitangent, up), 0.9994f) << k;
                EXPECT_EQ(t[k].w, mirror ? -1.0f : 1.0f) << k;
                ++checked;
            }
            EXPECT_GT(checked, 3500);
        }
    }
}

TEST(Tangents, NoneWithoutTextureCoordinatesOrWhereTheyHaveNoArea) {
    Mesh m = uv_sphere(false, false);
    for (vec2& uv : m.uvs) uv = vec2(0.25f);  // every triangle's uvs collapse to a point
    for (const vec4& t : mesh_tangents(m)) EXPECT_EQ(t, vec4(0.0f));
    m.uvs.clear();
    EXPECT_TRUE(mesh_tangents(m).empty());
}

TEST(Tangents, AnInterpolatedTangentIsMadeOrthogonalToTheShadingNormal) {
    const vec4 t = orthogonal_tangent(vec4(1.0f, 1.0f, 0.0f, -1.0f), vec3(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(t, vec4(1.0f, 0.0f, 0.0f, -1.0f));
    EXPECT_EQ(orthogonal_tangent(vec4(0.0f, 2.0f, 0.0f, 1.0f), vec3(0.0f, 1.0f, 0.0f)), vec4(0.0f));
}

}  // namespace
}  // namespace svetlo
