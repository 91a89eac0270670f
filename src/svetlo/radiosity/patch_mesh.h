// The scene as radiosity sees it (docs/radiosity.md): its triangles (every object's, then
// the area lights' quads, which emit like any emissive surface), a BVH over them for the
// visibility of form factors and shadow rays, and the element tree with the sizes resolved.
// Limits are checked on estimates before anything large is allocated.
#pragma once

#include <memory>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/geometry.h"
#include "svetlo/radiosity/element_tree.h"
#include "svetlo/shading/cutouts.h"
#include "svetlo/shading/environment.h"
#include "svetlo/shading/light_set.h"

namespace svetlo {

/// At most this many nodes in the element tree (about 250 bytes each with the solution).
inline constexpr uint64_t kMaxRadiosityNodes = uint64_t{1} << 23;
/// The hierarchical solver links every pair of roots: at most this many triangles.
inline constexpr size_t kMaxHierarchicalRoots = 4096;
/// `auto` picks progressive refinement where patches x elements, its form factors, are at
/// most this many (about 15 s of rays on two cores).
inline constexpr uint64_t kMaxAutoProgressivePairs = uint64_t{1} << 26;
/// Progressive refinement computes at most this many form factors (patches x elements, about
/// 20 minutes on two cores): past it a scene is refused instead of running for hours.
inline constexpr uint64_t kMaxProgressivePairs = uint64_t{1} << 32;

struct PatchMesh {
    /// Tessellates the scene and builds the accelerator and the tree's roots; resolves
    /// patch_size and element_size (0 = from the scene's size) into `settings`. Throws Error
    /// (naming render.radiosity's key) for a mesh past a limit.
    PatchMesh(const Scene& scene, int threads);
    PatchMesh(const PatchMesh&) = delete;  // the tree refers to the list and the materials
    PatchMesh& operator=(const PatchMesh&) = delete;

    /// Subdivides the roots into elements of settings.element_size (the uniform mesh of the
    /// progressive and matrix solvers).
    void subdivide_uniform();

    LightSet lights;
    Environment environment;  // the map or the uniform background, gathered before the solve
    TriangleList list;
    Geometry geometry;
    std::unique_ptr<Accel> bvh;        // the triangles' structure
    std::unique_ptr<Cutouts> cutouts;  // alpha's holes
    // Visibility: the structure, seeing through alpha's holes where a material has them.
    std::unique_ptr<Accel> accel;
    std::unique_ptr<ElementTree> tree;
    RadiositySettings settings;
    uint64_t patch_count = 0;  // the uniform mesh's patches and elements
    uint64_t element_count = 0;

private:
    /// The mesh's patch and element counts, the solver `auto` picks, and the limits each
    /// solver has (throws Error naming render.radiosity's key).
    void choose_solver(const std::string& file);
};

}  // namespace svetlo
