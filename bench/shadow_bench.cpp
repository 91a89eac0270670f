// The rasterizer's shadows next to Mesa's llvmpipe (OSMesa, OpenGL 3.3 core), the same work on
// both sides, at 1920 x 1080, with the same threads:
//
//   shadow map     a 2048^2 depth pass from a spot light over 1,048,576 triangles (32 spheres
//                  before a wall), then the frame with 3 x 3 PCF (GL: sampler2DShadow with
//                  GL_LINEAR, nine textureOffset taps, each four comparisons, as svetlo's
//                  bilinear taps; glPolygonOffset for the bias)
//   shadow volume  12 closed spheres (96,768 triangles) on a floor under a point light, z-fail
//                  (svetlo also with its default count, `auto`, which picks z-pass here)
//                  (GL: a depth and ambient pass, the volumes made by a geometry shader from
//                  triangles with adjacency, extruded to w = 0, glStencilOpSeparate with
//                  wrapping, depth clamp; then the lit pass where the stencil is 0)
//
// svetlo's frame is one render() with render.shadows map or volume: its shadow passes, the
// volumes' construction on the CPU and the colour pass. Then svetlo alone: the depth-only
// pass in triangles per second per thread, each technique's cost on the volume scene, and PCF's
// cost against its kernel.
#include "shadow_bench.h"

#include <chrono>
#include <map>

#include "bench_common.h"
#include "svetlo/geometry/tessellate.h"
#include "svetlo/geometry/triangle_list.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/draw_pass.h"
#include "svetlo/raster/raster_engine.h"

