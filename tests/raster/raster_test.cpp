// The rasterizer against closed forms, against the ray tracer, and its invariants (fill
// rule, depth test, clipping). Expected values are computed here, independently of the
// pipeline: a pixel's world point is the camera ray through its centre meeting the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "contract_camera.h"
#include "svetlo/core/image_io.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/clipper.h"
#include "svetlo/raster/edge_function.h"
#include "svetlo/raster/lines.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/raster/raster_lights.h"
#include "svetlo/raster/simd_shading.h"
#include "svetlo/scene/scene_loader.h"
#include "svetlo/shading/mipmap.h"
#include "test_scenes.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

RenderResult render(const json& j, const std::string& engine = "raster",
                    std::vector<std::string> aovs = {}, int threads = 2) {
    Scene scene = scene_from_json(j, "test.json");
    scene.render.engine = engine;
    RenderOptions options;
    options.threads = threads;
    options.aovs = std::move(aovs);
    return RasterRenderer().render(scene, options);
}

/// A perspective camera looking obliquely down at the y = 0 plane.
json oblique(int w, int h) {
    return {{"camera", {{"position", {0.4, 2.2, 3.5}}, {"look_at", {0, 0, 0}}, {"fov", 50}}},
            {"film", {{"width", w}, {"height", h}}},
            {"render", {{"engine", "raster"}, {"spp", 1}, {"max_depth", 0}}}};
}

using test_scenes::floor_quad;

/// Where the ray through the centre of pixel (i, j) meets y = 0 (false if it does not).
bool floor_point(const Scene& scene, int i, int j, vec3& p) {
    Ray r = contract_camera_ray(scene.camera, scene.film.width, scene.film.height,
                                (i + 0.5f) / scene.film.width, (j + 0.5f) / scene.film.height);
    if (!(r.d.y < 0.0f)) return false;
    p = r.o - (r.o.y / r.d.y) * r.d;
    return true;
}

/// Normalised Phong under a point light, docs/shading.md's formula.
Color phong_closed_form(vec3 p, vec3 eye, vec3 light, Color intensity, float kd, float ks, float n,
                        float ka, float ambient) {
    vec3 nrm(0, 1, 0);
    vec3 d = light - p;
    float d2 = glm::dot(d, d);
    vec3 l = d / std::sqrt(d2), v = glm::normalize(eye - p);
    float cos_t = glm::dot(nrm, l);
    vec3 r = 2.0f * cos_t * nrm - l;
    float spec = (n + 2.0f) / (2.0f * kPi) * std::pow(std::max(0.0f, glm::dot(r, v)), n);
    return Color(ka * ambient) + (kd / kPi + ks * spec) * intensity * (cos_t / d2);
}

// The world point of a pixel comes from vertices snapped to 1/256 pixel: the interpolated
// point moves by at most 1/512 pixel times the world size of a pixel (here < 0.03 m / px at
// 96 px: 6e-5 m), which changes the lighting by well under 1e-3 relative.
constexpr float kSnapTolerance = 1e-3f;

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

TEST(Raster, DepthTestDoesNotDependOnDrawOrder) {
    json j = oblique(64, 48);
    j["materials"] = {{"a", {{"type", "lambert"}, {"albedo", {0.8, 0.2, 0.2}}}},
                      {"b", {{"type", "lambert"}, {"albedo", {0.2, 0.8, 0.2}}}},
                      {"c", {{"type", "lambert"}, {"albedo", {0.2, 0.2, 0.8}}}}};
    j["lights"] = {{{"type", "directional"}, {"direction", {-0.3, -1, -0.2}}, {"irradiance", 2}}};
    json objects = {
        {{"type", "sphere"}, {"center", {0, 0.3, 0}}, {"radius", 0.6}, {"material", "a"}},
        {{"type", "box"}, {"min", {-0.8, 0, -0.2}}, {"max", {0.3, 0.5, 0.5}}, {"material", "b"}},
        floor_quad(1.5f, "c")};
    j["objects"] = objects;
    RenderResult first = render(j);
    j["objects"] = {objects[2], objects[0], objects[1]};
    RenderResult second = render(j);
    ASSERT_EQ(first.color.pixels.size(), second.color.pixels.size());
    for (size_t k = 0; k < first.color.pixels.size(); ++k)
        ASSERT_EQ(first.color.pixels[k], second.color.pixels[k]) << k;
    // Different thread counts give the same image.
    RenderResult one = render(j, "raster", {}, 1);
    for (size_t k = 0; k < one.color.pixels.size(); ++k)
        ASSERT_EQ(one.color.pixels[k], second.color.pixels[k]) << k;
    // The painter's algorithm gets this scene right (the floor is drawn first, being farthest)
    // except where the interpenetrating sphere and box cross: it has no per-pixel depth.
    j["render"]["visibility"] = "painter";
    RenderResult painter = render(j);
    int differ = 0;
    for (size_t k = 0; k < painter.color.pixels.size(); ++k)
        differ += painter.color.pixels[k] != first.color.pixels[k];
    EXPECT_GT(differ, 0);
    EXPECT_LT(differ, static_cast<int>(first.color.pixels.size() / 4));
}

