#include "svetlo/raster/raster_trace.h"

#include <variant>

#include "svetlo/raster/raster_engine.h"

namespace svetlo {

namespace {

/// Where light `light` lies seen from p: the unit direction toward it and the distance
/// (infinite for a directional light; an area light's centre).
std::pair<vec3, float> toward_light(const Light& light, vec3 p) {
    vec3 to(0.0f);
    if (const auto* pl = std::get_if<PointLight>(&light)) to = pl->position - p;
    if (const auto* sl = std::get_if<SpotLight>(&light)) to = sl->position - p;
    if (const auto* al = std::get_if<AreaLight>(&light))
        to = al->corner + 0.5f * (al->edge_u + al->edge_v) - p;
    if (const auto* dl = std::get_if<DirectionalLight>(&light))
        return {-glm::normalize(dl->direction), kInfinity};
    const float d = glm::length(to);
    return {d > 0.0f ? to / d : vec3(0.0f), d};
}

/// The camera ray through the centre of pixel (i, j) of the rasterizer's camera.
Ray pixel_ray(const CameraMatrices& camera, int i, int j) {
    const vec2 ndc(
        2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(camera.width) - 1.0f,
        1.0f - 2.0f * (static_cast<float>(j) + 0.5f) / static_cast<float>(camera.height));
    const mat4 inverse = glm::inverse(camera.view_projection());
    auto unproject = [&](float z) {
        const vec4 p = inverse * vec4(ndc, z, 1.0f);
        return vec3(p) / p.w;
    };
    const vec3 near = unproject(-1.0f), mid = unproject(0.0f);
    return Ray{camera.orthographic ? near : camera.eye, glm::normalize(mid - near), kInfinity};
}

}  // namespace

RenderResult trace_raster_pixel(Renderer& engine, const Scene& scene,
                                const RenderOptions& options) {
    PixelTrace& log = *options.trace;
    RenderOptions pixel;
    pixel.threads = options.threads;
    pixel.crop = Crop{log.x, log.x + 1, log.y, log.y + 1};
    auto draw = [&](const Scene& s, std::vector<std::string> aovs) {
        pixel.aovs = std::move(aovs);
        return engine.render(s, pixel);
    };
    // The pixel as the frame has it, with the fragment's attributes.
    RenderResult whole = draw(scene, {"depth", "normal", "albedo"});
    const float depth = whole.aovs["depth"].at(0, 0).r;
    const Ray ray = pixel_ray(raster_camera(scene), log.x, log.y);
    const vec3 p = ray.o + depth * ray.d;

    Scene unlit = scene;
    unlit.lights.clear();
    const Color base = draw(unlit, {}).color.at(0, 0);  // emission and ambient
    unlit.render.ambient = Color(0.0f);
    const Color emitted = draw(unlit, {}).color.at(0, 0);

    TraceRay camera;
    camera.kind = "camera";
    camera.origin = ray.o;
    camera.direction = ray.d;
    camera.t = depth > 0.0f ? depth : kInfinity;
    camera.contribution = base;
    camera.note = depth > 0.0f ? "the fragment: emission and the ambient term" : "the background";
    if (depth > 0.0f) {
        camera.set("point", p)
            .set("normal", vec3(whole.aovs["normal"].at(0, 0)))
            .set("albedo", whole.aovs["albedo"].at(0, 0))
            .set("emitted", emitted);
    }
    const int parent = log.add(std::move(camera));

    for (size_t k = 0; k < scene.lights.size(); ++k) {
        Scene alone = scene;
        alone.lights = {scene.lights[k]};
        alone.render.ambient = Color(0.0f);
        RenderResult lit = draw(alone, {"visibility"});
        alone.render.shadows = ShadowTechnique::None;
        const Color unshadowed = draw(alone, {}).color.at(0, 0) - emitted;
        const auto [wi, distance] = toward_light(scene.lights[k], p);
        TraceRay r;
        r.kind = "light";
        r.parent = parent;
        r.origin = p;
        r.direction = wi;
        r.t = distance;
        r.contribution = lit.color.at(0, 0) - emitted;
        r.note = "light " + std::to_string(k) + "'s term under the shadow technique";
        r.set("light", {static_cast<float>(k)})
            .set("visibility", {lit.aovs["visibility"].at(0, 0).r})
            .set("unshadowed", unshadowed);
        log.add(std::move(r));
    }
    log.notes.push_back(
        "the total is the pixel of the whole frame; each light's contribution is "
        "its frame alone less the emission");
    record_total(log, whole.color.at(0, 0), is_finite(whole.color.at(0, 0)));
    return whole;
}

}  // namespace svetlo
