// Analytic shapes for the ray tracer: sphere, quad, plane, box, cylinder and cone, each with
// a closed-form ray intersection. Quads and planes have their transform baked in; spheres,
// boxes, cylinders and cones under a transform intersect the ray taken to object space
// (the same t, since the direction is not renormalised).
#pragma once

#include <cstdint>

#include "svetlo/rt/ray.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

enum class ShapeKind : unsigned char { Sphere, Quad, Plane, Box, Cylinder, Cone };

struct AnalyticShape {
    ShapeKind kind = ShapeKind::Sphere;
    bool transformed = false;
    uint32_t material = 0;
    // Object-space parameters:
    vec3 p0{0.0f};  // sphere centre, quad corner, plane point, box min, cylinder/cone base
    vec3 p1{0.0f};  // quad edge_u, plane normal, box max, cylinder/cone axis
    vec3 p2{0.0f};  // quad edge_v
    float radius = 0.0f;
    float height = 0.0f;  // |axis| of a cylinder or cone
    Frame frame{};        // cylinder/cone: n along the axis; quad, plane: n is the unit normal
    mat4 to_local{1.0f};
    mat4 to_world{1.0f};
    mat3 normal_to_world{1.0f};  // inverse transpose of to_world's linear part
};

/// Builds the ray-tracing form of a scene shape (not meshes) with its transform.
AnalyticShape make_analytic_shape(const Shape& shape, const Transform& transform, uint32_t material);

/// World-space bounds; empty-infinite for planes.
Bounds3 shape_bounds(const AnalyticShape& s);

/// Closest hit with 0 < t < tmax; `part` names the face or surface that was hit.
bool intersect_shape(const AnalyticShape& s, const Ray& ray, float tmax, float& t, int& part);

struct ShapeSurface {
    vec3 p;   // world-space point, projected back onto the surface where that is exact
    vec3 n;   // unit outward geometric normal, world space
    vec2 uv;  // texture coordinates (docs/scene-format.md)
};

/// The surface at a hit found by intersect_shape.
ShapeSurface shape_surface(const AnalyticShape& s, const Ray& ray, float t, int part);

/// Surface area in world space; exact for untransformed shapes and under uniform scaling.
float shape_area(const AnalyticShape& s);

}  // namespace svetlo
