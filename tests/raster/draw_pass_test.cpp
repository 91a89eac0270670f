// The pass entry point (draw_pass.h): depth-only passes against the closed form of the depth
// key, depth writes off, the stencil's per-face operations and culling by the side the
// camera sees, the item buffer through clipping, the same depths without it, and the same
// targets on one thread and two.
#include "svetlo/raster/draw_pass.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

/// Appends the quad a, b, c, d (counter-clockwise seen from its front) as two triangles.
void add_quad(TriangleList& list, vec3 a, vec3 b, vec3 c, vec3 d) {
    auto base = static_cast<uint32_t>(list.positions.size());
    for (vec3 p : {a, b, c, d}) {
        list.positions.push_back(p);
        list.normals.push_back(vec3(0.0f));
        list.uvs.push_back(vec2(0.0f));
    }
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) list.indices.push_back(base + i);
    list.material.insert(list.material.end(), {0u, 0u});
}

/// A square of half size h at depth z (world), facing +z (the camera) or -z.
struct Square {
    float z, h;
    bool toward_camera;
};

TriangleList squares(std::initializer_list<Square> list) {
    TriangleList out;
    for (const Square& q : list) {
        vec3 a(-q.h, -q.h, q.z), b(q.h, -q.h, q.z), c(q.h, q.h, q.z), d(-q.h, q.h, q.z);
        if (q.toward_camera)
            add_quad(out, a, b, c, d);
        else
            add_quad(out, a, d, c, b);
    }
    return out;
}

/// A camera at (0, 0, 5) looking down -z, 32 x 32 pixels, near and far around z in [-5, 4].
CameraMatrices camera(Camera::Type type = Camera::Type::Perspective) {
    Camera c;
    c.type = type;
    c.position = vec3(0, 0, 5);
    c.look_at = vec3(0.0f);
    c.fov_deg = 40.0f;
    c.height = 4.0f;
    return camera_matrices(c, 32, 32, Bounds3{vec3(-3, -3, -5), vec3(3, 3, 4)});
}

TEST(DrawPass, ADepthPassStoresTheDepthKeyOfTheNearestSurface) {
    for (auto type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        CameraMatrices cam = camera(type);
        RenderTargets t;
        t.clear(32, 32);
        // Two squares: the nearer (z = 1, 4 from the camera) drawn last; the depth test keeps it.
        draw_pass(squares({{-2.0f, 1.8f, true}, {1.0f, 0.5f, true}}), cam, PipelineState{}, t, 2);
        float key_near, key_far;
        if (type == Camera::Type::Perspective) {  // -1/w, w the distance along the view axis
            key_near = -1.0f / 4.0f;
            key_far = -1.0f / 7.0f;
        } else {  // window z: (d - near) / (far - near)
            key_near = (4.0f - cam.near) / (cam.far - cam.near);
            key_far = (7.0f - cam.near) / (cam.far - cam.near);
        }
        EXPECT_NEAR(t.depth[t.index(16, 16)], key_near, 1e-5f);
        // The far square shows around the near one, and nothing beyond both.
        float half_near_px = 0.5f / (std::tan(radians(20.0f)) * 4.0f) * 16.0f;
        int x =
            type == Camera::Type::Perspective ? 16 + static_cast<int>(half_near_px) + 2 : 16 + 6;
        EXPECT_NEAR(t.depth[t.index(x, 16)], key_far, 1e-5f);
        EXPECT_EQ(t.depth[t.index(0, 0)], kInfinity);
    }
}

TEST(DrawPass, DepthWritesOffLeaveTheDepthButStillTestIt) {
    RenderTargets t;
    t.clear(32, 32, 1, false, true);
    draw_pass(squares({{-2.0f, 1.0f, true}}), camera(), PipelineState{}, t, 1);
    std::vector<float> before = t.depth;
    PipelineState state;
    state.depth_write = false;
    // A nearer square of two triangles (ids 0 and 1 of this list) is kept where it passes,
    // without changing the depth; a farther one is rejected everywhere.
    t.primitive.assign(t.primitive.size(), RenderTargets::kNoPrimitive);
    draw_pass(squares({{-3.0f, 1.0f, true}, {1.0f, 0.3f, true}}), camera(), state, t, 1);
    EXPECT_EQ(t.depth, before);
    EXPECT_NE(t.primitive[t.index(16, 16)], RenderTargets::kNoPrimitive);  // the near square
    EXPECT_GE(t.primitive[t.index(16, 16)], 2u);
    int far_kept = 0;
    for (uint32_t p : t.primitive) far_kept += p < 2u ? 1 : 0;
    EXPECT_EQ(far_kept, 0);
}

