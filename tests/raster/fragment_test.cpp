// The rasterizer's stage 6: flat, Gouraud and Phong shading against closed forms, the fast
// path's kernels against the scalar shading, textures.
#include "raster_testing.h"

namespace svetlo {
namespace {

using namespace raster_testing;

TEST(Raster, PhongShadedQuadUnderPointLightMatchesTheClosedForm) {
    const int w = 96, h = 64;
    json j = oblique(w, h);
    j["materials"] = {
        {"shiny", {{"type", "phong"}, {"kd", 0.5}, {"ks", 0.3}, {"shininess", 20}, {"ka", 0.5}}}};
    j["lights"] = {{{"type", "point"}, {"position", {0.5, 1.2, 0.3}}, {"intensity", {6, 3, 1.5}}}};
    j["render"]["ambient"] = 0.2;
    j["objects"] = {floor_quad(1.5f, "shiny")};
    Scene scene = scene_from_json(j, "test.json");
    RenderResult r = render(j);
    int checked = 0;
    for (int jj = 0; jj < h; ++jj) {
        for (int i = 0; i < w; ++i) {
            vec3 p;
            if (!floor_point(scene, i, jj, p) || std::abs(p.x) > 1.45f || std::abs(p.z) > 1.45f)
                continue;
            Color e = phong_closed_form(p, scene.camera.position, vec3(0.5f, 1.2f, 0.3f),
                                        Color(6, 3, 1.5f), 0.5f, 0.3f, 20.0f, 0.5f, 0.2f);
            ASSERT_NEAR(r.color.at(i, jj).r, e.r, kSnapTolerance * e.r) << i << "," << jj;
            ASSERT_NEAR(r.color.at(i, jj).b, e.b, kSnapTolerance * e.b) << i << "," << jj;
            ++checked;
        }
    }
    EXPECT_GT(checked, 1200);
}

/// A single triangle on the floor with per-vertex normals, for the Gouraud and flat tests.
json floor_triangle(const char* material) {
    return {{"type", "mesh"},       {"positions", {{-1.2, 0, 1.0}, {1.3, 0, 0.8}, {0.1, 0, -1.4}}},
            {"indices", {0, 1, 2}}, {"normals", {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}}},
            {"smooth", true},       {"material", material}};
}

TEST(Raster, GouraudInterpolatesTheVertexColours) {
    const int w = 80, h = 60;
    json j = oblique(w, h);
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.7}}}};
    vec3 light(0.2f, 0.6f, 0.1f);
    j["lights"] = {
        {{"type", "point"}, {"position", {light.x, light.y, light.z}}, {"intensity", 3}}};
    j["render"]["shading"] = "gouraud";
    j["objects"] = {floor_triangle("white")};
    Scene scene = scene_from_json(j, "test.json");
    RenderResult r = render(j);
    vec3 v[3] = {vec3(-1.2f, 0, 1.0f), vec3(1.3f, 0, 0.8f), vec3(0.1f, 0, -1.4f)};
    float c[3];
    for (int k = 0; k < 3; ++k) {
        vec3 d = light - v[k];
        float d2 = glm::dot(d, d);
        c[k] = 0.7f / kPi * 3.0f * (d.y / std::sqrt(d2)) / d2;
    }
    int checked = 0;
    float max_phong_gap = 0.0f;
    for (int jj = 0; jj < h; ++jj) {
        for (int i = 0; i < w; ++i) {
            vec3 p;
            if (!floor_point(scene, i, jj, p)) continue;
            // World barycentrics of p: perspective-correct interpolation reproduces them.
            vec3 e0 = v[1] - v[0], e1 = v[2] - v[0], q = p - v[0];
            float det = e0.x * e1.z - e0.z * e1.x;
            float b1 = (q.x * e1.z - q.z * e1.x) / det, b2 = (e0.x * q.z - e0.z * q.x) / det,
                  b0 = 1.0f - b1 - b2;
            if (b0 < 0.02f || b1 < 0.02f || b2 < 0.02f) continue;  // away from the edges
            float expected = b0 * c[0] + b1 * c[1] + b2 * c[2];
            ASSERT_NEAR(r.color.at(i, jj).g, expected, kSnapTolerance * expected) << i << "," << jj;
            vec3 d = light - p;
            float phong = 0.7f / kPi * 3.0f * (d.y / glm::length(d)) / glm::dot(d, d);
            max_phong_gap = std::max(max_phong_gap, std::abs(phong - expected) / phong);
            ++checked;
        }
    }
    EXPECT_GT(checked, 300);
    EXPECT_GT(max_phong_gap, 0.2f);  // the lesson: the light's peak between vertices is lost
}