TEST(Raster, RandomTrianglesRenderTheSameOnAnyThreadCountInEveryMode) {
    // Robustness: 2,000 random triangles from a hundredth of a pixel to far past the screen,
    // some crossing the near plane and some degenerate, through every mode of the pipeline.
    // Every image must be finite and the same bit for bit on one and on two threads.
    uint32_t state = 2024;
    auto rnd = [&](float lo, float hi) {
        state = state * 1664525u + 1013904223u;
        return lo + (hi - lo) * static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
    };
    json positions = json::array(), indices = json::array();
    for (int k = 0; k < 2000; ++k) {
        float size = k % 10 < 6 ? rnd(0.001f, 0.05f) : k % 10 < 9 ? rnd(0.05f, 2.0f) : 300.0f;
        vec3 c(rnd(-4, 4), rnd(-1, 3), rnd(-8, 4));
        for (int v = 0; v < 3; ++v) {
            vec3 p =
                k % 97 == 0 ? c : c + vec3(rnd(-size, size), rnd(-size, size), rnd(-size, size));
            positions.push_back({p.x, p.y, p.z});
            indices.push_back(3 * k + v);
        }
    }
    json j = oblique(96, 64);
    j["materials"] = {{"p", {{"type", "phong"}, {"kd", 0.5}, {"ks", 0.3}, {"shininess", 20}}},
                      {"l", {{"type", "lambert"}, {"albedo", 0.6}}}};
    j["objects"] = {
        {{"type", "mesh"}, {"positions", positions}, {"indices", indices}, {"material", "p"}},
        floor_quad(3.0f, "l")};
    json point = {{"type", "point"}, {"position", {0.5, 2, 1}}, {"intensity", 8}};
    json spot = {{"type", "spot"},  {"position", {0, 3, 2}}, {"direction", {0, -1, -0.5}},
                 {"intensity", 10}, {"inner_angle", 20},     {"outer_angle", 35}};
    std::vector<std::pair<const char*, json>> modes = {
        {"phong, point light (the SIMD path)", {{"lights", {point}}}},
        {"phong, spot light (the scalar path)", {{"lights", {spot}}}},
        {"flat", {{"lights", {point}}, {"render", {{"shading", "flat"}}}}},
        {"gouraud", {{"lights", {point}}, {"render", {{"shading", "gouraud"}}}}},
        {"depth", {{"lights", {point}}, {"render", {{"shading", "depth"}}}}},
        {"overdraw", {{"lights", {point}}, {"render", {{"shading", "overdraw"}}}}},
        {"4 spp", {{"lights", {point}}, {"render", {{"spp", 4}}}}},
        {"msaa", {{"lights", {point}}, {"render", {{"spp", 4}, {"antialias", "msaa"}}}}},
        {"painter", {{"lights", {point}}, {"render", {{"visibility", "painter"}}}}},
        {"wireframe", {{"lights", {point}}, {"render", {{"wireframe", "wu"}}}}},
        {"culling", {{"lights", {point}}, {"render", {{"cull", "back"}}}}}};
    for (const auto& [name, patch] : modes) {
        json scene = j;
        scene.merge_patch(patch);
        // Without AOVs (the fast path takes what it can), then with one (every sample shaded
        // by the scalar path).
        for (std::vector<std::string> aovs : {std::vector<std::string>{}, {"depth"}}) {
            RenderResult one = render(scene, "raster", aovs, 1);
            RenderResult two = render(scene, "raster", aovs, 2);
            for (size_t k = 0; k < one.color.pixels.size(); ++k) {
                for (int c = 0; c < 3; ++c)
                    ASSERT_TRUE(std::isfinite(one.color.pixels[k][c])) << name;
                ASSERT_EQ(one.color.pixels[k], two.color.pixels[k]) << name << ", pixel " << k;
                if (!aovs.empty()) {
                    ASSERT_EQ(one.aovs.at("depth").pixels[k], two.aovs.at("depth").pixels[k]);
                }
            }
        }
    }
}

