#include "svetlo/radiosity/patch_mesh.h"

#include <string>

#include "svetlo/core/error.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/geometry/tessellate.h"
#include "svetlo/radiosity/solver.h"
#include "svetlo/scene/instances.h"

namespace svetlo {

namespace {

constexpr uint64_t kMaxTessellatedTriangles = uint64_t{1} << 24;

/// The uniform mesh's sizes: patches and elements per root, 4^k each for k halvings.
uint64_t uniform_count(const TriangleList& list, float size) {
    uint64_t total = 0;
    for (size_t t = 0; t < list.triangle_count(); ++t) {
        vec3 p[3];
        for (int c = 0; c < 3; ++c) p[c] = list.positions[list.indices[3 * t + c]];
        int k = halvings_to(longest_edge(p), size);
        total += k >= 20 ? (uint64_t{1} << 40) : (uint64_t{1} << (2 * k));
        if (total > (uint64_t{1} << 40)) break;
    }
    return total;
}

}  // namespace

PatchMesh::PatchMesh(const Scene& scene, int threads)
    : lights(scene), environment(scene), settings(scene.render.radiosity) {
    const std::string file = scene.path.string();
    TessellationOptions options = tessellation_options(scene.render);
    const uint64_t triangles = tessellated_triangles(scene, options);
    if (triangles > kMaxTessellatedTriangles) {
        throw Error(file, "render.tessellation",
                    "the scene would make " + std::to_string(triangles) + " triangles (at most " +
                        std::to_string(kMaxTessellatedTriangles) + ")");
    }
    // Each instance's own patches: its objects written out (scene/instances.h).
    const std::vector<Object> copies = instance_copies(scene);
    const std::vector<const Object*> objects =
        object_pointers(scene.objects, copies, lights.area_light_quads());
    list = build_triangle_list(objects, options, threads);
    // An infinite plane stands in as a square around the rest of the scene: twice its
    // diameter across (the rasterizer's 100 m square would be millions of elements).
    const auto is_plane = [&](size_t k) {
        return std::holds_alternative<Plane>(objects[k]->shape);
    };
    Bounds3 bounds;
    for (size_t k = 0; k < list.objects.size(); ++k) {
        if (is_plane(k)) continue;
        for (uint32_t t = list.objects[k].first; t < list.objects[k].end; ++t)
            for (int c = 0; c < 3; ++c) bounds.extend(list.positions[list.indices[3 * t + c]]);
    }
    bool planes = false;
    for (size_t k = 0; k < objects.size(); ++k) planes |= is_plane(k);
    if (planes && !bounds.empty()) {
        // At most 1e37, so that the square stays within float range around a scene near it.
        options.plane_extent = std::clamp(glm::length(bounds.extent()), 1e-3f, 1e37f);
        list = build_triangle_list(objects, options, threads);
    }
    geometry = triangle_geometry(list);
    bvh = make_accel("bvh", geometry, threads);
    cutouts = std::make_unique<Cutouts>(geometry, lights.materials(), scene.textures);
    accel = std::make_unique<CutoutAccel>(*bvh, *cutouts);

    // Sizes from the scene's extent without infinite planes.
    if (bounds.empty()) bounds = list.bounds();
    const float diameter = bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-6f);
    // Patches of a quarter of the diameter: a shooter's light is spread over its patch, which
    // the smooth indirect light allows, and each costs a row of form factors to every element
    // (docs/radiosity.md measures the trade).
    if (settings.patch_size <= 0.0f)
        settings.patch_size = std::max(diameter / 4.0f, settings.element_size);
    if (settings.element_size <= 0.0f) settings.element_size = 0.25f * settings.patch_size;

    choose_solver(file);
    tree = std::make_unique<ElementTree>(list, lights.materials(), scene.textures);
}

void PatchMesh::choose_solver(const std::string& file) {
    patch_count = uniform_count(list, settings.patch_size);
    element_count = uniform_count(list, settings.element_size);
    // Whether a x b, form factors, pass `limit` (without overflowing).
    auto exceeds = [](uint64_t a, uint64_t b, uint64_t limit) {
        return a > limit / std::max<uint64_t>(b, 1);
    };
    if (settings.solver == RadiositySolver::Auto) {
        // Progressive where its rows of form factors are few enough: at equal time it is the
        // more accurate on such scenes (docs/performance.md); else hierarchical where the
        // scene's triangles may be linked pairwise.
        const bool rows_fit = !exceeds(patch_count, element_count, kMaxAutoProgressivePairs);
        const bool linkable = list.triangle_count() <= kMaxHierarchicalRoots &&
                              settings.form_factors != FormFactorMethod::Hemicube;
        settings.solver =
            rows_fit || !linkable ? RadiositySolver::Progressive : RadiositySolver::Hierarchical;
    }
    const bool hierarchical = settings.solver == RadiositySolver::Hierarchical;
    // Nodes of the uniform tree: about 4/3 of its leaves.
    const uint64_t nodes = element_count + element_count / 3 + list.triangle_count();
    if (!hierarchical && nodes > kMaxRadiosityNodes) {
        throw Error(file, "render.radiosity.element_size",
                    "the patch mesh would have " + std::to_string(element_count) +
                        " elements (at most about " + std::to_string(kMaxRadiosityNodes * 3 / 4) +
                        "); raise element_size");
    }
    const bool progressive = settings.solver == RadiositySolver::Progressive;
    if (progressive && exceeds(patch_count, element_count, kMaxProgressivePairs)) {
        // Every triangle is at least one patch and one element: past the limit on its own,
        // no size helps.
        const uint64_t roots = list.triangle_count();
        const bool each_triangle_a_patch = exceeds(roots, roots, kMaxProgressivePairs);
        throw Error(file, "render.radiosity.patch_size",
                    "progressive refinement would compute " + std::to_string(patch_count) +
                        " patches x " + std::to_string(element_count) +
                        " elements of form factors (at most 2^32); " +
                        (each_triangle_a_patch
                             ? "each of the scene's " + std::to_string(list.triangle_count()) +
                                   " triangles is at least one patch and one element: simplify "
                                   "its meshes, or use the path tracer"
                             : std::string("raise patch_size or element_size")));
    }
    const bool matrix = settings.solver == RadiositySolver::Jacobi ||
                        settings.solver == RadiositySolver::GaussSeidel;
    if (matrix && element_count > kMaxMatrixElements) {
        throw Error(file, "render.radiosity.solver",
                    "the matrix solvers take at most " + std::to_string(kMaxMatrixElements) +
                        " elements (this mesh has " + std::to_string(element_count) +
                        "); raise element_size or use progressive");
    }
    if (hierarchical && list.triangle_count() > kMaxHierarchicalRoots) {
        throw Error(file, "render.radiosity.solver",
                    "hierarchical radiosity links every pair of the scene's triangles: at most " +
                        std::to_string(kMaxHierarchicalRoots) + " (this scene has " +
                        std::to_string(list.triangle_count()) + "); use progressive");
    }
}

void PatchMesh::subdivide_uniform() {
    tree->subdivide_to(settings.element_size, kMaxRadiosityNodes);
}

}  // namespace svetlo
