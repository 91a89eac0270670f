// Instances drawn where they stand (docs/raster.md, "Instances drawn in place"): the rasterizer
// keeps each prototype tessellated once in its own space and draws it once per placement, a batch
// of placements at a time into the same targets, as a GPU's instanced draw call does, instead
// of a list of copies. The memory is the prototypes', the placements' and one batch's,
// whatever the number of placements.
//
// The colour pass then draws only what the camera sees: a visibility pass of every triangle
// (the list's, then the placements', in order) finds the triangles that hold a sample
// (visible_triangles), and the colour pass draws those alone. The depth test keeps, at each
// sample, the first drawn of the nearest, so the triangles that hold no sample change no
// sample: the frame is the one the whole scene's list would give. The shadow techniques that
// see the scene from elsewhere (shadow maps' depth passes, shadow rays) draw or trace every
// placement.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "svetlo/geometry/geometry.h"
#include "svetlo/geometry/triangle_list.h"
#include "svetlo/raster/draw_pass.h"

namespace svetlo::raster {

struct SamplePattern;

class PlacedDraws {
public:
    /// Most triangles written into one batch (a placement with more is a batch alone).
    static constexpr uint64_t kBatchTriangles = uint64_t{1} << 20;

    /// The scene's instances, each prototype tessellated once with `options` (and its parts'
    /// edge adjacency found, with `adjacency`). Their triangles are numbered after the frame's
    /// own list's `first_id` (ids [first_id, end_id())).
    /// Refused (Error naming `objects`) when the ids would not fit in 32 bits.
    PlacedDraws(const Scene& scene, const TessellationOptions& options, uint32_t first_id,
                bool adjacency, int threads);

    uint64_t end_id() const { return first_.back(); }
    /// The ids of placement p's triangles: [first, end).
    std::pair<uint64_t, uint64_t> ids_of(size_t p) const { return {first_[p], first_[p + 1]}; }
    /// A box around every placed triangle (each part's box carried into the world).
    Bounds3 bounds() const;
    /// The least distance from `eye` along `forward` of a placed point in front of the eye,
    /// a lower bound: each part's box where it lies wholly in front, else the nearest plane
    /// of its triangles not wholly behind (nearest_depth's rule). Infinity: none in front.
    float nearest_depth(vec3 eye, vec3 forward, int threads) const;

    /// What for_each_batch calls with each batch: its triangles, placement by placement (one
    /// object per part of each, in order; the parts' adjacency when the draws have it), each
    /// triangle's id, and the batch's placements.
    using BatchVisit =
        std::function<void(const TriangleList& batch, const std::vector<uint32_t>& items,
                           const std::vector<size_t>& placements)>;
    /// Writes the placements into `scratch` in batches of about kBatchTriangles and visits
    /// each; with `view_projection`, those whose box lies outside that view are left out.
    void for_each_batch(const mat4* view_projection, int threads, TriangleList& scratch,
                        const BatchVisit& visit) const;
    /// Each placement's box in the world (its parts' boxes carried out).
    const std::vector<Bounds3>& boxes() const { return boxes_; }

    /// The placements as they are: how many, the prototype each places, each prototype's
    /// parts (a mesh in its own space), and where placement p puts its part k.
    size_t placement_count() const { return placements_.size(); }
    uint32_t prototype_of(size_t p) const { return placements_[p].prototype; }
    size_t part_count(uint32_t prototype) const { return prototypes_[prototype].parts.size(); }
    const Mesh& part_mesh(uint32_t prototype, size_t k) const {
        return prototypes_[prototype].parts[k].mesh;
    }
    Transform placed_transform(size_t p, size_t k) const {
        return part_transform(placements_[p], prototypes_[placements_[p].prototype].parts[k]);
    }
    /// Where placed triangle `id` (in [first_id(), end_id())) lies: its placement, the part,
    /// and the triangle in the part's mesh.
    struct Located {
        size_t placement, part, triangle;
    };
    Located locate(uint32_t id) const;

    /// Draws every placement through `camera` with `state` into `targets` (draw_pass, batch
    /// by batch), the item buffer numbering triangles by their ids. A placement whose box
    /// lies outside the camera's view is left out. `scratch` holds a batch.
    void draw(const CameraMatrices& camera, const PipelineState& state, RenderTargets& targets,
              const SamplePattern& pattern, int threads, PassMemory* memory,
              TriangleList& scratch) const;