TEST(Raster, FillRuleCoversEverySampleOnce) {
    // A 9 x 7 grid of vertices, jittered (some exactly on sample centres and pixel edges),
    // two triangles per cell: every sample inside the outer rectangle belongs to exactly one.
    const int gx = 9, gy = 7;
    const int32_t step = 5 * kSubpixel;  // 5 pixels
    std::vector<int32_t> vx, vy;
    uint32_t state = 12345;
    auto rnd = [&] { return (state = state * 1664525u + 1013904223u) >> 8; };
    for (int y = 0; y < gy; ++y) {
        for (int x = 0; x < gx; ++x) {
            int32_t jx = 0, jy = 0;
            if (x > 0 && x < gx - 1 && y > 0 && y < gy - 1) {
                switch (rnd() % 3) {
                    case 0:
                        break;  // on a pixel corner
                    case 1:
                        jx = jy = kSubpixel / 2;
                        break;  // on a pixel centre
                    default:
                        jx = static_cast<int32_t>(rnd() % 400) - 200,
                        jy = static_cast<int32_t>(rnd() % 400) - 200;
                }
            }
            vx.push_back(x * step + jx);
            vy.push_back(y * step + jy);
        }
    }
    std::vector<std::array<int, 3>> tris;
    for (int y = 0; y + 1 < gy; ++y) {
        for (int x = 0; x + 1 < gx; ++x) {
            int a = y * gx + x, b = a + 1, c = a + gx, d = c + 1;
            if ((x + y) % 2) {
                tris.push_back({a, b, d});
                tris.push_back({a, d, c});
            } else {
                tris.push_back({a, b, c});
                tris.push_back({b, d, c});
            }
        }
    }
    // Samples at pixel centres and at a quarter of a pixel, over the grid's interior.
    for (int32_t offset : {kSubpixel / 2, kSubpixel / 4}) {
        for (int32_t sy = offset; sy < (gy - 1) * step; sy += kSubpixel) {
            for (int32_t sx = offset; sx < (gx - 1) * step; sx += kSubpixel) {
                int count = 0;
                for (const auto& t : tris) {
                    int32_t x[3] = {vx[t[0]], vx[t[1]], vx[t[2]]},
                            y[3] = {vy[t[0]], vy[t[1]], vy[t[2]]};
                    if (signed_area2(x, y) < 0) {
                        std::swap(x[1], x[2]);
                        std::swap(y[1], y[2]);
                    }
                    Edge e[3] = {Edge::make(x[1], y[1], x[2], y[2]),
                                 Edge::make(x[2], y[2], x[0], y[0]),
                                 Edge::make(x[0], y[0], x[1], y[1])};
                    bool in = true;
                    for (const Edge& edge : e) in = in && edge.at(sx, sy) + edge.bias >= 0;
                    count += in;
                }
                ASSERT_EQ(count, 1) << "sample " << sx << "," << sy;
            }
        }
    }
}

TEST(Raster, ClippingKeepsThePartInFrontOfTheNearPlane) {
    ClipVertex a, b, c;
    a.clip = vec4(0, 0, -2, 1);  // in front of the near plane (z < -w would be behind)
    b.clip = vec4(1, 0, -3, 1);  // behind it
    c.clip = vec4(0, 1, 0.5f, 1);
    a.uv = vec2(0, 0);
    b.uv = vec2(1, 0);
    c.uv = vec2(0, 1);
    ClipPolygon p = clip_triangle(a, b, c, 2.0f, 2.0f);
    ASSERT_EQ(p.count, 3);  // one vertex kept, two made on the near plane
    for (int k = 0; k < p.count; ++k) {
        const ClipVertex& v = p.v[static_cast<size_t>(k)];
        EXPECT_GE(v.clip.z, -v.clip.w - 1e-6f);
        EXPECT_LE(v.clip.z, v.clip.w + 1e-6f);
        // Attributes follow the clip-space position linearly: uv.y tracks y here.
        EXPECT_NEAR(v.uv.y, v.clip.y, 1e-6f);
    }
    ClipPolygon none = clip_triangle(b, b, b, 2.0f, 2.0f);
    EXPECT_EQ(none.count, 0);
}

