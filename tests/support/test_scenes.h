// Pieces of scenes (JSON, ../shared/CONTRACT.md) that several test programs build on.
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

}  // namespace svetlo::test_scenes
