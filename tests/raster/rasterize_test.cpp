// The rasterizer's stage 5: the depth test, the fill rule, small triangles without cracks, lines,
// overdraw, and the same image on any thread count.
#include "raster_testing.h"

namespace svetlo {
namespace {

using namespace raster_testing;

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
