// svetlo info SCENE.json: what the scene holds.
#include <cstdio>

#include "commands.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/job/engines.h"
#include "svetlo/radiosity/patch_mesh.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/rt_scene.h"
#include "svetlo/scene/instances.h"

namespace svetlo {

namespace {

const char* shape_name(const Shape& s) {
    static const char* names[] = {"sphere", "quad", "plane", "box",     "cylinder",
                                  "cone",   "mesh", "csg",   "implicit"};
    static_assert(std::variant_size_v<Shape> == 9, "a name for every shape");
    return names[s.index()];
}

const char* light_name(const Light& l) {
    static const char* names[] = {"point", "directional", "spot", "area"};
    return names[l.index()];
}

const char* material_name(const Material& m) {
    static const char* names[] = {"lambert", "phong",      "oren_nayar", "cook_torrance",
                                  "mirror",  "dielectric", "emissive"};
    if (const auto* p = std::get_if<PhongMaterial>(&m.model); p && p->blinn) return "blinn_phong";
    return names[m.model.index()];
}

/// The objects, one line each: name, shape, size, material.
void print_objects(const Scene& scene) {
    std::printf("objects    %zu\n", scene.objects.size());
    for (const Object& o : scene.objects) {
        std::printf("  %-14s %-8s", o.name.c_str(), shape_name(o.shape));
        if (const auto* m = std::get_if<Mesh>(&o.shape)) {
            std::printf(" %zu triangles, %zu vertices%s", m->triangle_count(), m->positions.size(),
                        m->smooth ? ", smooth" : "");
        }
        if (o.material >= 0) std::printf(" material %s", scene.material_names[o.material].c_str());
        std::printf("%s\n", o.transform.is_identity ? "" : " (transformed)");
    }
}

/// The rasterizer's vertex stage: clip = projection * view * model * p (column vectors).
void print_matrices(const Scene& scene) {
    CameraMatrices m = raster_camera(scene);
    auto print = [](const char* name, const mat4& a) {
        for (int row = 0; row < 4; ++row) {
            std::printf("%-10s %s[%10.5f %10.5f %10.5f %10.5f]\n", row == 0 ? name : "", "",
                        a[0][row], a[1][row], a[2][row], a[3][row]);
        }
    };
    std::printf("near, far  %g, %g\n", m.near, m.far);
    print("view", m.view);
    print("projection", m.projection);
    for (const Object& o : scene.objects) {
        if (!o.transform.is_identity) print((o.name + " model").c_str(), o.transform.matrix);
    }
    std::printf("viewport   x = (x_ndc + 1) / 2 * %d, y = (1 - y_ndc) / 2 * %d (pixels, y down)\n",
                m.width, m.height);
}

}  // namespace

int run_info(const InfoArgs& args) {
    Scene scene = load_scene(args.scene, parse_sets(args.sets, args.scene));
    const Capabilities& engine = capabilities_of(scene.render.engine, args.scene);
    for (const std::string& w : scene.warnings)
        std::fprintf(stderr, "svetlo: warning: %s: %s\n", args.scene.c_str(), w.c_str());
    LightSet lights(scene);
    Geometry g = build_geometry(object_pointers(scene.objects, lights.area_light_quads()));
    place_instances(scene, g);
    const Bounds3 bounds = g.bounds();
    const Camera& c = scene.camera;
    std::printf("scene      %s\n", scene.path.c_str());
    std::printf("camera     %s at (%g, %g, %g) looking at (%g, %g, %g), %s %g\n",
                c.type == Camera::Type::Perspective ? "perspective" : "orthographic", c.position.x,
                c.position.y, c.position.z, c.look_at.x, c.look_at.y, c.look_at.z,
                c.type == Camera::Type::Perspective ? "fov" : "height",
                c.type == Camera::Type::Perspective ? c.fov_deg : c.height);
    std::printf("film       %d x %d\n", scene.film.width, scene.film.height);
    std::printf("render     engine %s, spp %d, max_depth %d, seed %llu, accel %s\n",
                scene.render.engine.c_str(), scene.render.spp, scene.render.max_depth,
                static_cast<unsigned long long>(scene.render.seed), scene.render.accel.c_str());
    print_objects(scene);
    std::printf("triangles  %u\n", g.triangle_count());
    std::printf("shapes     %zu\n", g.shapes.size());
    std::printf("materials  %zu\n", scene.materials.size());
    for (size_t k = 0; k < scene.materials.size(); ++k) {
        std::printf("  %-24s %s\n", scene.material_names[k].c_str(),
                    material_name(scene.materials[k]));
    }
    std::printf("lights     %zu (+ %zu emissive objects)\n", scene.lights.size(),
                static_cast<size_t>(
                    std::count_if(lights.sources().begin(), lights.sources().end(),
                                  [](const LightSet::Source& s) { return s.light_index < 0; })));
    for (size_t k = 0; k < scene.lights.size(); ++k) {
        std::printf("  lights[%zu] %s\n", k, light_name(scene.lights[k]));
    }
    std::printf("textures   %zu\n", scene.textures.size());
    if (!scene.instances.empty() || scene.copied_objects > 0) {
        // Placed: traced without copies by the ray tracers; copied: written into the objects.
        std::printf("instances  %zu placed, of %zu prototypes, standing for %llu triangles",
                    scene.instances.size(), scene.prototypes.size(),
                    static_cast<unsigned long long>(instanced_triangles(scene)));
        std::printf(" (+ %zu objects written out as copies)\n", scene.copied_objects);
    }
    if (!scene.extensions.empty()) {
        std::string names;
        for (const std::string& e : scene.extensions) names += (names.empty() ? "" : ", ") + e;
        std::printf("extensions %s\n", names.c_str());
    }
    if (!bounds.empty()) {
        std::printf("bounds     (%g, %g, %g) - (%g, %g, %g)\n", bounds.min.x, bounds.min.y,
                    bounds.min.z, bounds.max.x, bounds.max.y, bounds.max.z);
    }
    if (engine.patch_mesh) {
        // The uniform patch mesh (adaptive and hierarchical subdivision come at render time).
        PatchMesh m(scene, 0);
        std::printf("patches    %llu of %g m from %zu triangles, %llu elements of %g m\n",
                    static_cast<unsigned long long>(m.patch_count), m.settings.patch_size,
                    m.list.triangle_count(), static_cast<unsigned long long>(m.element_count),
                    m.settings.element_size);
    }
    if (args.matrices) print_matrices(scene);
    return 0;
}

}  // namespace svetlo