namespace svetlo::bench {

namespace {

constexpr int kMapResolution = 2048;

struct ShadowScene {
    std::string name;
    Mesh occluders;  // world space, with normals
    Mesh receiver;   // a wall or a floor: two triangles
    Camera camera;
    Light light;
};

void append(Mesh& to, const Mesh& m) {
    auto base = static_cast<uint32_t>(to.positions.size());
    to.positions.insert(to.positions.end(), m.positions.begin(), m.positions.end());
    to.normals.insert(to.normals.end(), m.normals.begin(), m.normals.end());
    for (uint32_t i : m.indices) to.indices.push_back(base + i);
}

Mesh quad(vec3 corner, vec3 u, vec3 v) {
    Mesh m;
    vec3 n = glm::normalize(glm::cross(u, v));
    m.positions = {corner, corner + u, corner + u + v, corner + v};
    m.normals = {n, n, n, n};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

Mesh spheres(int count, int per_row, float spacing, float radius, int segments, vec3 origin,
             bool vertical) {
    Mesh out;
    TessellationOptions o;
    o.segments = segments;
    o.rings = segments;
    for (int k = 0; k < count; ++k) {
        float a = spacing * (static_cast<float>(k % per_row) - 0.5f * (per_row - 1));
        float b = spacing * static_cast<float>(k / per_row);
        Object sphere;
        sphere.shape = Sphere{origin + (vertical ? vec3(a, b, 0.0f) : vec3(a, 0.0f, -b)), radius};
        append(out, tessellate(sphere, o));
    }
    return out;
}

ShadowScene map_scene() {
    ShadowScene s;
    s.name = "shadow map (1M tris, spot, 2048^2, PCF 3x3)";
    s.occluders = spheres(32, 8, 1.0f, 0.48f, 128, vec3(0.0f, -1.5f, 0.0f), true);
    s.receiver = quad(vec3(-7.0f, -4.5f, -1.2f), vec3(14.0f, 0.0f, 0.0f), vec3(0.0f, 9.0f, 0.0f));
    s.camera.position = vec3(0.0f, 0.0f, 5.2f);
    s.camera.look_at = vec3(0.0f);
    s.camera.fov_deg = 50.0f;
    SpotLight spot;
    spot.position = vec3(1.5f, 2.0f, 5.0f);
    spot.direction = glm::normalize(vec3(0.0f, 0.0f, -1.2f) - spot.position);
    spot.intensity = Color(60.0f);
    spot.inner_deg = 40.0f;
    spot.outer_deg = 50.0f;
    s.light = spot;
    return s;
}

ShadowScene volume_scene() {
    ShadowScene s;
    s.name = "shadow volume (97k tris, point, z-fail)";
    s.occluders = spheres(12, 4, 1.3f, 0.5f, 64, vec3(0.0f, 0.6f, 1.0f), false);
    s.receiver = quad(vec3(-6.0f, 0.0f, 4.0f), vec3(12.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, -10.0f));
    s.camera.position = vec3(0.0f, 4.0f, 7.0f);
    s.camera.look_at = vec3(0.0f, 0.3f, 0.0f);
    s.camera.fov_deg = 45.0f;
    s.light = PointLight{vec3(1.0f, 5.0f, 2.0f), Color(40.0f)};
    return s;
}

Scene svetlo_scene(const ShadowScene& s, ShadowTechnique technique, int kernel = 3) {
    Scene scene = raster_scene(s.camera, {s.light}, {&s.occluders, &s.receiver}, technique);
    scene.render.shadow_map.resolution = kMapResolution;
    scene.render.shadow_map.filter = kernel > 1 ? ShadowFilter::Pcf : ShadowFilter::None;
    scene.render.shadow_map.kernel = kernel;
    return scene;
}

/// The spot light's view for its map (as svetlo's: around the cone, a margin for the filter).
CameraMatrices spot_view(const SpotLight& spot, int res) {
    CameraMatrices cam;
    vec3 up = std::abs(spot.direction.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0);
    cam.view = glm::lookAt(spot.position, spot.position + spot.direction, up);
    cam.near = 0.05f;
    cam.far = 100.0f;
    cam.projection =
        glm::perspective(2.0f * radians(spot.outer_deg) * 1.05f, 1.0f, cam.near, cam.far);
    cam.width = cam.height = res;
    cam.eye = spot.position;
    cam.forward = spot.direction;
    return cam;
}

/// svetlo's depth-only pass alone, from the spot light, over the map scene's triangles: the
/// median frame in ms.
double depth_pass_ms(const ShadowScene& s, int threads, int frames, size_t& triangles) {
    Object o;
    o.shape = s.occluders;
    TriangleList list = build_triangle_list({&o}, TessellationOptions{}, threads);
    triangles = list.triangle_count();
    const CameraMatrices cam = spot_view(std::get<SpotLight>(s.light), kMapResolution);
    RenderTargets targets;
    PassMemory memory;  // kept from pass to pass, as a GL context keeps its buffers
    std::vector<double> ms;
    for (int k = 0; k < frames + 1; ++k) {
        targets.clear(kMapResolution, kMapResolution);
        auto t0 = std::chrono::steady_clock::now();
        draw_pass(list, cam, PipelineState{}, targets, threads, 0, &memory);
        double frame =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        if (k > 0) ms.push_back(frame);
    }
    return median(ms);
}

#ifdef SVETLO_HAS_OSMESA

// Blinn-Phong, normalised as svetlo's, two-sided; a point light or a spot light (smoothstep
// between the cones' cosines), its term times the visibility `v`.
const char* kLightingFunctions = R"(
uniform vec3 eye, light_pos, spot_dir;
uniform float kd, ks, shininess, intensity, cos_inner, cos_outer;
vec3 lit(vec3 world, vec3 n, float v) {
    const float pi = 3.14159265;
    vec3 wo = normalize(eye - world);
    vec3 ns = normalize(n);
    if (dot(ns, wo) < 0.0) ns = -ns;
    vec3 d = light_pos - world;
    float d2 = dot(d, d);
    vec3 wi = d * inversesqrt(d2);
    float cone = 1.0;
    if (cos_outer > -1.0) {
        float t = clamp((dot(-wi, spot_dir) - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0);
        cone = t * t * (3.0 - 2.0 * t);
    }
    float cos_t = max(dot(ns, wi), 0.0);
    vec3 h = normalize(wi + wo);
    float f = kd / pi + ks * (shininess + 8.0) / (8.0 * pi) * pow(max(dot(ns, h), 0.0), shininess);
    return vec3(v * f * intensity * cone * cos_t / d2);
}
)";

const std::string kMapFragment = std::string(R"(#version 330 core
in vec3 world;
in vec3 n;
uniform mat4 light_vp;
uniform sampler2DShadow shadow_map;
uniform float ambient;
out vec4 color;
)") + kLightingFunctions + R"(
void main() {
    vec4 lc = light_vp * vec4(world, 1.0);
    vec3 c = lc.xyz / lc.w * 0.5 + 0.5;
    // (GLSL 3.30 wants constant offsets: the nine taps written out.)
    float v = textureOffset(shadow_map, c, ivec2(-1, -1)) + textureOffset(shadow_map, c, ivec2(0, -1)) +
              textureOffset(shadow_map, c, ivec2(1, -1)) + textureOffset(shadow_map, c, ivec2(-1, 0)) +
              textureOffset(shadow_map, c, ivec2(0, 0)) + textureOffset(shadow_map, c, ivec2(1, 0)) +
              textureOffset(shadow_map, c, ivec2(-1, 1)) + textureOffset(shadow_map, c, ivec2(0, 1)) +
              textureOffset(shadow_map, c, ivec2(1, 1));
    color = vec4(vec3(ambient) + lit(world, n, v / 9.0), 1.0);
})";

const char* kDepthVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 light_vp;
void main() { gl_Position = light_vp * vec4(position, 1.0); })";

const char* kEmptyFragment = R"(#version 330 core
void main() {})";

// The volumes of the triangles facing the light: near cap, far cap at w = 0, and a side on
// every edge whose neighbour faces away (or that has none: the neighbour index is then the
// triangle's own third vertex, which faces away).
const char* kVolumeGeometry = R"(#version 330 core
layout(triangles_adjacency) in;
layout(triangle_strip, max_vertices = 18) out;
in vec3 world_v[];
uniform mat4 view_projection;
uniform vec3 light_pos;
vec4 near(vec3 p) { return view_projection * vec4(p, 1.0); }
vec4 far(vec3 p) { return view_projection * vec4(p - light_pos, 0.0); }
bool faces(vec3 a, vec3 b, vec3 c) { return dot(cross(b - a, c - a), light_pos - a) > 0.0; }
void main() {
    vec3 p[6];
    for (int i = 0; i < 6; ++i) p[i] = world_v[i];
    if (!faces(p[0], p[2], p[4])) return;
    for (int e = 0; e < 3; ++e) {
        int a = 2 * e, b = (2 * e + 2) % 6, adj = 2 * e + 1;
        if (faces(p[b], p[a], p[adj])) continue;
        gl_Position = near(p[a]); EmitVertex();
        gl_Position = far(p[a]); EmitVertex();
        gl_Position = near(p[b]); EmitVertex();
        gl_Position = far(p[b]); EmitVertex();
        EndPrimitive();
    }
    gl_Position = near(p[0]); EmitVertex();
    gl_Position = near(p[2]); EmitVertex();
    gl_Position = near(p[4]); EmitVertex();
    EndPrimitive();
    gl_Position = far(p[0]); EmitVertex();
    gl_Position = far(p[4]); EmitVertex();
    gl_Position = far(p[2]); EmitVertex();
    EndPrimitive();
})";

