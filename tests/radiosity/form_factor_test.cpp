// Radiosity's form factors against closed forms: the point-to-polygon integral against
// Hottel's corner formula, the unit plates through every method, the rows of a closed box,
// and reciprocity.
#include <gtest/gtest.h>

#include <cmath>

#include "radiosity_test_support.h"
#include "svetlo/radiosity/form_factors.h"
#include "svetlo/radiosity/hemicube.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

/// From a differential area to a parallel rectangle a x b at height c, the area's foot under
/// one corner (Hottel; Howell's catalogue, B-3).
double corner_form_factor(double a, double b, double c) {
    double X = a / c, Y = b / c;
    double x1 = std::sqrt(1 + X * X), y1 = std::sqrt(1 + Y * Y);
    return (X / x1 * std::atan(Y / x1) + Y / y1 * std::atan(X / y1)) / (2 * kPi);
}

TEST(FormFactor, PointToPolygonIsHottelsCorner) {
    for (double c : {0.25, 1.0, 3.0}) {
        const vec3 x(0.0f), n(0.0f, 1.0f, 0.0f);
        const float h = static_cast<float>(c);
        // The rectangle [0, 1] x [0, 2] at height c, as two triangles, both windings.
        const vec3 a[3] = {{0, h, 0}, {1, h, 0}, {1, h, 2}};
        const vec3 b[3] = {{0, h, 0}, {0, h, 2}, {1, h, 2}};
        double F = point_triangle_form_factor(x, n, a) + point_triangle_form_factor(x, n, b);
        EXPECT_NEAR(F, corner_form_factor(1.0, 2.0, c), 1e-5) << c;
        // Seen from the other side, nothing.
        EXPECT_EQ(point_triangle_form_factor(x, -n, a), 0.0f);
    }
}

TEST(FormFactor, ClippedToTheHemisphere) {
    // A triangle that crosses the receiver's plane: only its part above counts, and the two
    // sides' parts add up to the whole seen from a point in the plane x = 0 (F sums to 1/2
    // for the half-plane sides of an infinite plane... here checked against splitting).
    const vec3 x(0.0f), n(0.0f, 1.0f, 0.0f);
    const vec3 t[3] = {{-1, -1, 1}, {1, -1, 1}, {0, 1, 1}};
    const vec3 up[3] = {{-0.5f, 0, 1}, {0.5f, 0, 1}, {0, 1, 1}};
    EXPECT_NEAR(point_triangle_form_factor(x, n, t), point_triangle_form_factor(x, n, up), 1e-6);
}

/// The form factor from plate A (the receiver, objects[0]) to plate B (objects[1]) as the
/// area-weighted mean of its elements' form factors to B's elements.
double plates_form_factor(const json& j, FormFactorMethod method, int samples = 16) {
    Scene scene = scene_from_json(j, "plates.json");
    PatchMesh mesh(scene, 2);
    mesh.subdivide_uniform();
    const ElementTree& tree = *mesh.tree;
    std::vector<uint32_t> a, b;
    for (uint32_t id : tree.leaves()) {
        uint32_t t = tree.node(id).root;
        (t < mesh.list.objects[0].end ? a : b).push_back(id);
    }
    double area = 0.0, sum = 0.0;
    if (method == FormFactorMethod::Hemicube) {
        std::vector<uint32_t> leaves = tree.leaves();
        TriangleList triangles = tree.leaf_triangles(leaves);
        Hemicube cube(256, mesh.list.bounds());
        std::vector<float> row(leaves.size());
        for (size_t k = 0; k < leaves.size(); ++k) {
            const ElementNode& e = tree.node(leaves[k]);
            if (e.root >= mesh.list.objects[0].end) continue;
            std::fill(row.begin(), row.end(), 0.0f);
            vec3 n = facing_normal(tree, leaves[k], tree.node(b[0]).centroid);
            cube.gather(triangles, e.centroid, n, row, 2);
            double f = 0.0;
            for (size_t m = 0; m < leaves.size(); ++m)
                if (tree.node(leaves[m]).root >= mesh.list.objects[0].end) f += row[m];
            sum += e.area * f;
            area += e.area;
        }
        return sum / area;
    }
    FormFactorContext ctx{tree, *mesh.accel, method, samples};
    uint64_t rays = 0;
    for (uint32_t r : a) {
        double f = 0.0;
        for (uint32_t s : b) f += form_factor(ctx, r, s, 7, rays).sum();
        sum += tree.node(r).area * f;
        area += tree.node(r).area;
    }
    return sum / area;
}