/// Stencil state that adds 1 where a front face passes and subtracts 1 where a back face does
/// (with wrapping, as z-pass shadow volumes count).
PipelineState counting_state() {
    PipelineState s;
    s.depth_write = false;
    s.stencil.enabled = true;
    s.stencil.front = {StencilFunc::Always, StencilOp::Keep, StencilOp::Keep, StencilOp::IncrWrap};
    s.stencil.back = {StencilFunc::Always, StencilOp::Keep, StencilOp::Keep, StencilOp::DecrWrap};
    return s;
}

TEST(DrawPass, TheStencilCountsUpOnFrontFacesAndDownOnBackFaces) {
    for (int threads : {1, 2}) {
        RenderTargets t;
        t.clear(32, 32, 1, true);
        // A large square facing the camera, a small one facing away in front of it.
        draw_pass(squares({{-1.0f, 1.5f, true}, {0.5f, 0.4f, false}}), camera(), counting_state(),
                  t, threads);
        EXPECT_EQ(t.stencil[t.index(16, 16)], 0);  // both: +1 - 1
        EXPECT_EQ(t.stencil[t.index(16, 22)], 1);  // the front face only
        EXPECT_EQ(t.stencil[t.index(0, 0)], 0);    // neither
        // The back face alone, with wrapping: 0 - 1 = 255.
        RenderTargets back;
        back.clear(32, 32, 1, true);
        draw_pass(squares({{0.5f, 0.4f, false}}), camera(), counting_state(), back, threads);
        EXPECT_EQ(back.stencil[back.index(16, 16)], 255);
    }
}

TEST(DrawPass, AStencilCountFourPixelsAtATimeEqualsTheCountSampleBySample) {
    // A shadow volume's stencil pass (test Always, wrapping counts, nothing else written) is
    // counted four pixels at a time, in 32-bit lanes where its edge functions fit and in 64-bit
    // ones where not; the same pass with a test that always passes too (0 <= value) goes
    // sample by sample. Random triangles, long and thin ones, in a second round ones crossing
    // the near plane, and in a third thin slivers reaching far past the guard band, whose
    // edge functions change by about 2^29 per pixel (beyond 32 bits within a block), against
    // a depth pass of three squares; z-fail and z-pass.
    uint32_t state = 7;
    auto rnd = [&](float lo, float hi) {
        state = state * 1664525u + 1013904223u;
        return lo + (hi - lo) * static_cast<float>(state >> 8) / 16777216.0f;
    };
    TriangleList scene = squares({{-2.0f, 1.8f, true}, {0.0f, 0.6f, false}, {1.5f, 0.3f, true}});
    TriangleList volume;
    for (int k = 0; k < 400; ++k) {
        const float reach = k < 300 ? 1.5f : 4.0f;
        vec3 a(rnd(-2, 2), rnd(-2, 2), k < 300 ? rnd(-4, 3) : rnd(-6, 4.9f));
        vec3 b = a + vec3(rnd(-reach, reach), rnd(-reach, reach), rnd(-reach, reach));
        vec3 c = a + vec3(rnd(-0.2f, 0.2f), rnd(-reach, reach), rnd(-reach, reach));
        auto base = static_cast<uint32_t>(volume.positions.size());
        for (vec3 p : {a, b, c}) {
            volume.positions.push_back(p);
            volume.normals.push_back(vec3(0.0f));
            volume.uvs.push_back(vec2(0.0f));
        }
        volume.indices.insert(volume.indices.end(), {base, base + 1, base + 2});
        volume.material.push_back(0);
    }
    for (int k = 0; k < 60; ++k) {
        // A sliver through the view, nearly vertical or horizontal, 1 km long at z in [-1, 1].
        const vec3 mid(rnd(-1.5f, 1.5f), rnd(-1.5f, 1.5f), rnd(-1, 1));
        const float tilt = rnd(-0.3f, 0.3f), width = rnd(0.01f, 0.3f);
        const vec3 along = k % 2 == 0 ? vec3(tilt, 1, 0) : vec3(1, tilt, 0);
        const vec3 across = k % 2 == 0 ? vec3(width, 0, 0) : vec3(0, width, 0);
        auto base = static_cast<uint32_t>(volume.positions.size());
        for (vec3 p : {mid - 500.0f * along, mid + 500.0f * along + across, mid + across}) {
            volume.positions.push_back(p);
            volume.normals.push_back(vec3(0.0f));
            volume.uvs.push_back(vec2(0.0f));
        }
        volume.indices.insert(volume.indices.end(), {base, base + 1, base + 2});
        volume.material.push_back(0);
    }
    for (bool zfail : {true, false}) {
        PipelineState fast = counting_state();
        fast.write_items = false;
        if (zfail) {
            fast.stencil.back = {StencilFunc::Always, StencilOp::Keep, StencilOp::IncrWrap,
                                 StencilOp::Keep};
            fast.stencil.front = {StencilFunc::Always, StencilOp::Keep, StencilOp::DecrWrap,
                                  StencilOp::Keep};
        }
        PipelineState plain = fast;
        plain.stencil.front.func = plain.stencil.back.func = StencilFunc::LessEqual;
        RenderTargets a, b;
        for (RenderTargets* t : {&a, &b}) {
            t->clear(32, 32, 1, true);
            draw_pass(scene, camera(), PipelineState{}, *t, 2);
        }
        draw_pass(volume, camera(), fast, a, 2);
        draw_pass(volume, camera(), plain, b, 2);
        int counted = 0;
        for (uint8_t s : a.stencil) counted += s != 0;
        EXPECT_GT(counted, 100) << zfail;
        EXPECT_EQ(a.stencil, b.stencil) << zfail;
    }
}