const char* kVolumeVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
out vec3 world_v;
void main() { world_v = position; })";

const char* kAmbientFragment = R"(#version 330 core
uniform float ambient;
out vec4 color;
void main() { color = vec4(vec3(ambient), 1.0); })";

const std::string kLitFragment = std::string(R"(#version 330 core
in vec3 world;
in vec3 n;
out vec4 color;
)") + kLightingFunctions + R"(
void main() { color = vec4(lit(world, n, 1.0), 1.0); })";

/// The scene's triangles in GL buffers: positions, normals, indices, and (for volumes) the
/// indices with adjacency, six per triangle.
struct GlMesh {
    GLuint vao = 0, ibo = 0, adjacency = 0;
    GLsizei count = 0, adjacency_count = 0;
};

GlMesh upload(const Mesh& m, bool with_adjacency) {
    GlMesh g;
    glGenVertexArrays(1, &g.vao);
    glBindVertexArray(g.vao);
    GLuint vbo[2];
    glGenBuffers(2, vbo);
    for (int a = 0; a < 2; ++a) {
        const auto& data = a == 0 ? m.positions : m.normals;
        glBindBuffer(GL_ARRAY_BUFFER, vbo[a]);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(vec3)),
                     data.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(static_cast<GLuint>(a), 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(static_cast<GLuint>(a));
    }
    glGenBuffers(1, &g.ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(m.indices.size() * 4),
                 m.indices.data(), GL_STATIC_DRAW);
    g.count = static_cast<GLsizei>(m.indices.size());
    if (!with_adjacency) return g;
    // Vertices welded by position, then each directed edge's triangle.
    std::map<std::tuple<float, float, float>, uint32_t> weld;
    std::vector<uint32_t> canon(m.positions.size());
    for (size_t v = 0; v < m.positions.size(); ++v) {
        vec3 p = m.positions[v];
        canon[v] = weld.try_emplace({p.x, p.y, p.z}, static_cast<uint32_t>(v)).first->second;
    }
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> third;  // edge (a, b) -> opposite vertex
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        for (int e = 0; e < 3; ++e) {
            uint32_t a = canon[m.indices[t + e]], b = canon[m.indices[t + (e + 1) % 3]];
            third[{a, b}] = m.indices[t + (e + 2) % 3];
        }
    }
    std::vector<uint32_t> adj;
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        for (int e = 0; e < 3; ++e) {
            uint32_t a = m.indices[t + e], b = m.indices[t + (e + 1) % 3];
            auto it = third.find({canon[b], canon[a]});
            adj.push_back(a);
            adj.push_back(it != third.end() ? it->second : m.indices[t + (e + 2) % 3]);
        }
    }
    glGenBuffers(1, &g.adjacency);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.adjacency);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(adj.size() * 4), adj.data(),
                 GL_STATIC_DRAW);
    g.adjacency_count = static_cast<GLsizei>(adj.size());
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
    return g;
}

