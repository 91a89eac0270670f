// Pieces of scenes (JSON, docs/scene-format.md) that several test programs build on.
#pragma once

#include <nlohmann/json.hpp>

namespace svetlo::test_scenes {

/// A square floor at y = 0 of half side `half`, its front (edge_u x edge_v) facing up.
inline nlohmann::json floor_quad(float half, const char* material) {
    return {{"type", "quad"},
            {"corner", {-half, 0, -half}},
            {"edge_u", {0, 0, 2 * half}},
            {"edge_v", {2 * half, 0, 0}},
            {"material", material}};
}

/// Two unit squares (the path tracer's settings; radiosity's tests swap the render section),
/// `emitter` of radiance 1 (a light, or an emissive quad) facing the receiver (albedo 1), seen
/// straight on by an orthographic camera that sees only the receiver: its mean radiance is F
/// (receiver to emitter) times L.
inline nlohmann::json unit_plates(bool perpendicular, bool area_light) {
    nlohmann::json j = {{"camera",
                         {{"type", "orthographic"},
                          {"position", {0.5, 0.5, 0.5}},  // between the plates
                          {"look_at", {0.5, 0, 0.5}},
                          {"up", {0, 0, -1}},
                          {"height", 1}}},
                        {"film", {{"width", 16}, {"height", 16}}},
                        {"render", {{"engine", "path"}, {"spp", 256}, {"max_depth", 0}}}};
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 1}}},
                      {"glow", {{"type", "emissive"}, {"radiance", 1}}}};
    nlohmann::json receiver = {{"type", "quad"},
                               {"corner", {0, 0, 0}},
                               {"edge_u", {0, 0, 1}},
                               {"edge_v", {1, 0, 0}},
                               {"material", "white"}};
    // The emitter faces the receiver: at y = 1 facing down, or in the plane x = 0 facing +x
    // (edge-on to the camera, which sees the receiver only).
    nlohmann::json corner = perpendicular ? nlohmann::json{0, 0, 0} : nlohmann::json{0, 1, 0};
    nlohmann::json eu = perpendicular ? nlohmann::json{0, 1, 0} : nlohmann::json{1, 0, 0};
    nlohmann::json ev = perpendicular ? nlohmann::json{0, 0, 1} : nlohmann::json{0, 0, 1};
    if (area_light) {
        j["lights"] = {{{"type", "area"},
                        {"corner", corner},
                        {"edge_u", eu},
                        {"edge_v", ev},
                        {"radiance", 1}}};
        j["objects"] = {receiver};
    } else {
        j["objects"] = {receiver,
                        {{"type", "quad"},
                         {"corner", corner},
                         {"edge_u", eu},
                         {"edge_v", ev},
                         {"material", "glow"}}};
    }
    return j;
}

}  // namespace svetlo::test_scenes
