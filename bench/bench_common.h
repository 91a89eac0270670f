// What the rasterizer's benchmarks share: the frame size, medians, and (with OSMesa) an
// OpenGL 3.3 core context on llvmpipe and shader compilation.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

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

#ifdef SVETLO_HAS_OSMESA

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

inline GLuint compile(GLenum type, const char* source) {
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        std::fprintf(stderr, "shader: %s\n", log);
        std::exit(1);
    }
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
    if (!ok) {
        char log[1024];
        glGetProgramInfoLog(p, sizeof log, nullptr, log);
        std::fprintf(stderr, "program: %s\n", log);
        std::exit(1);
    }
    return p;
}

#endif

}  // namespace svetlo::bench
