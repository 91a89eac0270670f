// The scene-wide triangle list: objects placed in the world with their ranges, and edge
// adjacency over welded positions (closed shapes have no open edge; holes and borders do).
#include "svetlo/geometry/triangle_list.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

Object cube_mesh(bool with_top) {
    Object o;
    Mesh m;
    for (int k = 0; k < 8; ++k)
        m.positions.push_back(vec3(k & 1 ? 1.0f : 0.0f, k & 2 ? 1.0f : 0.0f, k & 4 ? 1.0f : 0.0f));
    // Six faces, counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int f = 0; f < 6; ++f) {
        if (f == 3 && !with_top) continue;
        const uint32_t* q = faces[f];
        for (uint32_t i : {q[0], q[1], q[2], q[0], q[2], q[3]}) m.indices.push_back(i);
        m.face_material.insert(m.face_material.end(), {0, 0});
    }
    o.shape = m;
    o.material = 0;
    return o;
}

/// Open edges of the triangles with area (those of no area have no neighbours by design).
int open_edges(const TriangleList& list) {
    int open = 0;
    for (size_t t = 0; t < list.triangle_count(); ++t) {
        vec3 p[3];
        for (int c = 0; c < 3; ++c) p[c] = list.positions[list.indices[3 * t + c]];
        if (p[0] == p[1] || p[1] == p[2] || p[2] == p[0]) continue;
        for (int e = 0; e < 3; ++e) open += list.neighbour[3 * t + e] == TriangleList::kOpen;
    }
    return open;
}

void expect_symmetric(const TriangleList& list) {
    for (size_t t = 0; t < list.triangle_count(); ++t) {
        for (int e = 0; e < 3; ++e) {
            uint32_t n = list.neighbour[3 * t + e];
            if (n == TriangleList::kOpen) continue;
            int back = 0;
            for (int f = 0; f < 3; ++f) back += list.neighbour[3 * n + f] == t ? 1 : 0;
            EXPECT_EQ(back, 1) << t << " " << e;
        }
    }
}

TEST(TriangleList, ObjectsArePlacedInTheWorldWithTheirRanges) {
    Object sphere;
    sphere.shape = Sphere{vec3(0.0f), 1.0f};
    sphere.material = 1;
    sphere.transform.matrix =
        glm::translate(mat4(1.0f), vec3(5, 0, 0)) * glm::scale(mat4(1.0f), vec3(2.0f, 1.0f, 1.0f));
    sphere.transform.is_identity = false;
    Object cube = cube_mesh(true);
    TessellationOptions o;
    o.segments = 16;
    o.rings = 8;
    TriangleList list = build_triangle_list({&cube, &sphere}, o, 2);
    ASSERT_EQ(list.objects.size(), 2u);
    EXPECT_EQ(list.objects[0].first, 0u);
    EXPECT_EQ(list.objects[0].end, 12u);
    EXPECT_EQ(list.objects[1].first, 12u);
    EXPECT_EQ(list.objects[1].end, list.triangle_count());
    // A mesh is not known convex, a sphere is (under any transform); the sphere's centroid,
    // the mean of its triangles' corners, is its centre (the tessellation is symmetric).
    EXPECT_EQ(list.convex, (std::vector<char>{0, 1}));
    ASSERT_EQ(list.centroid.size(), 2u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(list.centroid[1][c], c == 0 ? 5.0f : 0.0f, 1e-5f);
    for (uint32_t t = list.objects[1].first; t < list.objects[1].end; ++t) {
        EXPECT_EQ(list.material[t], 1u);
        for (int c = 0; c < 3; ++c) {
            vec3 p = list.positions[list.indices[3 * t + c]] - vec3(5, 0, 0);
            // On the ellipsoid (x/2)^2 + y^2 + z^2 = 1 (tessellation vertices lie on it).
            EXPECT_NEAR(square(p.x / 2.0f) + p.y * p.y + p.z * p.z, 1.0f, 1e-5f);
            EXPECT_NEAR(glm::length(list.normals[list.indices[3 * t + c]]), 1.0f, 1e-5f);
        }
    }
}

TEST(TriangleList, AClosedMeshHasEveryEdgeJoined) {
    Object cube = cube_mesh(true);
    TriangleList list = build_triangle_list({&cube}, {}, 1);
    build_adjacency(list);
    EXPECT_EQ(open_edges(list), 0);
    expect_symmetric(list);
    EXPECT_EQ(closed_objects(list), std::vector<char>{1});
}

TEST(TriangleList, HolesAndBordersAreOpenEdges) {
    Object open_cube = cube_mesh(false);  // the top face missing: a hole of four edges
    TriangleList list = build_triangle_list({&open_cube}, {}, 1);
    build_adjacency(list);
    EXPECT_EQ(open_edges(list), 4);
    expect_symmetric(list);
    Object quad;
    quad.shape = Quad{vec3(0.0f), vec3(1, 0, 0), vec3(0, 0, 1)};
    quad.material = 0;
    TriangleList q = build_triangle_list({&quad}, {}, 1);
    build_adjacency(q);
    EXPECT_EQ(open_edges(q), 4) << "a quad: only its four border edges are open";
    EXPECT_EQ(closed_objects(list), std::vector<char>{0});
    EXPECT_EQ(closed_objects(q), std::vector<char>{0});
}

TEST(TriangleList, TessellatedClosedShapesAreClosed) {
    TessellationOptions o;
    o.segments = 24;
    o.rings = 12;
    for (Shape shape : {Shape{Box{vec3(-1), vec3(1)}}, Shape{Sphere{vec3(0.0f), 1.0f}},
                        Shape{Cylinder{vec3(0.0f), vec3(0, 2, 0), 0.5f}},
                        Shape{Cone{vec3(0.0f), vec3(0, 2, 0), 0.5f}}}) {
        Object obj;
        obj.shape = shape;
        obj.material = 0;
        TriangleList list = build_triangle_list({&obj}, o, 1);
        build_adjacency(list);
        EXPECT_EQ(open_edges(list), 0) << "shape " << shape.index();
        expect_symmetric(list);
        // (A sphere's and a cone's rows of triangles with no area at a pole or the apex have
        // no neighbours, and leave them closed.)
        EXPECT_EQ(closed_objects(list), std::vector<char>{1}) << "shape " << shape.index();
    }
}

}  // namespace
}  // namespace svetlo