TEST(DrawPass, CullingDropsTheSideItNames) {
    for (CullMode cull : {CullMode::None, CullMode::Back, CullMode::Front}) {
        for (bool toward : {true, false}) {
            RenderTargets t;
            t.clear(32, 32);
            PipelineState state;
            state.cull = cull;
            draw_pass(squares({{0.0f, 1.0f, toward}}), camera(), state, t, 2);
            bool drawn = t.depth[t.index(16, 16)] < kInfinity;
            bool expected = cull == CullMode::None || (cull == CullMode::Back) == toward;
            EXPECT_EQ(drawn, expected) << static_cast<int>(cull) << " toward=" << toward;
        }
    }
}

TEST(DrawPass, WithoutAnItemBufferTheDepthIsTheSame) {
    // A depth pass into targets without an item buffer keeps no triangle ids (a shadow map's):
    // its depths must be those of the pass that keeps them, bit for bit. Small triangles (a
    // 48 x 48 grid of quads over the view, tilted, two pixels a side) take the four-pixel
    // path, and two overlapping layers exercise the depth test.
    TriangleList list;
    for (float z : {-1.0f, 0.5f}) {
        for (int j = 0; j < 48; ++j) {
            for (int i = 0; i < 48; ++i) {
                const float x0 = -2.4f + 0.1f * static_cast<float>(i), y0 = -2.4f + 0.1f * j;
                auto at = [&](float x, float y) { return vec3(x, y, z + 0.3f * x - 0.2f * y); };
                add_quad(list, at(x0, y0), at(x0 + 0.1f, y0), at(x0 + 0.1f, y0 + 0.1f),
                         at(x0, y0 + 0.1f));
            }
        }
    }
    for (auto type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        RenderTargets with, without;
        with.clear(32, 32, 1, false, true);
        without.clear(32, 32);
        draw_pass(list, camera(type), PipelineState{}, with, 2);
        draw_pass(list, camera(type), PipelineState{}, without, 2);
        EXPECT_EQ(with.depth, without.depth);
        size_t covered = 0;
        for (float d : without.depth) covered += d != kInfinity ? 1 : 0;
        EXPECT_GT(covered, without.depth.size() / 2);
    }
}