void set_lighting(GLuint p, const ShadowScene& s, const CameraMatrices& cam) {
    glUseProgram(p);
    mat4 vp = cam.view_projection();
    glUniformMatrix4fv(glGetUniformLocation(p, "view_projection"), 1, GL_FALSE, &vp[0][0]);
    glUniform3fv(glGetUniformLocation(p, "eye"), 1, &s.camera.position[0]);
    vec3 pos(0.0f), dir(0.0f, 0.0f, -1.0f);
    float intensity = 0.0f, cos_inner = 1.0f, cos_outer = -2.0f;
    if (const auto* spot = std::get_if<SpotLight>(&s.light)) {
        pos = spot->position;
        dir = spot->direction;
        intensity = spot->intensity.r;
        cos_inner = std::cos(radians(spot->inner_deg));
        cos_outer = std::cos(radians(spot->outer_deg));
    } else {
        const auto& point = std::get<PointLight>(s.light);
        pos = point.position;
        intensity = point.intensity.r;
    }
    glUniform3fv(glGetUniformLocation(p, "light_pos"), 1, &pos[0]);
    glUniform3fv(glGetUniformLocation(p, "spot_dir"), 1, &dir[0]);
    glUniform1f(glGetUniformLocation(p, "kd"), kKd);
    glUniform1f(glGetUniformLocation(p, "ks"), kKs);
    glUniform1f(glGetUniformLocation(p, "shininess"), kShininess);
    glUniform1f(glGetUniformLocation(p, "intensity"), intensity);
    glUniform1f(glGetUniformLocation(p, "cos_inner"), cos_inner);
    glUniform1f(glGetUniformLocation(p, "cos_outer"), cos_outer);
    glUniform1f(glGetUniformLocation(p, "ambient"), kAmbient);
}

Mesh whole(const ShadowScene& s) {
    Mesh m = s.occluders;
    append(m, s.receiver);
    return m;
}

CameraMatrices frame_camera(const Mesh& m, const Camera& camera) {
    Bounds3 bounds;
    for (vec3 p : m.positions) bounds.extend(p);
    return camera_matrices(camera, kWidth, kHeight, bounds);
}

