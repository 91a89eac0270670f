// svetlo's software rasterizer next to Mesa's llvmpipe (through OSMesa, an OpenGL 3.3 core
// context, an equivalent GLSL Blinn-Phong shader), on the same triangles, at 1920 x 1080,
// with the same number of threads, in one run:
//
//   geometry  32 spheres of 32,768 triangles (1,048,576 small triangles, ~3 pixels each)
//   fragment  8 large overlapping triangles covering the screen about three times
//
// A frame is the whole pipeline from world-space vertex buffers to a finished colour buffer
// (svetlo: vertex stage, clipping, binning, rasterization, shading, resolve; GL: clear, draw,
// glFinish). Prints milliseconds per frame (median of several) and the ratio of frame rates.
// Usage: svetlo_raster_bench [THREADS [FRAMES [WORKLOAD]]] (one thread count per process:
// llvmpipe reads LP_NUM_THREADS once). With WORKLOAD (map, zfail, zpass or depth), svetlo
// alone renders that shadow workload FRAMES times, for a profiler.
// Without OSMesa at build time, only svetlo's figures are printed.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_common.h"
#include "shadow_bench.h"
#include "svetlo/geometry/tessellate.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/raster_engine.h"

namespace svetlo {
namespace {

using bench::kHeight;
using bench::kWidth;
using bench::median;

struct Workload {
    std::string name;
    Mesh mesh;  // world space, with normals
    Camera camera;
};

Workload geometry_heavy() {
    Workload w;
    w.name = "geometry (1M small triangles)";
    TessellationOptions o;
    o.segments = 128;
    o.rings = 128;
    for (int k = 0; k < 32; ++k) {
        Object sphere;
        sphere.shape = Sphere{
            vec3(static_cast<float>(k % 8) - 3.5f, static_cast<float>(k / 8) - 1.5f, 0.0f), 0.48f};
        sphere.material = 0;
        Mesh m = tessellate(sphere, o);
        auto base = static_cast<uint32_t>(w.mesh.positions.size());
        w.mesh.positions.insert(w.mesh.positions.end(), m.positions.begin(), m.positions.end());
        w.mesh.normals.insert(w.mesh.normals.end(), m.normals.begin(), m.normals.end());
        for (uint32_t i : m.indices) w.mesh.indices.push_back(base + i);
    }
    w.camera.position = vec3(0.0f, 0.0f, 5.2f);
    w.camera.look_at = vec3(0.0f);
    w.camera.fov_deg = 45.0f;
    return w;
}

Workload fragment_heavy() {
    Workload w;
    w.name = "fragment (8 large triangles)";
    for (int k = 0; k < 8; ++k) {
        float z = -0.3f * static_cast<float>(k), a = 0.7f * static_cast<float>(k);
        vec3 n = glm::normalize(vec3(0.15f * std::cos(a), 0.15f * std::sin(a), 1.0f));
        Frame f = Frame::from_normal(n);
        vec3 c(0.0f, 0.0f, z);
        for (int v = 0; v < 3; ++v) {
            float t = a + 2.0f * kPi * static_cast<float>(v) / 3.0f;
            w.mesh.positions.push_back(c + 9.0f * (std::cos(t) * f.t + std::sin(t) * f.b));
            w.mesh.normals.push_back(n);
            w.mesh.indices.push_back(static_cast<uint32_t>(w.mesh.positions.size() - 1));
        }
    }
    w.camera.position = vec3(0.0f, 0.0f, 4.0f);
    w.camera.look_at = vec3(0.0f);
    w.camera.fov_deg = 60.0f;
    return w;
}

// The light both renderers use (bench_common.h has the material): one point light.
const vec3 kLightPos(2.0f, 3.0f, 4.0f);
constexpr float kIntensity = 30.0f;

double svetlo_frame_ms(const Workload& w, int threads, int frames) {
    // (No shadows: the GL side draws none.)
    return bench::svetlo_frame_ms(
        bench::raster_scene(w.camera, {PointLight{kLightPos, Color(kIntensity)}}, {&w.mesh},
                            ShadowTechnique::None),
        threads, frames);
}

#ifdef SVETLO_HAS_OSMESA

const char* kFragmentShader = R"(#version 330 core
in vec3 world;
in vec3 n;
uniform vec3 eye, light_pos;
uniform float kd, ks, shininess, intensity, ambient;
out vec4 color;
void main() {
    const float pi = 3.14159265;
    vec3 wo = normalize(eye - world);
    vec3 ns = normalize(n);
    if (dot(ns, wo) < 0.0) ns = -ns;  // two-sided
    vec3 d = light_pos - world;
    float d2 = dot(d, d);
    vec3 wi = d * inversesqrt(d2);
    float cos_t = max(dot(ns, wi), 0.0);
    vec3 h = normalize(wi + wo);
    float f = kd / pi + ks * (shininess + 8.0) / (8.0 * pi) * pow(max(dot(ns, h), 0.0), shininess);
    color = vec4(vec3(ambient + f * intensity * cos_t / d2), 1.0);
})";

double llvmpipe_frame_ms(const Workload& w, int threads, int frames) {
    std::vector<unsigned char> buffer;
    OSMesaContext ctx = bench::gl_context(threads, buffer);
    if (!ctx) return 0.0;
    GLuint program = bench::program(bench::kSceneVertexShader, nullptr, kFragmentShader);
    glUseProgram(program);
    GLuint vao, vbo[2], ibo;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, vbo);
    for (int a = 0; a < 2; ++a) {
        const auto& data = a == 0 ? w.mesh.positions : w.mesh.normals;
        glBindBuffer(GL_ARRAY_BUFFER, vbo[a]);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(vec3)),
                     data.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(static_cast<GLuint>(a), 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(static_cast<GLuint>(a));
    }
    glGenBuffers(1, &ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(w.mesh.indices.size() * sizeof(uint32_t)),
                 w.mesh.indices.data(), GL_STATIC_DRAW);
    Bounds3 bounds;
    for (vec3 p : w.mesh.positions) bounds.extend(p);
    CameraMatrices cam = camera_matrices(w.camera, kWidth, kHeight, bounds);
    mat4 vp = cam.view_projection();
    glUniformMatrix4fv(glGetUniformLocation(program, "view_projection"), 1, GL_FALSE, &vp[0][0]);
    glUniform3f(glGetUniformLocation(program, "eye"), w.camera.position.x, w.camera.position.y,
                w.camera.position.z);
    glUniform3f(glGetUniformLocation(program, "light_pos"), kLightPos.x, kLightPos.y, kLightPos.z);
    glUniform1f(glGetUniformLocation(program, "kd"), bench::kKd);
    glUniform1f(glGetUniformLocation(program, "ks"), bench::kKs);
    glUniform1f(glGetUniformLocation(program, "shininess"), bench::kShininess);
    glUniform1f(glGetUniformLocation(program, "intensity"), kIntensity);
    glUniform1f(glGetUniformLocation(program, "ambient"), bench::kAmbient);
    glViewport(0, 0, kWidth, kHeight);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    std::vector<double> ms;
    for (int k = 0; k < frames + 1; ++k) {  // the first frame compiles the shaders: not counted
        auto t0 = std::chrono::steady_clock::now();
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(w.mesh.indices.size()), GL_UNSIGNED_INT,
                       nullptr);
        glFinish();
        if (k > 0)
            ms.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count());
    }
    OSMesaDestroyContext(ctx);
    return median(ms);
}

