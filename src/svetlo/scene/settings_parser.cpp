// camera, film and render sections.
#include "svetlo/scene/scene_loader.h"
#include "svetlo/scene/scene_parts.h"

namespace svetlo {

Camera parse_camera(const JsonNode& node) {
    node.expect_object(
        {"type", "position", "look_at", "up", "fov", "height", "aperture", "focus_distance"});
    Camera c;
    if (auto type = node.find("type")) {
        c.type = type->as_choice({"perspective", "orthographic"}) == "perspective"
                     ? Camera::Type::Perspective
                     : Camera::Type::Orthographic;
    }
    c.position = node.at("position").as_vec3();
    c.look_at = node.at("look_at").as_vec3();
    if (auto up = node.find("up")) c.up = up->as_direction();
    if (auto fov = node.find("fov")) {
        c.fov_deg = fov->as_positive();
        if (c.fov_deg >= 180.0f) fov->fail("must be < 180 degrees");
    }
    if (auto height = node.find("height")) c.height = height->as_positive();
    if (auto n = node.find("aperture")) {
        c.aperture = n->as_non_negative();
        if (c.aperture > 0.0f && c.type != Camera::Type::Perspective)
            n->fail("a thin lens needs a perspective camera");
    }
    if (auto n = node.find("focus_distance")) c.focus_distance = n->as_positive();
    vec3 forward = c.look_at - c.position;
    float len = glm::length(forward);
    if (!(len > 1e-12f * std::max(1.0f, glm::length(c.position)))) {
        node.at("look_at").fail("must differ from position (the camera has no direction)");
    }
    if (glm::length(glm::cross(forward / len, c.up)) < 1e-6f) {
        (node.has("up") ? node.at("up") : node).fail("up is parallel to the viewing direction");
    }
    return c;
}

Film parse_film(const JsonNode& node) {
    node.expect_object({"width", "height"});
    Film f;
    if (auto w = node.find("width")) f.width = static_cast<int>(w->as_integer(1, kMaxFilmSide));
    if (auto h = node.find("height")) f.height = static_cast<int>(h->as_integer(1, kMaxFilmSide));
    long long pixels = static_cast<long long>(f.width) * f.height;
    if (pixels > kMaxFilmPixels) {
        node.fail("film of " + std::to_string(f.width) + " x " + std::to_string(f.height) +
                  " pixels is too large (at most " + std::to_string(kMaxFilmPixels) + " pixels)");
    }
    return f;
}

namespace {

RadiositySettings parse_radiosity(const JsonNode& node) {
    node.expect_object({"patch_size", "element_size", "form_factors", "samples", "hemicube",
                        "solver", "tolerance", "max_iterations", "adaptive", "max_subdivision",
                        "link_epsilon", "display", "ambient_term", "form_factor_cache_mib",
                        "max_links"});
    RadiositySettings s;
    if (auto n = node.find("patch_size")) s.patch_size = n->as_positive();
    if (auto n = node.find("element_size")) s.element_size = n->as_positive();
    if (s.patch_size > 0.0f && s.element_size > s.patch_size)
        node.at("element_size").fail("must be <= patch_size");
    if (auto n = node.find("form_factors")) s.form_factors = n->as_enum(kFormFactorMethods);
    if (auto n = node.find("samples")) s.samples = static_cast<int>(n->as_integer(1, 256));
    if (auto n = node.find("hemicube")) s.hemicube = static_cast<int>(n->as_integer(8, 2048));
    if (auto n = node.find("solver")) s.solver = n->as_enum(kRadiositySolvers);
    if (auto n = node.find("tolerance")) {
        s.tolerance = n->as_in_range(0.0, 1.0);
        if (!(s.tolerance > 0.0f)) n->fail("must lie in (0, 1]");
    }
    if (auto n = node.find("max_iterations"))
        s.max_iterations = static_cast<int>(n->as_integer(0, 1000000000));
    if (auto n = node.find("adaptive")) s.adaptive = n->as_non_negative();
    if (auto n = node.find("max_subdivision"))
        s.max_subdivision = static_cast<int>(n->as_integer(0, 8));
    if (auto n = node.find("link_epsilon")) s.link_epsilon = n->as_positive();
    if (auto n = node.find("display")) s.display = n->as_enum(kRadiosityDisplays);
    if (auto n = node.find("ambient_term")) s.ambient_term = n->as_bool();
    if (auto n = node.find("form_factor_cache_mib"))
        s.form_factor_cache_mib = static_cast<int>(n->as_integer(0, 1 << 20));
    if (auto n = node.find("max_links")) s.max_links = static_cast<int>(n->as_integer(16, 1 << 30));
    if (s.solver == RadiositySolver::Hierarchical && s.form_factors == FormFactorMethod::Hemicube)
        node.at("form_factors")
            .fail("the hierarchical solver needs analytic or raycast form factors");
    return s;
}

ShadowMapSettings parse_shadow_map(const JsonNode& sm) {
    sm.expect_object(
        {"resolution", "bias", "normal_offset", "slope_bias", "filter", "kernel", "cascades"});
    ShadowMapSettings m;
    if (auto n = sm.find("resolution")) m.resolution = static_cast<int>(n->as_integer(1, 16384));
    if (auto n = sm.find("bias")) m.bias = n->as_non_negative();
    if (auto n = sm.find("normal_offset")) m.normal_offset = n->as_non_negative();
    if (auto n = sm.find("slope_bias")) m.slope_bias = n->as_non_negative();
    if (auto n = sm.find("filter")) m.filter = n->as_enum(kShadowFilters);
    if (auto n = sm.find("kernel")) m.kernel = static_cast<int>(n->as_integer(1, 64));
    if (auto n = sm.find("cascades")) m.cascades = static_cast<int>(n->as_integer(1, 8));
    return m;
}

PhotonSettings parse_photons(const JsonNode& ph) {
    ph.expect_object({"count", "radius", "alpha"});
    PhotonSettings p;
    if (auto n = ph.find("count")) p.count = static_cast<int>(n->as_integer(1, kMaxPhotons));
    if (auto n = ph.find("radius")) p.radius = n->as_positive();
    if (auto n = ph.find("alpha")) {
        p.alpha = n->as_in_range(0.0, 1.0);
        if (!(p.alpha > 0.0f && p.alpha < 1.0f)) n->fail("must lie in (0, 1)");
    }
    return p;
}

}  // namespace

RenderSettings parse_render(const JsonNode& node) {
    node.expect_object({"engine",
                        "spp",
                        "max_depth",
                        "seed",
                        "shading",
                        "shadows",
                        "shadow_map",
                        "ambient",
                        "background",
                        "exposure",
                        "accel",
                        "light_samples",
                        "area_shadow_points",
                        "area_light_points",
                        "shadow_volume",
                        "planar_shadows",
                        "visibility",
                        "cull",
                        "antialias",
                        "wireframe",
                        "wireframe_color",
                        "tessellation",
                        "caustics",
                        "photons",
                        "mis",
                        "guiding",
                        "radiosity"});
    RenderSettings r;
    // An open set: which engines exist is the job layer's registry's to say (job/engines.h).
    if (auto n = node.find("engine")) r.engine = n->as_string();
    if (auto n = node.find("spp")) r.spp = static_cast<int>(n->as_integer(1, kMaxSpp));
    if (auto n = node.find("max_depth")) r.max_depth = static_cast<int>(n->as_integer(0, 1000));
    if (auto n = node.find("seed")) r.seed = static_cast<uint64_t>(n->as_integer(0, kMaxSeed));
    if (auto n = node.find("shading")) r.shading = n->as_enum(kShadingModes);
    if (auto n = node.find("shadows")) r.shadows = n->as_enum(kShadowTechniques);
    if (auto sm = node.find("shadow_map")) r.shadow_map = parse_shadow_map(*sm);
    if (auto n = node.find("ambient")) r.ambient = n->as_color();
    if (auto n = node.find("background")) r.background = n->as_color();
    if (auto n = node.find("exposure")) r.exposure = n->as_non_negative();
    if (auto n = node.find("accel"))
        r.accel =
            n->as_choice({"none", "grid", "octree", "bvh2", "bvh4", "bvh", "bvh16", "embree"});
    if (auto n = node.find("light_samples")) {
        r.light_samples = static_cast<int>(n->as_integer(1, 4096));
    }
    if (auto sv = node.find("shadow_volume")) {
        sv->expect_object({"count"});
        if (auto n = sv->find("count")) r.shadow_teaching.volume_count = n->as_enum(kVolumeCounts);
    }
    if (auto ps = node.find("planar_shadows")) {
        ps->expect_object({"clip"});
        if (auto n = ps->find("clip")) r.shadow_teaching.planar_clip = n->as_bool();
    }
    if (auto n = node.find("area_shadow_points"))
        r.area_shadow_points = static_cast<int>(n->as_integer(1, 256));
    if (auto n = node.find("area_light_points"))
        r.area_light_points = static_cast<int>(n->as_integer(1, 1024));
    if (auto n = node.find("visibility")) r.raster.visibility = n->as_enum(kVisibilityMethods);
    if (auto n = node.find("cull"))
        r.raster.cull_back_faces = n->as_choice({"none", "back"}) == "back";
    if (auto n = node.find("antialias")) r.raster.msaa = n->as_choice({"ssaa", "msaa"}) == "msaa";
    if (auto n = node.find("wireframe")) r.raster.wireframe = n->as_enum(kWireframeModes);
    if (auto n = node.find("wireframe_color")) r.raster.wireframe_color = n->as_color();
    if (auto n = node.find("tessellation"))
        r.raster.tessellation = static_cast<int>(n->as_integer(3, 4096));
    if (auto n = node.find("mis")) r.mis = n->as_enum(kMisModes);
    if (auto n = node.find("guiding")) r.guiding = n->as_bool();
    if (auto n = node.find("caustics")) r.caustics = n->as_enum(kCausticModes);
    if (auto ph = node.find("photons")) r.photons = parse_photons(*ph);
    if (auto rad = node.find("radiosity")) r.radiosity = parse_radiosity(*rad);
    return r;
}

}  // namespace svetlo