template <class Frame>
double timed_frames(int frames, Frame&& frame) {
    std::vector<double> ms;
    for (int k = 0; k < frames + 1; ++k) {  // the first frame compiles the shaders: not counted
        auto t0 = std::chrono::steady_clock::now();
        frame();
        glFinish();
        double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                       .count();
        if (k > 0) ms.push_back(t);
    }
    return median(ms);
}

double llvmpipe_map_ms(const ShadowScene& s, int threads, int frames, double* depth_only) {
    std::vector<unsigned char> buffer;
    OSMesaContext ctx = gl_context(threads, buffer);
    if (!ctx) return 0.0;
    const Mesh m = whole(s);
    GlMesh g = upload(m, false);
    GLuint depth_program = program(kDepthVertex, nullptr, kEmptyFragment);
    GLuint main_program = program(kSceneVertexShader, nullptr, kMapFragment.c_str());
    // The map: a 24-bit depth texture that compares (sampler2DShadow), filtered bilinearly.
    GLuint tex, fbo;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, kMapResolution, kMapResolution, 0,
                 GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, tex, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    const CameraMatrices light = spot_view(std::get<SpotLight>(s.light), kMapResolution);
    const mat4 light_vp = light.view_projection();
    glUseProgram(depth_program);
    glUniformMatrix4fv(glGetUniformLocation(depth_program, "light_vp"), 1, GL_FALSE,
                       &light_vp[0][0]);
    set_lighting(main_program, s, frame_camera(m, s.camera));
    glUniformMatrix4fv(glGetUniformLocation(main_program, "light_vp"), 1, GL_FALSE,
                       &light_vp[0][0]);
    glUniform1i(glGetUniformLocation(main_program, "shadow_map"), 0);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    auto depth_pass = [&] {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, kMapResolution, kMapResolution);
        glClear(GL_DEPTH_BUFFER_BIT);
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.5f, 4.0f);
        glUseProgram(depth_program);
        glDrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
        glDisable(GL_POLYGON_OFFSET_FILL);
    };
    if (depth_only) *depth_only = timed_frames(frames, depth_pass);
    double ms = timed_frames(frames, [&] {
        depth_pass();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, kWidth, kHeight);
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glUseProgram(main_program);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, tex);
        glDrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
    });
    OSMesaDestroyContext(ctx);
    return ms;
}

double llvmpipe_volume_ms(const ShadowScene& s, int threads, int frames) {
    std::vector<unsigned char> buffer;
    OSMesaContext ctx = gl_context(threads, buffer);
    if (!ctx) return 0.0;
    const Mesh m = whole(s);
    GlMesh g = upload(m, true);
    const CameraMatrices cam = frame_camera(m, s.camera);
    GLuint ambient_program = program(kSceneVertexShader, nullptr, kAmbientFragment);
    GLuint volume_program = program(kVolumeVertex, kVolumeGeometry, kEmptyFragment);
    GLuint lit_program = program(kSceneVertexShader, nullptr, kLitFragment.c_str());
    set_lighting(ambient_program, s, cam);
    set_lighting(volume_program, s, cam);
    set_lighting(lit_program, s, cam);
    glViewport(0, 0, kWidth, kHeight);
    glDisable(GL_CULL_FACE);
    double ms = timed_frames(frames, [&] {
        glClearColor(0, 0, 0, 1);
        glClearStencil(0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
        // 1. Depth and ambient.
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_STENCIL_TEST);
        glDisable(GL_BLEND);
        glUseProgram(ambient_program);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
        glDrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
        // 2. The volumes, z-fail, into the stencil.
        glDepthMask(GL_FALSE);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glEnable(GL_DEPTH_CLAMP);
        glEnable(GL_STENCIL_TEST);
        glStencilFunc(GL_ALWAYS, 0, 0xff);
        glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
        glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
        glUseProgram(volume_program);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.adjacency);
        glDrawElements(GL_TRIANGLES_ADJACENCY, g.adjacency_count, GL_UNSIGNED_INT, nullptr);
        glDisable(GL_DEPTH_CLAMP);
        // 3. The light where the count is 0, added.
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glStencilFunc(GL_EQUAL, 0, 0xff);
        glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        glDepthFunc(GL_EQUAL);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        glUseProgram(lit_program);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
        glDrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
    });
    OSMesaDestroyContext(ctx);
    return ms;
}