TEST(FormFactor, UnitPlatesByEveryMethod) {
    // The tolerances docs/radiosity.md states, at elements of 1/8 of the plate.
    struct Case {
        FormFactorMethod method;
        double tolerance;
    };
    for (Case c : {Case{FormFactorMethod::Analytic, 0.005}, Case{FormFactorMethod::Raycast, 0.01},
                   Case{FormFactorMethod::Hemicube, 0.01}}) {
        for (bool perpendicular : {false, true}) {
            const double expected = perpendicular ? 0.200044 : 0.199825;
            double F = plates_form_factor(radiosity_unit_plates(perpendicular, 0.125f), c.method);
            EXPECT_NEAR(F, expected, c.tolerance * expected)
                << name_of(kFormFactorMethods, c.method) << " perpendicular " << perpendicular;
        }
    }
}

TEST(FormFactor, ReciprocityOfThePlates) {
    // A_a F_ab = A_b F_ba: the plates swapped give the same form factor (equal areas).
    for (bool perpendicular : {false, true}) {
        json j = radiosity_unit_plates(perpendicular, 0.125f);
        json swapped = j;
        std::swap(swapped["objects"][0], swapped["objects"][1]);
        for (FormFactorMethod m : {FormFactorMethod::Analytic, FormFactorMethod::Raycast}) {
            double ab = plates_form_factor(j, m), ba = plates_form_factor(swapped, m);
            EXPECT_NEAR(ab, ba, 0.005 * ab) << perpendicular;
        }
    }
}

TEST(FormFactor, RowsOfAClosedBoxSumToOne) {
    // Every element of a closed box sees the box's inside and nothing else.
    json j = radiosity_closed_box(0.5f, 0.0f, 0.0f);
    j["render"]["radiosity"]["element_size"] = 0.3;
    Scene scene = scene_from_json(j, "box.json");
    PatchMesh mesh(scene, 2);
    mesh.subdivide_uniform();
    const ElementTree& tree = *mesh.tree;
    const std::vector<uint32_t> leaves = tree.leaves();
    for (FormFactorMethod m : {FormFactorMethod::Analytic, FormFactorMethod::Raycast}) {
        FormFactorContext ctx{tree, *mesh.accel, m, 16};
        uint64_t rays = 0;
        double worst = 0.0;
        for (uint32_t r : leaves) {
            double row = 0.0;
            for (uint32_t s : leaves)
                if (s != r) row += form_factor(ctx, r, s, 3, rays).sum();
            worst = std::max(worst, std::abs(row - 1.0));
        }
        EXPECT_LT(worst, m == FormFactorMethod::Analytic ? 1e-3 : 0.1)
            << name_of(kFormFactorMethods, m);
    }
    // The hemicube's delta form factors over one whole hemicube sum to 1 (to its cells'
    // discretisation), and inside the box they all meet an element.
    std::vector<uint32_t> all = leaves;
    TriangleList triangles = tree.leaf_triangles(all);
    Hemicube cube(128, mesh.list.bounds());
    std::vector<float> row(all.size(), 0.0f);
    const ElementNode& e = tree.node(all[0]);
    float total = cube.gather(triangles, e.centroid,
                              facing_normal(tree, all[0], vec3(0.0f, 0.0f, 0.0f)), row, 2);
    EXPECT_NEAR(total, 1.0f, 2e-3f);
}

}  // namespace
}  // namespace svetlo