/// Appends triangle a, b, c (reversed when `flip`).
void add_triangle(TriangleList& list, vec3 a, vec3 b, vec3 c, bool flip = false) {
    auto base = static_cast<uint32_t>(list.positions.size());
    for (vec3 p : {a, flip ? c : b, flip ? b : c}) {
        list.positions.push_back(p);
        list.normals.push_back(vec3(0.0f));
        list.uvs.push_back(vec2(0.0f));
    }
    for (uint32_t v : {0u, 1u, 2u}) list.indices.push_back(base + v);
    list.material.push_back(0u);
}

/// A depth-only pass of `list` (its own records and rasterization: draw_pass.h) against the
/// same pass with an item buffer, bit for bit: every cull mode, one thread and two, twice
/// through one PassMemory. At least 1/`part` of the view covered.
void expect_same_depths_with_and_without_items(const TriangleList& list, const CameraMatrices& cam,
                                               size_t part) {
    for (CullMode cull : {CullMode::None, CullMode::Back, CullMode::Front}) {
        PipelineState pass;
        pass.cull = cull;
        RenderTargets with;
        with.clear(cam.width, cam.height, 1, false, true);
        draw_pass(list, cam, pass, with, 1);
        for (int threads : {1, 2}) {
            RenderTargets without;
            without.clear(cam.width, cam.height);
            PassMemory memory;
            for (int again = 0; again < 2; ++again) {
                draw_pass(list, cam, pass, without, threads, 0, &memory);
                EXPECT_EQ(with.depth, without.depth)
                    << "cull " << static_cast<int>(cull) << ", " << threads << " threads";
            }
        }
        size_t covered = 0;
        for (float d : with.depth) covered += d != kInfinity ? 1 : 0;
        EXPECT_GT(covered, with.depth.size() / part) << "cull " << static_cast<int>(cull);
    }
}

TEST(DrawPass, ADepthOnlyPassOfTrianglesOfEverySizeGivesTheDepthsOfAPassWithItems) {
    // A depth-only pass sets up its small triangles eight at a time (AVX2, where the processor
    // has it) into records of its own, and draws them 4 x 2 pixels at a time: its depths must
    // be those of a pass that keeps items (the SetupTriangle road), bit for bit. Triangles
    // from a pixel to the whole view, straddling tiles, through the near plane, both windings,
    // every cull mode; one thread and two. Counts of seven past a multiple of eight: the last
    // seven take the general road in the same pass.
    TriangleList list;
    uint64_t state = 12345;
    auto uniform = [&](float lo, float hi) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return lo + (hi - lo) * static_cast<float>(state >> 40) / 16777216.0f;
    };
    for (int k = 0; k < 4007; ++k) {
        const float size = k % 50 == 0 ? 2.0f : k % 7 == 0 ? 0.2f : 0.02f;
        const vec3 c(uniform(-3.0f, 3.0f), uniform(-2.5f, 2.5f), uniform(-4.0f, 5.5f));
        auto corner = [&] {
            return c + size * vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        };
        const vec3 a = corner(), b = corner();
        add_triangle(list, a, b, corner());
    }
    Camera c;
    c.position = vec3(0, 0, 5);
    c.look_at = vec3(0.0f);
    c.fov_deg = 50.0f;
    const Bounds3 box{vec3(-3, -3, -5), vec3(3, 3, 6)};
    expect_same_depths_with_and_without_items(list, camera_matrices(c, 200, 150, box), 4);
    // Samples on the edges, where only the fill rule decides: small triangles whose corners
    // lie on pixel centres (an orthographic view of 1/128 world unit per pixel), every
    // orientation and both windings, alone (no neighbour to take the sample instead).
    TriangleList on_centres;
    auto centre = [](int i, int j, float z) {
        return vec3(-100.0f / 128.0f + (static_cast<float>(i) + 0.5f) / 128.0f,
                    75.0f / 128.0f - (static_cast<float>(j) + 0.5f) / 128.0f, z);
    };
    for (int j = 2, n = 0; j + 6 < 150; j += 6) {
        for (int i = 2; i + 6 < 200 && n < 767; i += 6, ++n) {
            const int a = 1 + n % 4, b = 1 + (n / 4) % 3, sx = n % 2 ? 1 : -1,
                      sy = (n / 2) % 2 ? 1 : -1;
            const int ci = sx > 0 ? i : i + 4, cj = sy > 0 ? j : j + 4;
            const float z = 0.1f * static_cast<float>(n % 5);
            add_triangle(on_centres, centre(ci, cj, z), centre(ci + sx * a, cj, z + 0.05f),
                         centre(ci, cj + sy * b, z - 0.05f), n % 3 == 0);
        }
    }
    Camera o;
    o.type = Camera::Type::Orthographic;
    o.position = vec3(0, 0, 5);
    o.look_at = vec3(0.0f);
    o.height = 150.0f / 128.0f;
    expect_same_depths_with_and_without_items(on_centres, camera_matrices(o, 200, 150, box), 64);
}