#endif

void row(const std::string& name, int threads, double ours, double theirs) {
    if (theirs > 0.0) {
        std::printf("%-46s %7d %12.1f %12.1f %9.2fx\n", name.c_str(), threads, ours, theirs,
                    ours > 0.0 ? theirs / ours : 0.0);
    } else {
        std::printf("%-46s %7d %12.1f %12s %10s\n", name.c_str(), threads, ours, "-", "-");
    }
    std::fflush(stdout);
}

}  // namespace

void shadow_benchmarks(int threads, int frames) {
    const ShadowScene map = map_scene(), volume = volume_scene();
    double gl_map = 0.0, gl_volume = 0.0, gl_depth = 0.0;
#ifdef SVETLO_HAS_OSMESA
    gl_map = llvmpipe_map_ms(map, threads, frames, &gl_depth);
    gl_volume = llvmpipe_volume_ms(volume, threads, frames);
#endif
    std::printf("\n%-46s %7s %12s %12s %10s\n", "shadows, 1920x1080", "threads", "svetlo ms",
                "llvmpipe ms", "ratio");
    row(map.name, threads,
        svetlo_frame_ms(svetlo_scene(map, ShadowTechnique::Map), threads, frames), gl_map);
    Scene zfail = svetlo_scene(volume, ShadowTechnique::Volume);
    zfail.render.shadow_teaching.volume_count = VolumeCount::ZFail;  // as the GL side
    row(volume.name, threads, svetlo_frame_ms(zfail, threads, frames), gl_volume);
    row("  the same, count auto (z-pass here)", threads,
        svetlo_frame_ms(svetlo_scene(volume, ShadowTechnique::Volume), threads, frames), gl_volume);
    size_t triangles = 0;
    const double depth = depth_pass_ms(map, threads, frames, triangles);
    row("depth-only pass, 1M tris at 2048^2", threads, depth, gl_depth);
    std::printf("  svetlo: %.1f M triangles/s per thread\n",
                static_cast<double>(triangles) / (depth * 1e3) / threads);
    std::printf("\nsvetlo alone, %s, ms per frame:\n", volume.name.c_str());
    for (ShadowTechnique t :
         {ShadowTechnique::None, ShadowTechnique::Raytraced, ShadowTechnique::Map,
          ShadowTechnique::Volume, ShadowTechnique::Planar}) {
        std::printf("  %-10s %8.1f\n", std::string(name_of(kShadowTechniques, t)).c_str(),
                    svetlo_frame_ms(svetlo_scene(volume, t), threads, frames));
    }
    std::printf("\nsvetlo alone, %s, ms per frame against the PCF kernel:\n", map.name.c_str());
    for (int kernel : {1, 3, 5, 7, 9}) {
        std::printf(
            "  %dx%d %8.1f\n", kernel, kernel,
            svetlo_frame_ms(svetlo_scene(map, ShadowTechnique::Map, kernel), threads, frames));
    }
}

bool shadow_profile(const char* workload, int threads, int frames) {
    const std::string w = workload;
    double ms = 0.0;
    if (w == "map") {
        ms = svetlo_frame_ms(svetlo_scene(map_scene(), ShadowTechnique::Map), threads, frames);
    } else if (w == "zfail" || w == "zpass") {
        Scene scene = svetlo_scene(volume_scene(), ShadowTechnique::Volume);
        scene.render.shadow_teaching.volume_count =
            w == "zfail" ? VolumeCount::ZFail : VolumeCount::ZPass;
        ms = svetlo_frame_ms(scene, threads, frames);
    } else if (w == "depth") {
        size_t triangles = 0;
        ms = depth_pass_ms(map_scene(), threads, frames, triangles);
    } else {
        return false;
    }
    std::printf("%s: %.1f ms per frame (median of %d, %d threads)\n", workload, ms, frames,
                threads);
    return true;
}

}  // namespace svetlo::bench
