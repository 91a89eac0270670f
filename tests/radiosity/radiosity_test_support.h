// Scenes the radiosity tests share (JSON, docs/scene-format.md).
#pragma once

#include <nlohmann/json.hpp>

#include "svetlo/radiosity/adaptive_subdivision.h"
#include "svetlo/radiosity/patch_mesh.h"
#include "svetlo/radiosity/radiosity_engine.h"
#include "svetlo/scene/scene_loader.h"
#include "test_scenes.h"

namespace svetlo {

/// The unit plates (test_scenes.h): A (objects[0], albedo 1) at y = 0 and B (objects[1],
/// radiance 1) facing it, parallel at y = 1 or perpendicular in x = 0; an orthographic camera
/// sees only A. Radiosity with uniform elements of `element_size`, progressive.
inline nlohmann::json radiosity_unit_plates(bool perpendicular, float element_size) {
    nlohmann::json j = test_scenes::unit_plates(perpendicular, false);
    j["render"] = {{"engine", "radiosity"},
                   {"radiosity",
                    {{"solver", "progressive"},
                     {"patch_size", 2 * element_size},
                     {"element_size", element_size},
                     {"adaptive", 0}}}};
    return j;
}

/// The inside of a closed cube of half side `half` at the origin whose walls emit radiance
/// `Le` and reflect with albedo `rho`, seen from its centre.
inline nlohmann::json radiosity_closed_box(float half, float Le, float rho) {
    using json = nlohmann::json;
    json j = {
        {"camera", {{"position", {0, 0, 0.5 * half}}, {"look_at", {0, 0, -half}}, {"fov", 60}}},
        {"film", {{"width", 16}, {"height", 16}}},
        {"render", {{"engine", "radiosity"}, {"radiosity", {{"adaptive", 0}}}}}};
    j["materials"] = {{"wall", {{"type", "emissive"}, {"radiance", Le}, {"albedo", rho}}}};
    // A box's faces face out; its walls emit from their front side only, so the box is made
    // of six quads facing in.
    json objects = json::array();
    const float h = half;
    auto quad = [&](json c, json v, json u) {  // listed with edge_v first: u x v faces in
        objects.push_back(
            {{"type", "quad"}, {"corner", c}, {"edge_u", u}, {"edge_v", v}, {"material", "wall"}});
    };
    quad({-h, -h, -h}, {2 * h, 0, 0}, {0, 0, 2 * h});  // floor, facing +y
    quad({-h, h, -h}, {0, 0, 2 * h}, {2 * h, 0, 0});   // ceiling, facing -y
    quad({-h, -h, -h}, {0, 2 * h, 0}, {2 * h, 0, 0});  // back, facing +z
    quad({-h, -h, h}, {2 * h, 0, 0}, {0, 2 * h, 0});   // front, facing -z
    quad({-h, -h, -h}, {0, 0, 2 * h}, {0, 2 * h, 0});  // left, facing +x
    quad({h, -h, -h}, {0, 2 * h, 0}, {0, 0, 2 * h});   // right, facing -x
    j["objects"] = objects;
    return j;
}

}  // namespace svetlo