    /// A corner of a placed triangle, as the visible list shares its vertices: the vertex
    /// (numbered placement by placement, part by part), the triangle's material, and the id of
    /// the first of the placement's triangles that uses the vertex with that material (the
    /// face Gouraud shading lights the vertex on, as the copies' split list has it).
    struct Corner {
        uint64_t vertex;
        uint32_t material;
        uint32_t first_face;
    };
    /// The corners of placed triangle `id` (in [first_id(), end_id())).
    void corners(uint32_t id, Corner out[3]) const;
    /// Writes placed vertex vertices[j] - base (a Corner's vertex), for j < count, into vertex
    /// first + j of `list` (sized), as `draw` places them. Ascending, a part's vertices share
    /// its transform, found once.
    void write_vertices(const uint64_t* vertices, size_t count, uint64_t base, TriangleList& list,
                        size_t first) const;
    /// Whether some prototype's mesh has a second uv set, or vertex colours.
    bool second_set() const { return second_set_; }
    bool colored() const { return colored_; }

    /// The placements as ray-traceable instances of `g`: each part of a prototype a
    /// prototype of its own, in its own space, placed once per instance.
    void add_to(Geometry& g) const;

private:
    struct Part {
        Mesh mesh;                         // tessellated in its own space
        Transform transform;               // the object's, within the prototype
        Bounds3 bounds;                    // of the mesh, in its own space
        std::vector<uint32_t> first_any;   // per vertex, the first triangle that uses it
        std::vector<uint32_t> first_same;  // per corner 3 t + c, the first triangle that uses
                                           // its vertex with triangle t's material
        std::vector<uint32_t> neighbour;   // with adjacency: TriangleList::neighbour, its own
    };
    struct Prototype {
        std::vector<Part> parts;
        std::vector<uint64_t> first;         // per part, its first triangle; the count at the end
        std::vector<uint64_t> first_vertex;  // per part, its first vertex; the count at the end
    };
    struct Placement {
        uint32_t prototype;
        Transform transform;  // the instance's
        int material;         // replaces the prototype's where >= 0
    };
    /// Placement p's part k as the copies would place it (placed_object's product).
    Transform part_transform(const Placement& p, const Part& part) const;
    /// Placement p's triangles written into `list` (sized) from vertex v and triangle t.
    void write(size_t p, TriangleList& list, size_t v, size_t t) const;
    uint64_t vertices(size_t p) const {
        return prototypes_[placements_[p].prototype].first_vertex.back();
    }

    std::vector<Prototype> prototypes_;
    std::vector<Placement> placements_;
    std::vector<Bounds3> boxes_;   // per placement, its parts' boxes carried into the world
    std::vector<uint64_t> first_;  // per placement, its first triangle's id; end_id() at the end
    std::vector<uint64_t> first_vertex_;  // per placement, its first vertex; the count at the end
    bool second_set_ = false, colored_ = false;
    bool adjacency_ = false;
};

/// The whole scene as the rasterizer draws it: its own list, and the placements drawn in
/// place when there are (null: the list holds every triangle).
struct SceneTriangles {
    const TriangleList& list;
    const PlacedDraws* placed = nullptr;
    // A batch of placements, kept from draw to draw (and lent to a pass between draws).
    mutable TriangleList scratch = {};

    Bounds3 bounds() const;
    /// draw_samples of the list, then of every placement (their items numbered on).
    void draw(const CameraMatrices& camera, const PipelineState& state, RenderTargets& targets,
              const SamplePattern& pattern, int threads, PassMemory* memory) const;
};

/// The triangles of `scene` that hold a sample of one of `passes` (each drawn with `state`
/// through `camera`), in drawing order, with their vertices shared as the whole scene's list
/// shares them (one per vertex and material): what the colour pass draws when instances are
/// drawn in place. With `first_faces`, each vertex's first face comes too (the face Gouraud
/// shading lights it on; it holds no sample, so it changes none). No objects (no convex
/// shortcut for shadow rays). The colour pass draws it with `items` (PipelineState::items),
/// so that a blended triangle tosses the coins it tossed here.
struct VisibleTriangles {
    TriangleList list;
    std::vector<uint32_t> items;  // per triangle of the list, its number in the scene
};
VisibleTriangles visible_triangles(const SceneTriangles& scene, const CameraMatrices& camera,
                                   const PipelineState& state,
                                   const std::vector<SamplePattern>& passes, bool first_faces,
                                   int threads, PassMemory* memory);

}  // namespace svetlo::raster