// Found by tests/fuzz/mutate_scenes.py: a sphere of radius 3.4e38 gave a vertex y = -inf with
// a finite w, inside the clip volume because g w overflowed to inf; it was snapped to INT_MIN,
// and the triangle's bounds overflowed a signed integer (under UBSan).
TEST(Raster, AVertexThatCannotBeProjectedIsNotInside) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_TRUE(inside(vec4(0.5f, -0.5f, 0.0f, 1.0f), 2.0f, 2.0f));
    EXPECT_TRUE(inside(vec4(0.0f, 0.0f, 0.0f, std::numeric_limits<float>::min()), 2.0f, 2.0f));
    EXPECT_FALSE(inside(vec4(inf, 0.0f, 0.0f, inf), 2.0f, 2.0f));      // overflowed
    EXPECT_FALSE(inside(vec4(0.0f, 0.0f, 0.0f, inf), 2.0f, 2.0f));     // 0 / inf: nothing
    EXPECT_FALSE(inside(vec4(0.0f, 0.0f, 0.0f, 1e-40f), 2.0f, 2.0f));  // 1 / w = inf
    EXPECT_FALSE(inside(vec4(0.0f, 0.0f, 0.0f, 0.0f), 2.0f, 2.0f));
    // The fuzzer's vertex: y overflowed, w did not, and g w does.
    EXPECT_FALSE(inside(vec4(4.79f, -inf, 1.8e38f, 1.8e38f), 8193.0f, 8193.0f));
    // The sphere itself, in every shading mode and on films down to one pixel: every value
    // finite (and, under UBSan, no overflow on the way).
    for (const char* shading : {"flat", "gouraud", "phong"}) {
        for (int size : {1, 3, 24}) {
            json j = oblique(size, size);
            j["render"]["shading"] = shading;
            j["materials"] = {{"grey", {{"type", "lambert"}, {"albedo", 0.5}}}};
            j["lights"] = {
                {{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", {1, 1, 1}}}};
            j["objects"] = {{{"type", "sphere"},
                             {"center", {2.25, 0.6, 0}},
                             {"radius", 3.4e38},
                             {"material", "grey"}}};
            RenderResult r = render(j);
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) EXPECT_TRUE(is_finite(r.color.at(x, y)));
        }
    }
}

/// A camera looking obliquely at the origin, for the matrices' tests.
Camera oblique_camera(Camera::Type type) {
    Camera cam;
    cam.type = type;
    cam.position = vec3(1, 2, 3);
    cam.look_at = vec3(0, 0.5f, 0);
    cam.fov_deg = 45.0f;
    return cam;
}

TEST(Raster, MatricesProjectWhereTheCameraRaysGo) {
    for (auto type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        const Camera cam = oblique_camera(type);
        CameraMatrices m = camera_matrices(cam, 200, 100, Bounds3{vec3(-2), vec3(2)});
        for (vec2 film : {vec2(0.1f, 0.2f), vec2(0.5f, 0.5f), vec2(0.9f, 0.7f)}) {
            Ray r = contract_camera_ray(cam, 200, 100, film.x, film.y);
            vec3 p = r.o + 2.5f * r.d;
            vec4 clip = m.view_projection() * vec4(p, 1.0f);
            vec2 px = m.to_pixels(vec2(clip) / clip.w);
            EXPECT_NEAR(px.x, film.x * 200.0f, 1e-3f);
            EXPECT_NEAR(px.y, film.y * 100.0f, 1e-3f);
        }
    }
}

TEST(Raster, AJitteredCameraShowsTheJitteredRayAtThePixelCentre) {
    for (auto type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        const Camera cam = oblique_camera(type);
        for (int w : {1, 3, 200}) {
            const int h = w == 200 ? 100 : w;
            const CameraMatrices m = camera_matrices(cam, w, h, Bounds3{vec3(-2), vec3(2)});
            for (vec2 jitter : {vec2(0.5f), vec2(0.1f, 0.8f), vec2(0.95f, 0.05f)}) {
                const CameraMatrices jm = jittered_camera(m, jitter);
                const int i = w / 2, j = h / 3;
                Ray r = contract_camera_ray(cam, w, h, (static_cast<float>(i) + jitter.x) / w,
                                            (static_cast<float>(j) + jitter.y) / h);
                vec3 p = r.o + 2.5f * r.d;
                vec4 clip = jm.view_projection() * vec4(p, 1.0f);
                vec2 px = jm.to_pixels(vec2(clip) / clip.w);
                EXPECT_NEAR(px.x, static_cast<float>(i) + 0.5f, 1e-3f) << w << " " << jitter.x;
                EXPECT_NEAR(px.y, static_cast<float>(j) + 0.5f, 1e-3f) << h << " " << jitter.y;
            }
        }
    }
}

TEST(Raster, LinesCoverWhatTheyShould) {
    std::vector<std::pair<int, int>> pixels;
    draw_line_bresenham(vec2(0.5f, 0.5f), vec2(10.5f, 4.5f), [&](int i, int j, float c, float) {
        EXPECT_EQ(c, 1.0f);
        pixels.emplace_back(i, j);
    });
    ASSERT_EQ(pixels.size(), 11u);  // one pixel per step of the major axis
    EXPECT_EQ(pixels.front(), std::make_pair(0, 0));
    EXPECT_EQ(pixels.back(), std::make_pair(10, 4));
    for (size_t k = 1; k < pixels.size(); ++k)
        EXPECT_LE(std::abs(pixels[k].second - pixels[k - 1].second), 1);
    // Wu: the two pixels straddling the line share its unit intensity per column.
    std::map<int, float> column;
    draw_line_wu(vec2(0.5f, 0.5f), vec2(20.5f, 7.3f),
                 [&](int i, int, float c, float) { column[i] += c; });
    for (int i = 1; i < 20; ++i) EXPECT_NEAR(column[i], 1.0f, 1e-5f) << i;
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
    // directional and a spot light (its cone's edge across the scene), seen from both sides; a
    // whole shininess (powers by repeated squaring) and a fractional one (exp2 and log2).
    json j = oblique(64, 48);
    j["materials"] = {
        {"l", {{"type", "lambert"}, {"albedo", {0.7, 0.5, 0.3}}}},
        {"p", {{"type", "phong"}, {"ka", 0.3}, {"kd", 0.5}, {"ks", 0.4}, {"shininess", 40}}},
        {"b", {{"type", "blinn_phong"}, {"kd", 0.2}, {"ks", 0.6}, {"shininess", 12.5}}}};
    j["lights"] = {{{"type", "point"}, {"position", {0.5, 1.5, 0.8}}, {"intensity", {5, 4, 3}}},
                   {{"type", "directional"}, {"direction", {0.3, -1, -0.4}}, {"irradiance", 0.8}},
                   {{"type", "spot"},
                    {"position", {-0.5, 2, 1}},
                    {"direction", {0.3, -1, -0.3}},
                    {"intensity", {6, 6, 8}},
                    {"inner_angle", 15},
                    {"outer_angle", 30}}};
    j["render"]["ambient"] = 0.1;
    j["render"]["spp"] = 4;
    j["objects"] = {
        floor_quad(1.5f, "l"),
        {{"type", "sphere"}, {"center", {-0.5, 0.5, 0}}, {"radius", 0.5}, {"material", "p"}},
        {{"type", "box"}, {"min", {0.2, 0, -0.6}}, {"max", {0.9, 0.7, 0.1}}, {"material", "b"}},
        {{"type", "quad"},
         {"corner", {-1, 0, -1}},
         {"edge_u", {0, 1, 0}},
         {"edge_v", {1, 0, 0}},
         {"material", "p"}}};
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
}

TEST(Raster, AMeshOfSmallTrianglesHasNoCracks) {
    // A 60 x 40 grid of jittered vertices, two triangles per cell (a few pixels each, so the
    // small-triangle path draws them), against the one quad it tiles: the same pixels covered.
    const int nx = 60, ny = 40;
    json positions = json::array(), indices = json::array();
    uint32_t state = 99;
    auto jitter = [&] {
        return (static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) / 16777216.0f -
                0.5f) *
               0.6f;
    };
    for (int y = 0; y <= ny; ++y) {
        for (int x = 0; x <= nx; ++x) {
            bool inner = x > 0 && x < nx && y > 0 && y < ny;
            float fx = static_cast<float>(x) + (inner ? jitter() : 0.0f),
                  fy = static_cast<float>(y) + (inner ? jitter() : 0.0f);
            positions.push_back({-1.5f + 3.0f * fx / nx, 0.0f, -1.0f + 2.0f * fy / ny});
        }
    }
    for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
            int a = y * (nx + 1) + x, b = a + 1, c = a + nx + 1, d = c + 1;
            for (int v : {a, c, b, b, c, d}) indices.push_back(v);
        }
    }
    json j = {
        {"camera",
         {{"type", "orthographic"},
          {"position", {0.013, 5, 0.007}},
          {"look_at", {0.013, 0, 0.007}},
          {"up", {0, 0, -1}},
          {"height", 2.5}}},
        {"film", {{"width", 160}, {"height", 120}}},
        {"render", {{"spp", 1}, {"ambient", 1}, {"background", 5}}},
        {"materials", {{"m", {{"type", "lambert"}, {"albedo", 0.5}}}}},
        {"lights", json::array()},
        {"objects",
         {{{"type", "mesh"}, {"positions", positions}, {"indices", indices}, {"material", "m"}}}}};
    RenderResult mesh = render(j);
    j["objects"] = {floor_quad(1.0f, "m")};
    j["objects"][0]["corner"] = {-1.5, 0, -1};
    j["objects"][0]["edge_u"] = {0, 0, 2};
    j["objects"][0]["edge_v"] = {3, 0, 0};
    RenderResult quad = render(j);
    int covered = 0;
    for (size_t k = 0; k < mesh.color.pixels.size(); ++k) {
        bool a = mesh.color.pixels[k].r < 1.0f, b = quad.color.pixels[k].r < 1.0f;
        covered += b;
        ASSERT_EQ(a, b) << "pixel " << k % 160 << "," << k / 160;
    }
    EXPECT_GT(covered, 8000);
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

