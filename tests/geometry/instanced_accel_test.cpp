// Instances in every structure (geometry/instanced_accel.h): a field of placed prototypes,
// turned, scaled unevenly and mirrored, gives the hits of the same objects written out, and
// costs memory independent of the prototype's size.
#include <gtest/gtest.h>

#include <cmath>

#include "svetlo/core/error.h"
#include "svetlo/core/rng.h"
#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/scene/instances.h"

namespace svetlo {
namespace {

/// A bumpy latitude-longitude sphere of 2 n^2 triangles, radius about 1.
Mesh bumpy_sphere(int n) {
    Mesh m;
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
            const float theta = 3.14159265f * static_cast<float>(i) / static_cast<float>(n);
            const float phi = 6.2831853f * static_cast<float>(j) / static_cast<float>(n);
            const float r = 1.0f + 0.05f * std::sin(7.0f * theta) * std::cos(9.0f * phi);
            m.positions.push_back(r * vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                           std::sin(theta) * std::sin(phi)));
        }
    }
    const auto at = [&](int i, int j) { return static_cast<uint32_t>(i * (n + 1) + j); };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            for (uint32_t v : {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1),
                               at(i, j + 1)})
                m.indices.push_back(v);
            m.face_material.push_back(0);
            m.face_material.push_back(0);
        }
    }
    return m;
}

/// A prototype of a bumpy sphere, a turned box and a sphere, placed `count` times over a
/// square of side `side`: turned, scaled unevenly, every fourth mirrored, every fifth with its
/// own material.
Scene field(int count, int resolution, float side, uint64_t seed) {
    Scene scene;
    Prototype p;
    p.name = "tree";
    Object body;
    body.name = "body";
    body.shape = bumpy_sphere(resolution);
    p.objects.push_back(body);
    Object box;
    box.name = "box";
    box.shape = Box{vec3(-0.3f, 0.8f, -0.3f), vec3(0.3f, 1.6f, 0.3f)};
    box.material = 0;
    box.transform.matrix = glm::rotate(mat4(1.0f), 0.4f, vec3(0.0f, 1.0f, 0.0f));
    box.transform.is_identity = false;
    p.objects.push_back(box);
    Object ball;
    ball.name = "ball";
    ball.shape = Sphere{vec3(0.0f, 1.9f, 0.0f), 0.3f};
    ball.material = 0;
    p.objects.push_back(ball);
    scene.prototypes.push_back(p);
    Rng rng(seed, 3);
    for (int k = 0; k < count; ++k) {
        Instance i;
        i.name = "objects[" + std::to_string(k) + "]";
        mat4 m = glm::translate(mat4(1.0f), vec3(side * (rng.next_float() - 0.5f), 0.0f,
                                                 side * (rng.next_float() - 0.5f)));
        m = glm::rotate(m, 6.28f * rng.next_float(), glm::normalize(vec3(0.2f, 1.0f, 0.1f)));
        m = glm::scale(m, vec3(0.5f + rng.next_float(), 0.5f + rng.next_float(),
                               (k % 4 == 3 ? -1.0f : 1.0f) * (0.5f + rng.next_float())));
        i.transform.matrix = m;
        i.transform.is_identity = false;
        i.material = k % 5 == 4 ? 1 : -1;
        scene.instances.push_back(i);
    }
    return scene;
}