#endif

}  // namespace
}  // namespace svetlo

int main(int argc, char** argv) {
    using namespace svetlo;
    // llvmpipe reads LP_NUM_THREADS once per process: one thread count per run.
    int threads = argc > 1 ? std::max(1, std::atoi(argv[1])) : 1;
    int frames = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
    if (argc > 3) {
        // One workload, svetlo alone (for a profiler).
        const std::string name = argv[3];
        if (name == "geometry" || name == "fragment") {
            const Workload w = name == "geometry" ? geometry_heavy() : fragment_heavy();
            std::printf("%s: %.1f ms per frame (median of %d, %d threads)\n", name.c_str(),
                        svetlo_frame_ms(w, threads, frames), frames, threads);
            return 0;
        }
        if (bench::shadow_profile(argv[3], threads, frames)) return 0;
        std::fprintf(stderr,
                     "unknown workload %s (geometry, fragment, map, zfail, zpass or depth)\n",
                     argv[3]);
        return 1;
    }
    std::printf("%-32s %7s %12s %12s %10s\n", "workload, 1920x1080", "threads", "svetlo ms",
                "llvmpipe ms", "ratio");
    for (const Workload& w : {geometry_heavy(), fragment_heavy()}) {
        double ours = svetlo_frame_ms(w, threads, frames);
#ifdef SVETLO_HAS_OSMESA
        double theirs = llvmpipe_frame_ms(w, threads, frames);
        std::printf("%-32s %7d %12.1f %12.1f %9.2fx\n", w.name.c_str(), threads, ours, theirs,
                    ours > 0.0 ? theirs / ours : 0.0);
#else
        std::printf("%-32s %7d %12.1f %12s %10s\n", w.name.c_str(), threads, ours, "-", "-");
#endif
        std::fflush(stdout);
    }
    bench::shadow_benchmarks(threads, frames);
    return 0;
}
