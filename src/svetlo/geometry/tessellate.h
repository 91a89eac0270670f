// Every shape as triangles, behind one function, so that the rasterizer and the radiosity
// solver draw what the ray tracer intersects. Analytic shapes are sampled on their natural
// parameters (longitude / latitude, angle / height) with exact normals and the ray tracer's
// texture coordinates; meshes pass through; CSG trees and implicit surfaces are polygonised
// by surface nets (Gibson, "Constrained Elastic Surface Nets", MERL TR-99-24, 1998), a dual
// method: one vertex per grid cell the surface crosses, one quad per crossed grid edge.
#pragma once

#include "svetlo/scene/scene.h"

namespace svetlo {

struct TessellationOptions {
    int segments = 64;           // around a sphere, cylinder or cone
    int rings = 32;              // from pole to pole of a sphere
    int grid = 96;               // cells along the longest side of a CSG or implicit surface
    float plane_extent = 50.0f;  // half the side of the square that stands for an infinite plane
};

/// The options a render's triangle list is made with: render.tessellation segments around a
/// sphere, cylinder or cone, half as many rings (the rasterizer and radiosity).
inline TessellationOptions tessellation_options(const RenderSettings& render) {
    TessellationOptions options;
    options.segments = render.raster.tessellation;
    options.rings = options.segments / 2 > 2 ? options.segments / 2 : 2;
    return options;
}

/// The object `obj` as a world-space triangle mesh with per-vertex normals (smooth where the
/// surface is) and uvs, and one material per face (obj.material, or the CSG leaf's, or the
/// mesh file's). Triangles wind counter-clockwise seen from outside.
Mesh tessellate(const Object& obj, const TessellationOptions& options = {});

/// Whether every triangle tessellate() makes of `obj` lies in a plane with all the others on
/// one side of it (or in it): a sphere, box, cylinder or cone (the boundary of a convex solid:
/// each cell of a sphere, a cylinder or a cone is a planar trapezoid or triangle), a quad or a
/// plane (flat), under any transform (affine maps keep both). A ray that leaves one of its
/// triangles toward the side away from the others never meets the object again (the
/// rasterizer's shadow rays leave such an object's triangles untested).
bool tessellates_convex(const Object& obj);

/// An upper bound on the triangles tessellate() makes of `obj` (for memory limits before
/// tessellating: a CSG or implicit surface counts its grid's worst case).
uint64_t tessellated_triangles(const Object& obj, const TessellationOptions& options = {});
/// The same for every object of the scene and every instance's (drawn as copies).
uint64_t tessellated_triangles(const Scene& scene, const TessellationOptions& options);

/// A bound on the distance between a sphere of radius r and its tessellation with these
/// options: r (1 - cos(d / 2)), d the angular diagonal of a longitude-latitude cell (used by
/// the tests and to pick resolutions).
float sphere_tessellation_error(float r, const TessellationOptions& options);

}  // namespace svetlo
