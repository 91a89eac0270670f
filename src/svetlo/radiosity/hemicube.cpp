#include "svetlo/radiosity/hemicube.h"

#include <cmath>

namespace svetlo {

Hemicube::Hemicube(int resolution, const Bounds3& bounds)
    : resolution_(resolution), bounds_(bounds) {
    float diameter = bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-6f);
    nearest_ = 1e-5f * diameter;
    const int n = resolution;
    const float cell = 2.0f / static_cast<float>(n);  // the face spans [-1, 1]^2
    top_.resize(static_cast<size_t>(n) * n);
    side_.resize(static_cast<size_t>(n) * n);
    for (int j = 0; j < n; ++j) {
        // Row j from the top: the face's "up" coordinate v falls from 1 to -1.
        float v = 1.0f - (static_cast<float>(j) + 0.5f) * cell;
        for (int i = 0; i < n; ++i) {
            float u = -1.0f + (static_cast<float>(i) + 0.5f) * cell;
            float r2 = u * u + v * v + 1.0f;
            float base = cell * cell / (kPi * r2 * r2);
            top_[static_cast<size_t>(j) * n + i] = base;
            // On a side face "up" is the normal: the cell's height above the base is v.
            side_[static_cast<size_t>(j) * n + i] = v > 0.0f ? v * base : 0.0f;
        }
    }
}

float Hemicube::gather(const TriangleList& triangles, vec3 x, vec3 n, std::vector<float>& row,
                       int threads) {
    const Frame frame = Frame::from_normal(n);
    // The top face looks along n; the sides along +-t and +-b with n up.
    const vec3 forward[5] = {n, frame.t, -frame.t, frame.b, -frame.b};
    const vec3 up[5] = {frame.t, n, n, n, n};
    const vec3 eye = x + n * nearest_;
    float total = 0.0f;
    for (int face = 0; face < 5; ++face) {
        Camera camera;
        camera.position = eye;
        camera.look_at = eye + forward[face];
        camera.up = up[face];
        camera.fov_deg = 90.0f;
        CameraMatrices matrices =
            camera_matrices(camera, resolution_, resolution_, bounds_, nearest_);
        PipelineState state;
        state.cull = CullMode::None;
        targets_.clear(resolution_, resolution_, 1, false, true);
        draw_pass(triangles, matrices, state, targets_, threads, 0, &memory_);
        const std::vector<float>& table = face == 0 ? top_ : side_;
        for (size_t cell = 0; cell < table.size(); ++cell) {
            uint32_t item = targets_.primitive[cell];
            if (item == RenderTargets::kNoPrimitive || table[cell] == 0.0f) continue;
            row[item] += table[cell];
            total += table[cell];
        }
    }
    return total;
}

}  // namespace svetlo