TEST(Raster, OverdrawCountsEveryFragmentInTheStencilBuffer) {
    // Three stacked squares, y = 0, 0.1, 0.2, of half sizes 1, 0.6, 0.3: a pixel's count is
    // the number of squares its centre's ray crosses, hidden ones included (the stencil
    // buffer increments whether the depth test passes or fails), while the visibility buffer
    // still holds the nearest surface (its normal points up).
    const int w = 96, h = 64;
    json j = oblique(w, h);
    j["render"]["shading"] = "overdraw";
    j["materials"] = {{"m", {{"type", "lambert"}, {"albedo", {0.5, 0.5, 0.5}}}}};
    const float heights[3] = {0.0f, 0.1f, 0.2f}, halves[3] = {1.0f, 0.6f, 0.3f};
    for (int k = 2; k >= 0; --k) {  // nearest first: the others fail the depth test
        json q = floor_quad(halves[k], "m");
        q["corner"][1] = heights[k];
        j["objects"].push_back(q);
    }
    Scene scene = scene_from_json(j, "test.json");
    RenderResult r = render(j, "raster", {"normal"});
    int checked = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            Ray ray = contract_camera_ray(scene.camera, w, h, (x + 0.5f) / w, (y + 0.5f) / h);
            int count = 0;
            float margin = kInfinity;  // distance of a crossing from a square's edge
            for (int k = 0; k < 3; ++k) {
                if (!(ray.d.y < 0.0f)) continue;
                vec3 p = ray.o + ((heights[k] - ray.o.y) / ray.d.y) * ray.d;
                float inside = halves[k] - std::max(std::abs(p.x), std::abs(p.z));
                margin = std::min(margin, std::abs(inside));
                count += inside > 0.0f ? 1 : 0;
            }
            if (margin < 0.03f) continue;  // within a pixel of an edge
            ++checked;
            ASSERT_FLOAT_EQ(r.color.at(x, y).x, static_cast<float>(count) / 8.0f) << x << "," << y;
            if (count > 0) {
                EXPECT_NEAR(r.aovs.at("normal").at(x, y).y, 1.0f, 1e-5f) << x << "," << y;
            }
        }
    }
    EXPECT_GT(checked, w * h / 2);
}

}  // namespace
}  // namespace svetlo
