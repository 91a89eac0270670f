#include "svetlo/geometry/tessellate.h"

#include <gtest/gtest.h>

#include <map>

#include "svetlo/geometry/csg.h"
#include "svetlo/geometry/sdf.h"

namespace svetlo {
namespace {

Object object(Shape s, Transform t = {}, int material = 0) {
    Object o;
    o.shape = std::move(s);
    o.transform = t;
    o.material = material;
    return o;
}

vec3 face_normal(const Mesh& m, size_t f) {
    vec3 a = m.positions[m.indices[3 * f]], b = m.positions[m.indices[3 * f + 1]],
         c = m.positions[m.indices[3 * f + 2]];
    return glm::cross(b - a, c - a);
}

vec3 centroid(const Mesh& m, size_t f) {
    return (m.positions[m.indices[3 * f]] + m.positions[m.indices[3 * f + 1]] +
            m.positions[m.indices[3 * f + 2]]) /
           3.0f;
}

double area(const Mesh& m) {
    double a = 0.0;
    for (size_t f = 0; f < m.triangle_count(); ++f) a += 0.5 * glm::length(face_normal(m, f));
    return a;
}

/// Every edge of a closed surface is shared by exactly two triangles, in opposite directions.
/// Vertices are matched by position (analytic shapes duplicate them along seams).
void expect_closed(const Mesh& m) {
    std::map<std::tuple<float, float, float>, uint32_t> ids;
    auto id = [&](uint32_t v) {
        vec3 p = m.positions[v];
        return ids.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<uint32_t>(ids.size()))
            .first->second;
    };
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t f = 0; f < m.triangle_count(); ++f) {
        uint32_t v[3] = {id(m.indices[3 * f]), id(m.indices[3 * f + 1]), id(m.indices[3 * f + 2])};
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;  // collapsed at a pole
        for (int e = 0; e < 3; ++e) edges[{v[e], v[(e + 1) % 3]}]++;
    }
    for (const auto& [edge, count] : edges) {
        EXPECT_EQ(count, 1) << "edge used twice in one direction";
        EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << "open edge";
    }
}

TEST(Tessellate, SphereWithinTheSagittaBound) {
    TessellationOptions o;
    Sphere s{vec3(1, 2, 3), 2.0f};
    Mesh m = tessellate(object(s), o);
    ASSERT_GT(m.triangle_count(), 1000u);
    float bound = sphere_tessellation_error(s.radius, o);
    EXPECT_LT(bound, 0.01f * s.radius);  // the default is fine enough for 1% shading
    float worst = 0.0f;
    for (size_t f = 0; f < m.triangle_count(); ++f) {
        vec3 n = face_normal(m, f);
        if (glm::length(n) < 1e-9f) continue;  // degenerate at the poles
        vec3 c = centroid(m, f);
        EXPECT_GT(glm::dot(n, c - s.center), 0.0f) << "face " << f << " winds inward";
        worst = std::max(worst, s.radius - glm::length(c - s.center));
    }
    EXPECT_LE(worst, bound);
    EXPECT_GT(worst, 0.25f * bound);  // the bound is tight, not vacuous
    AnalyticShape rt = make_analytic_shape(s, Transform{}, 0);
    for (size_t v = 0; v < m.positions.size(); ++v) {
        EXPECT_NEAR(glm::length(m.positions[v] - s.center), s.radius, 1e-5f);
        EXPECT_NEAR(glm::dot(m.normals[v], glm::normalize(m.positions[v] - s.center)), 1.0f, 1e-5f);
        // Texture coordinates follow the ray tracer's (away from the seam and the poles).
        vec2 uv = m.uvs[v];
        if (uv.x < 0.01f || uv.x > 0.99f || uv.y < 0.01f || uv.y > 0.99f) continue;
        vec3 origin = s.center + 3.0f * (m.positions[v] - s.center);
        Ray ray{origin, s.center - origin, kInfinity};
        ShapeHit h;
        ASSERT_TRUE(intersect_shape(rt, ray, kInfinity, h));
        vec2 ruv = shape_surface(rt, ray, h).uv;
        EXPECT_NEAR(ruv.x, uv.x, 1e-4f);
        EXPECT_NEAR(ruv.y, uv.y, 1e-4f);
    }
    expect_closed(m);
}

