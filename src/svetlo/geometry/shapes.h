// Analytic shapes for the ray tracer: sphere, quad, plane, box, cylinder and cone, each with
// a closed-form ray intersection. Quads and planes have their transform baked in; spheres,
// boxes, cylinders and cones under a transform intersect the ray taken to object space
// (the same t, since the direction is not renormalised). CSG trees (csg.h) and implicit
// surfaces (sdf.h) are shapes too, held by pointer and always in world space.
#pragma once

#include <cstdint>
#include <memory>

#include "svetlo/geometry/ray.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

enum class ShapeKind : unsigned char { Sphere, Quad, Plane, Box, Cylinder, Cone, Csg, Implicit };

class CsgShape;
class SdfShape;

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
    mat3 normal_to_world{1.0f};           // inverse transpose of to_world's linear part
    std::shared_ptr<const CsgShape> csg;  // kind Csg
    std::shared_ptr<const SdfShape> sdf;  // kind Implicit
};

/// Where a ray meets a shape. Analytic shapes set t and part (the face); a CSG hit also names
/// the leaf (`sub`) and, on a mesh leaf, the triangle (`part`) and its barycentrics.
struct ShapeHit {
    float t = kInfinity;
    int part = 0;
    uint32_t sub = 0;
    float u = 0.0f, v = 0.0f;
};

/// Builds the ray-tracing form of a scene shape (not meshes) with its transform.
AnalyticShape make_analytic_shape(const Shape& shape, const Transform& transform,
                                  uint32_t material);

/// World-space bounds; empty-infinite for planes.
Bounds3 shape_bounds(const AnalyticShape& s);

/// Closest hit with 0 < t < tmax.
bool intersect_shape(const AnalyticShape& s, const Ray& ray, float tmax, ShapeHit& hit);

/// For the closed convex shapes (sphere, box, cylinder, cone): the whole line o + t d, t of
/// any sign, meets the solid in [t0, t1]; part0 and part1 name the faces there. False when
/// the line misses it. CSG classifies rays with these intervals.
bool shape_interval(const AnalyticShape& s, const Ray& ray, float& t0, int& part0, float& t1,
                    int& part1);

/// True when the world-space point lies inside the closed shape (sphere, box, cylinder,
/// cone, CSG, implicit); false for quads and planes.
bool shape_contains(const AnalyticShape& s, vec3 p);

struct ShapeSurface {
    vec3 p;   // world-space point, projected back onto the surface where that is exact
    vec3 n;   // unit outward geometric normal, world space
    vec3 ns;  // unit shading normal (a smooth CSG mesh leaf interpolates), same side as n
    vec2 uv;  // texture coordinates (docs/scene-format.md)
    // Unit tangent along increasing u (xyz) and the bitangent's side (w), as Mesh::tangents;
    // zero where the shape has none (CSG, implicit, a sphere's poles).
    vec4 tangent{0.0f};
    uint32_t material;  // the shape's, or the CSG leaf's
};

/// The surface at a hit found by intersect_shape.
ShapeSurface shape_surface(const AnalyticShape& s, const Ray& ray, const ShapeHit& hit);

/// Surface area in world space; exact for untransformed shapes and under uniform scaling.
float shape_area(const AnalyticShape& s);

}  // namespace svetlo