TEST(Raster, GouraudLightsASharedVertexOncePerMaterial) {
    // One OBJ mesh, two squares sharing an edge, red on the left and blue on the right, under
    // a light straight above: every vertex colour of a square is its own material's, so each
    // square is uniform, right up to the shared edge (a vertex lit with one material for both
    // squares would blend the two colours there).
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / "svetlo_raster_gouraud_test";
    fs::create_directories(dir);
    {
        std::ofstream obj(dir / "two.obj");
        obj << "mtllib two.mtl\nv -1 0 1\nv 0 0 1\nv 1 0 1\nv -1 0 -1\nv 0 0 -1\nv 1 0 -1\n"
               "usemtl red\nf 1 2 5\nf 1 5 4\nusemtl blue\nf 2 3 6\nf 2 6 5\n";
        std::ofstream mtl(dir / "two.mtl");
        mtl << "newmtl red\nKd 0.8 0.1 0.1\nKs 0 0 0\nnewmtl blue\nKd 0.1 0.2 0.9\nKs 0 0 0\n";
    }
    const int w = 80, h = 60;
    json j = oblique(w, h);
    j["render"]["shading"] = "gouraud";
    j["lights"] = {{{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", 2}}};
    j["objects"] = {{{"type", "mesh"}, {"file", (dir / "two.obj").string()}}};
    Scene scene = scene_from_json(j, "test.json");
    RenderResult r = render(j);
    const Color red = Color(0.8f, 0.1f, 0.1f) * (2.0f / kPi),
                blue = Color(0.1f, 0.2f, 0.9f) * (2.0f / kPi);
    int checked[2] = {0, 0};
    for (int jj = 0; jj < h; ++jj) {
        for (int i = 0; i < w; ++i) {
            vec3 p;
            if (!floor_point(scene, i, jj, p)) continue;
            if (std::abs(p.x) < 0.03f || std::abs(p.x) > 0.97f || std::abs(p.z) > 0.97f) continue;
            Color expected = p.x < 0.0f ? red : blue;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(r.color.at(i, jj)[c], expected[c], 1e-4f) << i << "," << jj;
            ++checked[p.x < 0.0f ? 0 : 1];
        }
    }
    EXPECT_GT(checked[0], 100);
    EXPECT_GT(checked[1], 100);
    fs::remove_all(dir);
}

TEST(Raster, FlatShadingIsOneColourPerFace) {
    const int w = 80, h = 60;
    json j = oblique(w, h);
    j["materials"] = {{"white", {{"type", "phong"}, {"kd", 0.6}, {"ks", 0.2}, {"shininess", 10}}}};
    vec3 light(0.2f, 0.6f, 0.1f);
    j["lights"] = {
        {{"type", "point"}, {"position", {light.x, light.y, light.z}}, {"intensity", 3}}};
    j["render"]["shading"] = "flat";
    j["objects"] = {floor_triangle("white")};
    Scene scene = scene_from_json(j, "test.json");
    RenderResult r = render(j);
    vec3 centroid = (vec3(-1.2f, 0, 1.0f) + vec3(1.3f, 0, 0.8f) + vec3(0.1f, 0, -1.4f)) / 3.0f;
    Color expected = phong_closed_form(centroid, scene.camera.position, light, Color(3.0f), 0.6f,
                                       0.2f, 10.0f, 0.0f, 0.0f);
    int covered = 0;
    for (const Color& c : r.color.pixels) {
        if (c.r == 0.0f) continue;  // background
        ASSERT_NEAR(c.r, expected.r, 1e-6f * expected.r);
        ++covered;
    }
    EXPECT_GT(covered, 400);
}

#if SVETLO_SIMD  // the fast path's pow, in a build with SIMD
TEST(Raster, SimdPowMatchesStdPow) {
    float worst = 0.0f;
    for (float n : {0.0f, 1.0f, 2.5f, 8.0f, 32.0f, 100.0f, 1000.0f}) {
        for (float x = 0.0f; x <= 1.0f; x += 1.0f / 4096.0f) {
            float xs[4] = {x, x * 0.5f, 1.0f - x, std::min(1.0f, x + 1e-3f)}, ns[4] = {n, n, n, n},
                  out[4];
            pow4(xs, ns, out);
            for (int k = 0; k < 4; ++k) {
                float e = std::pow(xs[k], n);
                if (e < 1e-30f) {
                    EXPECT_LT(out[k], 1e-29f);
                    continue;
                }
                worst = std::max(worst, std::abs(out[k] - e) / e);
            }
        }
    }
    EXPECT_LT(worst, 2e-5f);  // n log2(x) carries the 1e-7 of log2, times n up to 1000
}
#endif

TEST(Raster, SimdFastPathAgreesWithTheScalarShading) {
    // The same frame shaded four samples at a time (no AOVs) and one by one (an AOV asked for
    // sends every sample through the scalar path): Lambert, Phong and Blinn-Phong, a point, a
    // directional and a spot light (its cone's edge across the scene), and a light with area
    // (its VPLs; facing down at y = 0.8, so that the sphere's top and the wall see its back,
    // and the box's top lies closer to some VPLs than the area each stands for), seen from
    // both sides; a whole shininess (powers by repeated squaring) and a fractional one (exp2
    // and log2); textured colours.
    json j = oblique(64, 48);
    // Textured colours, evaluated per sample: a checkered Lambert floor and a wall whose kd
    // is an image under trilinear filtering (the pixel's footprint).
    Image stripes(32, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            stripes.at(x, y) = Color(0.2f + 0.6f * ((x / 3) & 1), 0.5f, 0.3f);
    auto dir =
        std::filesystem::temp_directory_path() / ("svetlo_fast_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    write_image(dir / "stripes.pfm", stripes, PixelMeaning::Radiance, 1.0f, "test");
    j["materials"] = {
        {"l", {{"type", "lambert"}, {"albedo", {0.7, 0.5, 0.3}}}},
        {"c",
         {{"type", "lambert"},
          {"albedo", {{"checker", {{"a", 0.1}, {"b", {0.9, 0.6, 0.3}}, {"scale", 6}}}}}}},
        {"p", {{"type", "phong"}, {"ka", 0.3}, {"kd", 0.5}, {"ks", 0.4}, {"shininess", 40}}},
        {"t",
         {{"type", "phong"},
          {"kd", {{"texture", (dir / "stripes.pfm").string()}, {"filter", "trilinear"}}},
          {"ks", 0.3},
          {"shininess", 20}}},
        {"b", {{"type", "blinn_phong"}, {"kd", 0.2}, {"ks", 0.6}, {"shininess", 12.5}}}};
    j["lights"] = {{{"type", "point"}, {"position", {0.5, 1.5, 0.8}}, {"intensity", {5, 4, 3}}},
                   {{"type", "directional"}, {"direction", {0.3, -1, -0.4}}, {"irradiance", 0.8}},
                   {{"type", "spot"},
                    {"position", {-0.5, 2, 1}},
                    {"direction", {0.3, -1, -0.3}},
                    {"intensity", {6, 6, 8}},
                    {"inner_angle", 15},
                    {"outer_angle", 30}},
                   {{"type", "area"},
                    {"corner", {0.3, 0.8, -0.5}},
                    {"edge_u", {0.5, 0, 0}},
                    {"edge_v", {0, 0, 0.4}},
                    {"radiance", {2, 3, 4}}}};
    j["render"]["ambient"] = 0.1;
    j["render"]["spp"] = 4;
    j["render"]["area_light_points"] = 5;
    j["objects"] = {
        floor_quad(1.5f, "c"),
        {{"type", "sphere"}, {"center", {-0.5, 0.5, 0}}, {"radius", 0.5}, {"material", "p"}},
        {{"type", "box"}, {"min", {0.2, 0, -0.6}}, {"max", {0.9, 0.7, 0.1}}, {"material", "b"}},
        {{"type", "sphere"}, {"center", {0.9, 0.25, 0.6}}, {"radius", 0.25}, {"material", "l"}},
        {{"type", "quad"},
         {"corner", {-1, 0, -1}},
         {"edge_u", {0, 1, 0}},
         {"edge_v", {1, 0, 0}},
         {"material", "t"}}};
    for (int spp : {1, 4}) {  // one sample: runs along rows; more: batches of samples
        j["render"]["spp"] = spp;
        RenderResult fast = render(j);
        RenderResult scalar = render(j, "raster", {"albedo"});
        float worst = 0.0f;
        for (size_t k = 0; k < fast.color.pixels.size(); ++k) {
            for (int c = 0; c < 3; ++c) {
                float a = fast.color.pixels[k][c], b = scalar.color.pixels[k][c];
                worst = std::max(worst, std::abs(a - b) / std::max(b, 1e-3f));
            }
        }
        EXPECT_LT(worst, 1e-4f) << spp;
    }
    std::filesystem::remove_all(dir);
}

#if SVETLO_SIMD
/// A run of one triangle for the kernel tests: the weights of its first sample, 1/w and
/// world positions of its vertices.
TriangleRun test_run() {
    TriangleRun q;
    q.l1 = 0.05f;
    q.l2 = 0.1f;
    q.invw[0] = 0.5f;
    q.invw[1] = 0.25f;
    q.invw[2] = 0.4f;
    q.world[0] = vec3(-1, 0, 0);
    q.world[1] = vec3(1, 0, -0.5f);
    q.world[2] = vec3(0, 1, 0.3f);
    return q;
}

TEST(Raster, FourAndEightLaneKernelsAgree) {
    // A run of 64 samples of one triangle through the four-lane kernel and through the best
    // one of this processor (eight lanes with AVX2): the same colours.
    TriangleRun q = test_run();
    q.normal[0] = glm::normalize(vec3(-0.2f, 0.1f, 1));
    q.normal[1] = glm::normalize(vec3(0.3f, 0, 1));
    q.normal[2] = glm::normalize(vec3(0, 0.4f, 1));
    SimdLights lights;
    lights.points.push_back({vec3(0.5f, 1.5f, 2), Color(6, 5, 4), 0});
    lights.directionals.push_back({glm::normalize(vec3(0.2f, 0.5f, 1)), Color(0.7f), 1});
    for (int variant = 0; variant < 4; ++variant) {
        bool blinn = variant % 2 == 1;
        float shininess = variant < 2 ? 24.0f : 24.5f;  // repeated squaring, or exp2 and log2
        SimdMaterial m(Color(0.2f), Color(0.5f, 0.4f, 0.3f), Color(0.4f), shininess, blinn, true);
        Color four[64], best[64];
        vec3 ng = glm::normalize(glm::cross(q.world[1] - q.world[0], q.world[2] - q.world[0]));
        shade_run(q, 0.01f, 0.008f, 16, m, ng, lights, vec3(0, 0.2f, 3), false, vec3(0, 0, -1),
                  Color(0.1f), four, 4);
        shade_run(q, 0.01f, 0.008f, 16, m, ng, lights, vec3(0, 0.2f, 3), false, vec3(0, 0, -1),
                  Color(0.1f), best);
        for (int k = 0; k < 64; ++k) {
            for (int c = 0; c < 3; ++c) {
                ASSERT_GT(four[k][c], 0.0f);
                EXPECT_NEAR(best[k][c], four[k][c], 1e-6f * four[k][c])
                    << k << " lanes " << simd_lanes();
            }
        }
    }
}

TEST(Raster, TheKernelMultipliesEachLightByItsVisibility) {
    // A shadow technique's masks through the fast path: V = 0.25 for the point light and a
    // ramp for the directional one must give what lights of those strengths give unmasked,
    // for runs and batches, on four lanes and on the processor's best.
    TriangleRun q = test_run();
    for (vec3& n : q.normal) n = vec3(0, 0, 1);
    vec3 ng(0, 0, 1), eye(0, 0.2f, 3), forward(0, 0, -1);
    SimdMaterial m(Color(0.0f), Color(0.5f, 0.4f, 0.3f), Color(0.4f), 16.0f, true, true);
    SimdLights lights;
    lights.points.push_back({vec3(0.5f, 1.5f, 2), Color(6, 5, 4), 0});
    lights.directionals.push_back({glm::normalize(vec3(0.2f, 0.5f, 1)), Color(0.7f), 1});
    constexpr int kSamples = 32;
    std::vector<float> mask(2 * kSamples);
    for (int k = 0; k < kSamples; ++k) {
        mask[k] = 0.25f;
        mask[kSamples + k] = static_cast<float>(k) / kSamples;
    }
    LightVisibility vis{mask.data(), kSamples};
    for (int lanes : {4, 0}) {
        Color masked[kSamples], point_only[kSamples], sun_only[kSamples];
        shade_run(q, 0.01f, 0.008f, kSamples / 4, m, ng, lights, eye, false, forward, Color(0.0f),
                  masked, lanes, vis);
        SimdLights point = lights, sun = lights;
        point.directionals.clear();
        sun.points.clear();
        shade_run(q, 0.01f, 0.008f, kSamples / 4, m, ng, point, eye, false, forward, Color(0.0f),
                  point_only, lanes);
        shade_run(q, 0.01f, 0.008f, kSamples / 4, m, ng, sun, eye, false, forward, Color(0.0f),
                  sun_only, lanes);
        for (int k = 0; k < kSamples; ++k) {
            Color expected = 0.25f * point_only[k] + mask[kSamples + k] * sun_only[k];
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(masked[k][c], expected[c], 1e-5f * expected[c] + 1e-7f) << k;
        }
        // The same samples gathered into a batch, in reverse order: each lane reads its own
        // sample's visibility.
        ShadeBatch batch;
        Color lit[ShadeBatch::kCapacity];
        for (int k = 7; k >= 0; --k) {
            float l1 = q.l1 + 0.01f * k, l2 = q.l2 + 0.008f * k, l0 = 1.0f - l1 - l2;
            float w0 = l0 * q.invw[0], w1 = l1 * q.invw[1], w2 = l2 * q.invw[2];
            float inv = 1.0f / (w0 + w1 + w2);
            vec3 p = (w0 * q.world[0] + w1 * q.world[1] + w2 * q.world[2]) * inv;
            batch.add(p, vec3(0, 0, 1), ng, &m, static_cast<uint32_t>(k));
        }
        shade_batch(batch, lights, eye, false, forward, Color(0.0f), lit, vis);
        for (int k = 0; k < 8; ++k) {
            Color expected = 0.25f * point_only[7 - k] + mask[kSamples + 7 - k] * sun_only[7 - k];
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(lit[k][c], expected[c], 1e-4f * expected[c] + 1e-6f) << k;
        }
    }
}
TEST(Raster, ARunWithItsOwnColoursShadesAsABatchWithThem) {
    // A textured material's run: each sample brings its colours (ka, kd, ks), as the batch's
    // lanes do; the two kernels must agree lane by lane, on four lanes and on the processor's
    // best, and a run whose colours are the material's must shade as the material.
    TriangleRun q = test_run();
    for (vec3& n : q.normal) n = vec3(0, 0, 1);
    const vec3 ng(0, 0, 1), eye(0, 0.2f, 3), forward(0, 0, -1);
    const Color ambient(0.1f);
    SimdMaterial m(Color(0.2f), Color(0.5f, 0.4f, 0.3f), Color(0.4f), 16.0f, true, true);
    SimdLights lights;
    lights.points.push_back({vec3(0.5f, 1.5f, 2), Color(6, 5, 4), 0});
    lights.directionals.push_back({glm::normalize(vec3(0.2f, 0.5f, 1)), Color(0.7f), 1});
    constexpr int kSamples = 16;
    Color own[kSamples][3], material[kSamples][3];
    for (int k = 0; k < kSamples; ++k) {
        const float t = static_cast<float>(k) / kSamples;
        own[k][0] = Color(0.3f * t, 0.1f, 0.2f);
        own[k][1] = Color(0.9f - 0.5f * t, 0.2f + 0.6f * t, 0.4f);
        own[k][2] = Color(0.1f + 0.5f * t);
        material[k][0] = m.ka;
        material[k][1] = m.kd;
        material[k][2] = m.ks;
    }
    for (int lanes : {4, 0}) {
        Color run[kSamples], plain[kSamples], as_material[kSamples];
        q.own = own;
        shade_run(q, 0.01f, 0.008f, kSamples / 4, m, ng, lights, eye, false, forward, ambient, run,
                  lanes);
        q.own = material;
        shade_run(q, 0.01f, 0.008f, kSamples / 4, m, ng, lights, eye, false, forward, ambient,
                  as_material, lanes);
        q.own = nullptr;
        shade_run(q, 0.01f, 0.008f, kSamples / 4, m, ng, lights, eye, false, forward, ambient,
                  plain, lanes);
        for (int first = 0; first < kSamples; first += ShadeBatch::kCapacity) {
            ShadeBatch batch;
            Color lit[ShadeBatch::kCapacity];
            for (int k = first; k < first + ShadeBatch::kCapacity; ++k) {
                float l1 = q.l1 + 0.01f * k, l2 = q.l2 + 0.008f * k, l0 = 1.0f - l1 - l2;
                float w0 = l0 * q.invw[0], w1 = l1 * q.invw[1], w2 = l2 * q.invw[2];
                float inv = 1.0f / (w0 + w1 + w2);
                vec3 p = (w0 * q.world[0] + w1 * q.world[1] + w2 * q.world[2]) * inv;
                batch.add(p, vec3(0, 0, 1), ng, &m, static_cast<uint32_t>(k), own[k]);
            }
            shade_batch(batch, lights, eye, false, forward, ambient, lit);
            for (int k = 0; k < ShadeBatch::kCapacity; ++k) {
                for (int c = 0; c < 3; ++c) {
                    const float expected = lit[k][c];
                    ASSERT_GT(expected, 0.0f);
                    EXPECT_NEAR(run[first + k][c], expected, 1e-4f * expected) << first + k;
                }
            }
        }
        for (int k = 0; k < kSamples; ++k) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(as_material[k][c], plain[k][c]) << k;
                EXPECT_GT(std::abs(run[k][c] - plain[k][c]), 1e-3f * plain[k][c]) << k;
            }
        }
    }
}
#endif  // the SIMD kernels' own tests

TEST(Raster, TheScalarShadingMultipliesEachLightByItsVisibility) {
    // shade_point with a mask per light: the direct light of each is scaled by its V, the
    // emission and the ambient term are not.
    json j = oblique(8, 8);
    j["lights"] = {{{"type", "point"}, {"position", {0, 2, 0}}, {"intensity", 4}},
                   {{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", 2}}};
    j["render"]["ambient"] = 0.5;
    Scene scene = scene_from_json(j, "test.json");
    RasterLights lights(scene);
    LambertMaterial m;
    m.albedo = ColorSource::constant(Color(0.6f));
    Bsdf bsdf = make_bsdf(Material{m}, vec2(0.0f), scene.textures);
    ShadingFrame frame = make_shading_frame(vec3(0, 1, 0), vec3(0, 1, 0), vec3(0, 1, 0));
    const float mask[4] = {0.0f, 0.25f,  // the point light at samples 0 and 1
                           1.0f, 0.5f};  // the directional light
    LightVisibility vis{mask, 2};
    for (size_t sample : {0u, 1u}) {
        Color L = shade_point(bsdf, vec3(0.0f), frame, vec3(0, 1, 0), lights, Color(0.5f),
                              Color(0.0f), vis, sample);
        // ka I_a + albedo/pi (V_point I / d^2 + V_sun E).
        float expected =
            0.6f * 0.5f + 0.6f / kPi * (mask[sample] * 4.0f / 4.0f + mask[2 + sample] * 2.0f);
        EXPECT_NEAR(L.r, expected, 1e-6f) << sample;
    }
}

TEST(Raster, AreaLightPointsSetTheVpls) {
    // render.area_light_points: n VPLs on the light (a grid for a square n, else a lattice
    // spread over both edges), each standing for area / n; far below the light, where every
    // point sees it alike, the shading gives the closed form E = L A / d^2 for every n.
    json j = oblique(8, 8);
    j["lights"] = {{{"type", "area"},
                    {"corner", {-0.5, 20, -0.5}},
                    {"edge_u", {1, 0, 0}},
                    {"edge_v", {0, 0, 1}},
                    {"radiance", 3}}};  // edge_u x edge_v = -y: it faces the origin
    LambertMaterial white;
    white.albedo = ColorSource::constant(Color(1.0f));
    const ShadingFrame frame = make_shading_frame(vec3(0, 1, 0), vec3(0, 1, 0), vec3(0, 1, 0));
    for (int n : {1, 4, 5, 64, 1024}) {
        j["render"]["area_light_points"] = n;
        const Scene scene = scene_from_json(j, "test.json");
        const RasterLights lights(scene);
        ASSERT_EQ(lights.vpls.size(), 1u);
        ASSERT_EQ(lights.vpls[0].size(), static_cast<size_t>(n));
        EXPECT_FLOAT_EQ(lights.min_dist2[0], 1.0f / static_cast<float>(n));
        float x_lo = 1.0f, x_hi = -1.0f, z_lo = 1.0f, z_hi = -1.0f;
        for (const AreaPoint& a : lights.vpls[0]) {
            EXPECT_NEAR(a.surface.p.y, 20.0f, 1e-5f);
            x_lo = std::min(x_lo, a.surface.p.x), x_hi = std::max(x_hi, a.surface.p.x);
            z_lo = std::min(z_lo, a.surface.p.z), z_hi = std::max(z_hi, a.surface.p.z);
        }
        EXPECT_GE(x_lo, -0.5f);
        EXPECT_LE(x_hi, 0.5f);
        EXPECT_GE(z_lo, -0.5f);
        EXPECT_LE(z_hi, 0.5f);
        if (n >= 4) {  // spread over both edges, not a line
            EXPECT_GT(x_hi - x_lo, 0.4f) << n;
            EXPECT_GT(z_hi - z_lo, 0.4f) << n;
        }
        const Bsdf bsdf = make_bsdf(Material{white}, vec2(0.0f), scene.textures);
        const Color L =
            shade_point(bsdf, vec3(0.0f), frame, vec3(0, 1, 0), lights, Color(0.0f), Color(0.0f));
        // Lambert: L_o = E / pi, E = L A cos cos / d^2: over the light, cos cos / d^2 varies
        // from 1 / 400 m^-2 by at most 2.5e-3 at 20 m, its mean by under 1e-3.
        EXPECT_NEAR(L.r, 3.0f / 400.0f / kPi, 2e-3f * 3.0f / 400.0f / kPi) << n;
    }
}

TEST(Raster, EachLightApartSumsToTheMaskedShading) {
    // Flat and Gouraud shading under a shadow technique light a point once per light:
    // unlit_point + sum of V_k times light k's term is shade_point under the same mask, for
    // a delta light and a light with area (its VPLs), on a Phong and a mirror material.
    json j = oblique(8, 8);
    j["lights"] = {{{"type", "point"}, {"position", {0.5, 2, 0}}, {"intensity", 4}},
                   {{"type", "area"},
                    {"corner", {-0.5, 1.5, -0.5}},
                    {"edge_u", {1, 0, 0}},
                    {"edge_v", {0, 0, 1}},
                    {"radiance", 3}}};
    j["render"]["ambient"] = 0.25;
    Scene scene = scene_from_json(j, "test.json");
    RasterLights lights(scene);
    ASSERT_EQ(lights.set.sources().size(), 2u);
    PhongMaterial phong;
    phong.kd = ColorSource::constant(Color(0.5f, 0.4f, 0.3f));
    phong.ks = ColorSource::constant(Color(0.3f));
    phong.shininess = 20.0f;
    MirrorMaterial mirror;
    mirror.reflectance = ColorSource::constant(Color(0.8f));
    const vec3 wo = glm::normalize(vec3(0.3f, 1.0f, 0.2f));
    const ShadingFrame frame = make_shading_frame(vec3(0, 1, 0), vec3(0, 1, 0), wo);
    const Color background(0.1f, 0.2f, 0.3f);
    for (const Material& m : {Material{phong}, Material{mirror}}) {
        Bsdf bsdf = make_bsdf(m, vec2(0.0f), scene.textures);
        Color terms[2];
        const Color unlit = shade_point_per_light(bsdf, vec3(0.1f, 0.0f, -0.2f), frame, wo, lights,
                                                  Color(0.25f), background, terms);
        EXPECT_EQ(unlit,
                  unlit_point(bsdf, frame, wo, Color(0.25f), background, lights.environment));
        const float mask[6] = {1.0f, 0.0f, 0.5f,    // the point light at samples 0, 1, 2
                               0.0f, 1.0f, 0.25f};  // the area light
        LightVisibility vis{mask, 3};
        for (size_t sample = 0; sample < 3; ++sample) {
            const Color masked = shade_point(bsdf, vec3(0.1f, 0.0f, -0.2f), frame, wo, lights,
                                             Color(0.25f), background, vis, sample);
            const Color apart = unlit + terms[0] * mask[sample] + terms[1] * mask[3 + sample];
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(apart[c], masked[c], 1e-6f * (1.0f + masked[c])) << sample;
        }
        if (bsdf.has_lobes()) {
            EXPECT_GT(terms[0].r, 0.0f);  // both lights reach the point
            EXPECT_GT(terms[1].r, 0.0f);
        }
    }
}

TEST(Raster, FlatAndGouraudModulateTheirLightByTheTexturePerSample) {
    // A checkered Lambert floor under a directional light (the same light at every vertex):
    // flat and Gouraud shading, lighting a white floor and multiplying by the texture at each
    // sample (OpenGL's GL_MODULATE), give Phong's image. They sampled the texture at the
    // vertices or the centroid only, and lost the checkers.
    json j = oblique(96, 64);
    j["materials"] = {
        {"c",
         {{"type", "lambert"},
          {"albedo", {{"checker", {{"a", 0.1}, {"b", {0.9, 0.6, 0.3}}, {"scale", 6}}}}}}}};
    j["lights"] = {{{"type", "directional"}, {"direction", {0.3, -1, 0.2}}, {"irradiance", 2}}};
    j["render"]["ambient"] = 0.1;
    j["objects"] = {floor_quad(1.5f, "c")};
    RenderResult phong = render(j);
    for (const char* mode : {"gouraud", "flat"}) {
        j["render"]["shading"] = mode;
        RenderResult r = render(j);
        int dark = 0, bright = 0;
        for (size_t k = 0; k < phong.color.pixels.size(); ++k) {
            for (int c = 0; c < 3; ++c) {
                float e = phong.color.pixels[k][c];
                ASSERT_NEAR(r.color.pixels[k][c], e, 1e-5f * (1.0f + e)) << mode << " " << k;
            }
            dark += phong.color.pixels[k].b > 0.0f && phong.color.pixels[k].r < 0.1f ? 1 : 0;
            bright += phong.color.pixels[k].r > 0.3f ? 1 : 0;
        }
        EXPECT_GT(dark, 500);  // both checker colours are on screen
        EXPECT_GT(bright, 500);
    }
}

TEST(Raster, TrilinearFilteringAveragesWhenMinified) {
    // A texel-sized black and white checker, 64 x 64.
    Image checker(64, 64);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) checker.at(x, y) = Color(((x + y) & 1) ? 1.0f : 0.0f);
    TextureImage texture(checker);
    MipChain chain = build_mip_chain(texture);
    ASSERT_EQ(chain.count(), 7);
    EXPECT_EQ(chain.level(1).texel(3, 5), Color(0.5f));
    EXPECT_EQ(chain.level(6).texel(0, 0), Color(0.5f));
    // A footprint of 8 texels per pixel selects level 3.
    EXPECT_NEAR(mip_level(chain, vec2(8.0f / 64.0f, 0.0f), vec2(0.0f, 1.0f / 64.0f)), 3.0f, 1e-5f);
    EXPECT_EQ(sample_trilinear(chain, vec2(0.37f, 0.61f), 3.0f, TextureWrap::Repeat), Color(0.5f));
    EXPECT_EQ(sample_trilinear(chain, vec2(0.37f, 0.61f), 2.5f, TextureWrap::Repeat), Color(0.5f));
    // Rendered: a far, textured floor is grey with trilinear filtering, noise with bilinear.
    Image fine(256, 256);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) fine.at(x, y) = Color(((x + y) & 1) ? 1.0f : 0.0f);
    auto dir = std::filesystem::temp_directory_path() /
               ("svetlo_raster_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    write_image(dir / "checker.pfm", fine, PixelMeaning::Radiance, 1.0f, "test");
    json j = {{"camera", {{"position", {0, 1, 0}}, {"look_at", {0, 0.85, -1}}, {"fov", 40}}},
              {"film", {{"width", 48}, {"height", 32}}},
              {"render", {{"spp", 1}, {"max_depth", 0}, {"ambient", 1}}},
              {"lights", json::array()},
              {"objects", {floor_quad(1.0f, "tex")}}};
    j["objects"][0]["corner"] = {-4, 0, -12};
    j["objects"][0]["edge_u"] = {0, 0, 11};
    j["objects"][0]["edge_v"] = {8, 0, 0};
    j["materials"] = {{"tex", {{"type", "lambert"}, {"albedo", 0.5}}}};
    Scene scene = scene_from_json(j, "test.json");  // for the camera rays
    double spread[2];
    for (int k = 0; k < 2; ++k) {
        const char* filter = k == 0 ? "trilinear" : "bilinear";
        j["materials"] = {
            {"tex",
             {{"type", "lambert"},
              {"albedo", {{"texture", (dir / "checker.pfm").string()}, {"filter", filter}}}}}};
        RenderResult r = render(j);
        double lo = 1.0, hi = 0.0;
        int n = 0;
        for (int y = 0; y < 32; ++y) {
            for (int x = 4; x < 44; ++x) {
                vec3 p;
                // On the quad, and at least 2 m away: 4 or more texels per pixel.
                if (!floor_point(scene, x, y, p) || p.z > -2.0f || p.z < -11.5f ||
                    std::abs(p.x) > 3.5f)
                    continue;
                double v = r.color.at(x, y).r;
                lo = std::min(lo, v);
                hi = std::max(hi, v);
                ++n;
            }
        }
        ASSERT_GT(n, 200);
        spread[k] = hi - lo;
        if (k == 0) {
            EXPECT_NEAR(lo, 0.5, 0.03);
            EXPECT_NEAR(hi, 0.5, 0.03);
        }
    }
    EXPECT_GT(spread[1], 0.3);  // bilinear aliases
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace svetlo
