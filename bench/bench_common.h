// What the rasterizer's benchmarks share: the frame size, medians, and (with OSMesa) an
// OpenGL 3.3 core context on llvmpipe and shader compilation.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "svetlo/raster/raster_engine.h"

#ifdef SVETLO_HAS_OSMESA
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
#endif

namespace svetlo::bench {

constexpr int kWidth = 1920, kHeight = 1080;

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

/// The material and ambient term every workload uses on both sides: Blinn-Phong (svetlo's
/// normalisation), kd 0.6, ks 0.3, shininess 32, ambient 0.05.
constexpr float kKd = 0.6f, kKs = 0.3f, kShininess = 32.0f, kAmbient = 0.05f;

/// A raster scene of `meshes` (world space) in that material under `lights`, seen by `camera`
/// at kWidth x kHeight, with the shadow technique `shadows`.
inline Scene raster_scene(const Camera& camera, std::vector<Light> lights,
                          const std::vector<const Mesh*>& meshes, ShadowTechnique shadows) {
    Scene scene;
    scene.camera = camera;
    scene.film = Film{kWidth, kHeight};
    scene.render.engine = "raster";
    scene.render.shadows = shadows;
    scene.render.ambient = Color(kAmbient);
    PhongMaterial m;
    m.blinn = true;
    m.ka = ColorSource::constant(Color(1.0f));
    m.kd = ColorSource::constant(Color(kKd));
    m.ks = ColorSource::constant(Color(kKs));
    m.shininess = kShininess;
    scene.materials = {m};
    scene.material_names = {"m"};
    scene.lights = std::move(lights);
    for (const Mesh* mesh : meshes) {
        Object o;
        o.shape = *mesh;
        o.material = 0;
        scene.objects.push_back(o);
    }
    return scene;
}

/// svetlo's rasterizer on `scene`: the median of `frames` frames in ms, by one renderer frame
/// after frame (it keeps its buffers, as a GL context does; the first frame, which
/// allocates them, is not counted, as GL's first, which compiles the shaders, is not).
inline double svetlo_frame_ms(const Scene& scene, int threads, int frames) {
    RenderOptions options;
    options.threads = threads;
    RasterRenderer renderer;
    std::vector<double> ms;
    for (int k = 0; k < frames + 1; ++k) {
        double frame = renderer.render(scene, options).stats.seconds * 1e3;
        if (k > 0) ms.push_back(frame);
    }
    return median(ms);
}

#ifdef SVETLO_HAS_OSMESA

/// World-space positions and normals in, world position and normal out to the fragments.
inline const char* const kSceneVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 view_projection;
out vec3 world;
out vec3 n;
void main() {
    world = position;
    n = normal;
    gl_Position = view_projection * vec4(position, 1.0);
})";

/// An OpenGL 3.3 core context drawing into `buffer` (kWidth x kHeight RGBA), with a depth and
/// a stencil buffer, on `threads` llvmpipe threads (LP_NUM_THREADS is read once per process).
inline OSMesaContext gl_context(int threads, std::vector<unsigned char>& buffer) {
    setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_STENCIL_BITS,
                           8,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx) {
        std::fprintf(stderr, "OSMesa: no OpenGL 3.3 core context\n");
        return nullptr;
    }
    buffer.assign(static_cast<size_t>(kWidth) * kHeight * 4, 0);
    OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, kWidth, kHeight);
    return ctx;
}

/// Stops the benchmark with GL's log when a shader or program (`what`) failed.
template <class GetLog>
void stop_unless(GLint ok, const char* what, GLuint object, GetLog get_log) {
    if (ok) return;
    char log[1024];
    get_log(object, static_cast<GLsizei>(sizeof log), nullptr, log);
    std::fprintf(stderr, "%s: %s\n", what, log);
    std::exit(1);
}

inline GLuint compile(GLenum type, const char* source) {
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    stop_unless(ok, "shader", s, glGetShaderInfoLog);
    return s;
}

/// A program of the given stages (null sources are left out).
inline GLuint program(const char* vertex, const char* geometry, const char* fragment) {
    GLuint p = glCreateProgram();
    glAttachShader(p, compile(GL_VERTEX_SHADER, vertex));
    if (geometry) glAttachShader(p, compile(GL_GEOMETRY_SHADER, geometry));
    if (fragment) glAttachShader(p, compile(GL_FRAGMENT_SHADER, fragment));
    glLinkProgram(p);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    stop_unless(ok, "program", p, glGetProgramInfoLog);
    return p;
}

#endif

}  // namespace svetlo::bench