TEST(Instances, EveryStructureFindsTheHitsOfTheObjectsWrittenOut) {
    const Scene scene = field(40, 24, 12.0f, 7);
    Geometry placed;
    place_instances(scene, placed);
    const std::vector<Object> copies = instance_copies(scene);
    const Geometry written = build_geometry(object_pointers(copies));
    ASSERT_EQ(placed.triangle_count(), 0u);
    ASSERT_EQ(written.triangle_count(), 40u * 2 * 24 * 24);
    const BruteForce reference(written);

    // Rays from around the field toward points within it, and down onto it.
    Rng rng(11, 5);
    std::vector<Ray> rays;
    for (int k = 0; k < 4000; ++k) {
        const vec3 target(12.0f * (rng.next_float() - 0.5f), 2.5f * rng.next_float() - 0.5f,
                          12.0f * (rng.next_float() - 0.5f));
        const float a = 6.2831853f * rng.next_float();
        const vec3 from =
            k % 2 ? vec3(10.0f * std::cos(a), 1.0f + 4.0f * rng.next_float(), 10.0f * std::sin(a))
                  : target + vec3(0.0f, 8.0f, 0.0f);
        rays.push_back({from, target - from, k % 3 == 0 ? 1.0f : kInfinity});
    }
    std::vector<Hit> expected(rays.size());
    for (size_t k = 0; k < rays.size(); ++k) reference.intersect(rays[k], expected[k]);
    for (const std::string& name : accel_names()) {
        const std::unique_ptr<Accel> accel = make_accel(name, placed, 2);
        if (!accel) continue;  // (a build without Embree)
        int hits = 0, disagree = 0;
        for (size_t k = 0; k < rays.size(); ++k) {
            const Ray& ray = rays[k];
            Hit a;
            const Hit& b = expected[k];
            const bool ha = accel->intersect(ray, a);
            const bool hb = b.valid();
            EXPECT_EQ(accel->occluded(ray), ha) << name;
            if (ha != hb) {
                ++disagree;
                continue;
            }
            if (!ha) continue;
            ++hits;
            ASSERT_NE(a.instance, Hit::kNone) << name;
            const SurfaceHit sa = placed.surface(ray, a), sb = written.surface(ray, b);
            // The same t and point up to the rounding of the transforms (t in units of |d|,
            // about 10 scene units), the same side, the same material.
            if (std::abs(a.t - b.t) > 1e-4f * b.t) {
                ++disagree;  // a grazing ray met a neighbouring face first
                continue;
            }
            EXPECT_LT(glm::length(sa.p - sb.p), 1e-3f) << name;
            EXPECT_GT(glm::dot(sa.ng, sb.ng), 0.999f) << name;
            EXPECT_GT(glm::dot(sa.ns, sb.ns), 0.99f) << name;
            EXPECT_EQ(sa.material, sb.material) << name;
        }
        EXPECT_GT(hits, 1500) << name;
        // A ray that grazes an edge may pass on the other side of it, rounded an ulp apart.
        EXPECT_LE(disagree, 1) << name;
    }
}

TEST(Instances, CostMemoryIndependentOfTheirPrototype) {
    // 10,000 placements of a 20,000-triangle prototype stand for 200 M triangles: as copies,
    // more than 5 GiB of geometry; placed, the prototype once and 10,000 placements.
    const Scene scene = field(10000, 100, 400.0f, 3);
    Geometry placed;
    place_instances(scene, placed);
    EXPECT_EQ(instanced_triangles(scene), 10000u * (2 * 100 * 100 + 1 + 1));
    // svetlo's BVH, and Embree with its own instances (its memory counted as its device
    // allocates it; a structure per copy would take gigabytes).
    for (const std::string name : {"bvh", "embree"}) {
        const std::unique_ptr<Accel> accel = make_accel(name, placed, 2);
        if (!accel) continue;  // (a build without Embree)
        EXPECT_GT(accel->memory_bytes(), size_t{1} << 20) << name;
        EXPECT_LT(placed.memory_bytes() + accel->memory_bytes(), size_t{12} << 20) << name;
        // And it is all there: a ray down onto every fifth placement meets it.
        for (size_t k = 0; k < scene.instances.size(); k += 5) {
            const vec3 c = vec3(scene.instances[k].transform.matrix[3]);
            Hit hit;
            ASSERT_TRUE(
                accel->intersect({c + vec3(0.0f, 50.0f, 0.0f), vec3(0.0f, -1.0f, 0.0f)}, hit))
                << name;
            EXPECT_NE(hit.instance, Hit::kNone) << name;
        }
    }
    // instance_copies refuses to write them out (the rasterizer and radiosity draw copies).
    EXPECT_THROW(instance_copies(scene), Error);
}

}  // namespace
}  // namespace svetlo