TEST(DrawPass, AFanOfLongSliversCoversEveryPixelExactlyOnce) {
    // Triangles are binned only in the tiles their edges reach, not every tile of their
    // bounds: a fan of long, thin triangles across a view of many tiles (every one a diagonal
    // through the bounds of its tiles), alternately wound, must still cover every pixel once:
    // counted in the stencil (up on front faces, down on back faces: +1 or -1 each), and in
    // the item buffer, on one thread and two.
    TriangleList fan;
    const vec3 apex(-2.0f, -1.5f, 0.0f);
    std::vector<vec3> rim;
    for (int k = 0; k <= 40; ++k)
        rim.emplace_back(-2.0f + 0.1f * static_cast<float>(k), 1.5f, 0.0f);
    for (int k = 1; k <= 30; ++k) rim.emplace_back(2.0f, 1.5f - 0.1f * static_cast<float>(k), 0.0f);
    for (size_t k = 0; k + 1 < rim.size(); ++k)
        add_triangle(fan, apex, rim[k + 1], rim[k], k % 2 == 1);
    Camera c;
    c.type = Camera::Type::Orthographic;
    c.position = vec3(0, 0, 5);
    c.look_at = vec3(0.0f);
    c.height = 2.0f;
    const CameraMatrices cam = camera_matrices(c, 300, 200, Bounds3{vec3(-2), vec3(2)});
    PipelineState count = counting_state();
    count.depth_test = false;
    for (int threads : {1, 2}) {
        RenderTargets t;
        t.clear(300, 200, 1, true, true);
        draw_pass(fan, cam, count, t, threads);
        RenderTargets items;
        items.clear(300, 200, 1, false, true);
        draw_pass(fan, cam, PipelineState{}, items, threads);
        int wrong = 0, uncovered = 0;
        for (int j = 0; j < 200; ++j) {
            for (int i = 0; i < 300; ++i) {
                const uint8_t n = t.stencil[t.index(i, j)];
                wrong += n == 1 || n == 255 ? 0 : 1;
                uncovered += items.primitive[items.index(i, j)] == RenderTargets::kNoPrimitive;
            }
        }
        EXPECT_EQ(wrong, 0) << threads << " threads";
        EXPECT_EQ(uncovered, 0) << threads << " threads";
    }
}

TEST(DrawPass, TheItemBufferNamesTheInputTriangleThroughClipping) {
    // A floor from under the camera to far ahead: its triangles cross the near plane, and
    // their clipped pieces still report the input triangle.
    TriangleList list = squares({{0.0f, 0.3f, true}});
    add_quad(list, vec3(-4, -1, 6), vec3(4, -1, 6), vec3(4, -1, -5), vec3(-4, -1, -5));
    RenderTargets one, two;
    one.clear(32, 32, 4, false, true);
    two.clear(32, 32, 4, false, true);
    draw_pass(list, camera(), PipelineState{}, one, 1, 7);
    draw_pass(list, camera(), PipelineState{}, two, 2, 7);
    EXPECT_EQ(one.primitive, two.primitive);
    EXPECT_EQ(one.depth, two.depth);
    int seen[4] = {0, 0, 0, 0};
    for (uint32_t p : one.primitive) {
        ASSERT_TRUE(p == RenderTargets::kNoPrimitive || p < 4u) << p;
        if (p < 4u) ++seen[p];
    }
    for (int k = 0; k < 4; ++k) EXPECT_GT(seen[k], 0) << k;  // square 0, 1; floor 2, 3
    // The bottom row sees the floor's near end, clipped at the near plane.
    uint32_t bottom = one.primitive[one.index(16, 31)];
    EXPECT_TRUE(bottom == 2u || bottom == 3u);
}

}  // namespace
}  // namespace svetlo
