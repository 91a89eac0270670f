#include "svetlo/scene/instances.h"

#include "svetlo/core/error.h"

namespace svetlo {

uint64_t object_triangles(const Object& object) {
    const auto* mesh = std::get_if<Mesh>(&object.shape);
    return mesh ? mesh->triangle_count() : 1;
}

uint64_t instanced_triangles(const Scene& scene) {
    return sum_over_instances(scene, object_triangles);
}

Object placed_object(const Object& object, const Instance& instance) {
    Object copy = object;
    copy.name = instance.name + "/" + object.name;
    copy.transform.matrix = instance.transform.matrix * object.transform.matrix;
    copy.transform.is_identity = instance.transform.is_identity && object.transform.is_identity;
    if (instance.material >= 0) copy.material = instance.material;
    return copy;
}

std::vector<Object> instance_copies(const Scene& scene) {
    const uint64_t triangles = instanced_triangles(scene);
    if (triangles > kMaxCopiedTriangles) {
        throw Error(scene.path.string(), "objects",
                    "the instances stand for " + std::to_string(triangles) +
                        " triangles; this engine draws instances as copies, at most " +
                        std::to_string(kMaxCopiedTriangles) +
                        " (the ray-traced engines place them without copying)");
    }
    std::vector<Object> out;
    for (const Instance& i : scene.instances)
        for (const Object& o : scene.prototypes[i.prototype].objects)
            out.push_back(placed_object(o, i));
    return out;
}

}  // namespace svetlo