TEST(Tessellate, BoxCylinderConeAreasAndWinding) {
    TessellationOptions o;
    Mesh box = tessellate(object(Box{vec3(0), vec3(1, 2, 3)}), o);
    EXPECT_EQ(box.triangle_count(), 12u);
    EXPECT_NEAR(area(box), 2.0 * (2 + 6 + 3), 1e-5);
    vec3 mid(0.5f, 1.0f, 1.5f);
    for (size_t f = 0; f < 12; ++f)
        EXPECT_GT(glm::dot(face_normal(box, f), centroid(box, f) - mid), 0.0f);
    expect_closed(box);

    // A polygon of n sides inscribed in a circle: area and perimeter shrink by known factors.
    double n = o.segments, shrink_area = n / (2.0 * kPi) * std::sin(2.0 * kPi / n),
           shrink_perim = n / kPi * std::sin(kPi / n);
    Mesh cyl = tessellate(object(Cylinder{vec3(0), vec3(0, 2, 0), 0.5f}), o);
    double expected = 2.0 * kPi * 0.5 * 2.0 * shrink_perim + 2.0 * kPi * 0.25 * shrink_area;
    EXPECT_NEAR(area(cyl), expected, 1e-4 * expected);
    for (size_t f = 0; f < cyl.triangle_count(); ++f) {
        vec3 c = centroid(cyl, f);
        vec3 out = c.y < 1e-5f          ? vec3(0, -1, 0)
                   : c.y > 2.0f - 1e-5f ? vec3(0, 1, 0)
                                        : vec3(c.x, 0, c.z);
        EXPECT_GT(glm::dot(face_normal(cyl, f), out), 0.0f) << f;
    }
    expect_closed(cyl);

    Mesh cone = tessellate(object(Cone{vec3(0), vec3(0, 1, 0), 1.0f}), o);
    for (size_t f = 0; f < cone.triangle_count(); ++f) {
        vec3 c = centroid(cone, f), fn = face_normal(cone, f);
        if (glm::length(fn) < 1e-12f) continue;
        vec3 out = c.y < 1e-5f ? vec3(0, -1, 0) : vec3(c.x, 0.0f, c.z);
        EXPECT_GT(glm::dot(fn, out), 0.0f) << f;
    }
    expect_closed(cone);
}

TEST(Tessellate, MirroringTransformKeepsOutwardWinding) {
    Transform t;
    t.matrix = glm::scale(mat4(1.0f), vec3(-1, 2, 1));
    t.is_identity = false;
    Mesh m = tessellate(object(Sphere{vec3(0), 1.0f}, t));
    for (size_t f = 0; f < m.triangle_count(); ++f) {
        vec3 n = face_normal(m, f);
        if (glm::length(n) > 1e-9f) {
            EXPECT_GT(glm::dot(n, centroid(m, f)), 0.0f);
        }
    }
}

TEST(Tessellate, ImplicitSurfaceNetsLieOnTheSurface) {
    SdfNode a, b, blend;
    a.op = b.op = SdfOp::Sphere;
    a.a = vec3(-0.5f, 0, 0);
    b.a = vec3(0.5f, 0, 0);
    a.r1 = b.r1 = 0.6f;
    blend.op = SdfOp::Union;
    blend.smooth = 0.3f;
    blend.children = {a, b};
    TessellationOptions o;
    o.grid = 48;
    Mesh m = tessellate(object(Implicit{blend}), o);
    ASSERT_GT(m.triangle_count(), 1000u);
    SdfShape sdf(blend, mat4(1.0f));
    for (vec3 p : m.positions) EXPECT_LT(std::abs(sdf.eval(p)), 1e-4f);
    for (size_t f = 0; f < m.triangle_count(); ++f) {
        EXPECT_GT(glm::dot(face_normal(m, f), sdf.normal(centroid(m, f))), 0.0f) << f;
    }
    expect_closed(m);
    EXPECT_EQ(m.face_material.size(), m.triangle_count());
}

TEST(Tessellate, CsgSurfaceNetsFollowTheSolid) {
    Object body = object(Box{vec3(-1), vec3(1)}, {}, 1);
    Object cut = object(Sphere{vec3(0, 1, 0), 0.6f}, {}, 2);
    Object root;
    root.shape = Csg{CsgOp::Difference, {body, cut}};
    root.material = 0;
    TessellationOptions o;
    o.grid = 40;
    Mesh m = tessellate(root, o);
    ASSERT_GT(m.triangle_count(), 500u);
    AnalyticShape shape = make_analytic_shape(root.shape, Transform{}, 0);
    float cell = 2.0f / static_cast<float>(o.grid);
    // Every vertex is within a cell of the boundary: inside on one side, outside on the other.
    for (size_t v = 0; v < m.positions.size(); ++v) {
        vec3 p = m.positions[v], n = m.normals[v];
        EXPECT_TRUE(shape.csg->contains(p - 1.8f * cell * n) ||
                    shape.csg->contains(p - 1.8f * cell * glm::normalize(p)));
        EXPECT_FALSE(shape.csg->contains(p + 1.8f * cell * n)) << v;
    }
    expect_closed(m);
    // Faces inside the spherical dent carry the cutter's material, the others the box's.
    int dent = 0;
    for (size_t f = 0; f < m.triangle_count(); ++f) {
        vec3 c = centroid(m, f);
        if (std::abs(glm::length(c - vec3(0, 1, 0)) - 0.6f) < 0.05f && c.y < 0.9f) {
            EXPECT_EQ(m.face_material[f], 2) << f;
            ++dent;
        }
        if (std::abs(c.x) > 0.99f && std::abs(c.y) < 0.8f) {
            EXPECT_EQ(m.face_material[f], 1) << f;
        }
    }
    EXPECT_GT(dent, 10);
}

}  // namespace
}  // namespace svetlo
