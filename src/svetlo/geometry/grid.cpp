#include "svetlo/geometry/grid.h"

#include <algorithm>
#include <cmath>

#include "svetlo/geometry/ray_box.h"

namespace svetlo {

namespace {

constexpr double kCellsPerPrimitive = 2.0;
constexpr int kMaxResolution = 512;             // cells along one axis
constexpr uint64_t kMaxReferences = 64u << 20;  // cell entries: bounds the memory (256 MiB)

}  // namespace

Grid::Grid(const Geometry& geometry) : geometry_(geometry) {
    std::vector<uint32_t> ids = geometry.bounded_primitives();
    if (ids.empty()) return;
    std::vector<Bounds3> prim_bounds(ids.size());
    for (size_t k = 0; k < ids.size(); ++k) {
        prim_bounds[k] = geometry.primitive_bounds(ids[k]);
        bounds_.extend(prim_bounds[k]);
    }
    // Pad flat bounds so every axis has a positive width.
    vec3 extent = bounds_.extent();
    float pad = 1e-4f * std::max(max_component(extent), 1e-3f);
    for (int a = 0; a < 3; ++a) {
        if (extent[a] <= pad) {
            bounds_.min[a] -= pad;
            bounds_.max[a] += pad;
        }
    }
    widen_box(bounds_.min, bounds_.max);
    extent = bounds_.extent();
    double volume = static_cast<double>(extent.x) * extent.y * extent.z;
    double density = std::cbrt(kCellsPerPrimitive * static_cast<double>(ids.size()) / volume);
    // Cells overlapped by each primitive; if the references would exceed the budget (large
    // primitives in a fine grid), halve the resolution until they fit.
    std::vector<std::array<int, 6>> ranges(ids.size());
    for (;;) {
        for (int a = 0; a < 3; ++a) {
            res_[a] =
                std::clamp(static_cast<int>(std::lround(extent[a] * density)), 1, kMaxResolution);
            cell_size_[a] = extent[a] / static_cast<float>(res_[a]);
        }
        uint64_t refs = 0;
        for (size_t k = 0; k < ids.size(); ++k) {
            uint64_t cells = 1;
            for (int a = 0; a < 3; ++a) {
                auto cell = [&](float x) {
                    return std::clamp(static_cast<int>((x - bounds_.min[a]) / cell_size_[a]), 0,
                                      res_[a] - 1);
                };
                ranges[k][a] = cell(prim_bounds[k].min[a]);
                ranges[k][a + 3] = cell(prim_bounds[k].max[a]);
                cells *= static_cast<uint64_t>(ranges[k][a + 3] - ranges[k][a] + 1);
            }
            refs += cells;
        }
        if (refs <= kMaxReferences || (res_[0] == 1 && res_[1] == 1 && res_[2] == 1)) break;
        density *= 0.5;
    }
    size_t cells = static_cast<size_t>(res_[0]) * res_[1] * res_[2];
    cell_start_.assign(cells + 1, 0);
    auto for_cells = [&](const std::array<int, 6>& r, auto&& f) {
        for (int z = r[2]; z <= r[5]; ++z)
            for (int y = r[1]; y <= r[4]; ++y)
                for (int x = r[0]; x <= r[3]; ++x)
                    f((static_cast<size_t>(z) * res_[1] + y) * res_[0] + x);
    };
    for (const auto& r : ranges) for_cells(r, [&](size_t c) { cell_start_[c + 1]++; });
    for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
    cell_prims_.resize(cell_start_[cells]);
    std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (size_t k = 0; k < ids.size(); ++k) {
        for_cells(ranges[k], [&](size_t c) { cell_prims_[fill[c]++] = ids[k]; });
    }
}

template <class Visit>
void Grid::walk(const Ray& ray, float tmax, Visit&& visit) const {
    if (cell_start_.empty()) return;
    vec3 inv_d = safe_inverse(ray.d);
    float t0, t1;
    if (!ray_box(bounds_.min, bounds_.max, ray.o, inv_d, tmax, t0, t1)) return;
    vec3 entry = ray.o + t0 * ray.d;
    int cell[3], step[3], out[3];
    float t_next[3], t_delta[3];
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(static_cast<int>((entry[a] - bounds_.min[a]) / cell_size_[a]), 0,
                             res_[a] - 1);
        if (ray.d[a] > 0.0f) {
            step[a] = 1;
            out[a] = res_[a];
            float boundary = bounds_.min[a] + static_cast<float>(cell[a] + 1) * cell_size_[a];
            t_next[a] = (boundary - ray.o[a]) * inv_d[a];
            t_delta[a] = cell_size_[a] * inv_d[a];
        } else if (ray.d[a] < 0.0f) {
            step[a] = -1;
            out[a] = -1;
            float boundary = bounds_.min[a] + static_cast<float>(cell[a]) * cell_size_[a];
            t_next[a] = (boundary - ray.o[a]) * inv_d[a];
            t_delta[a] = -cell_size_[a] * inv_d[a];
        } else {
            step[a] = 0;
            out[a] = -2;
            t_next[a] = kInfinity;
            t_delta[a] = kInfinity;
        }
    }
    for (;;) {
        // The axis whose cell boundary comes first.
        int a = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2)
                                      : (t_next[1] < t_next[2] ? 1 : 2);
        float t_exit = std::min(t_next[a], t1) * kSlabRobust;
        size_t c = (static_cast<size_t>(cell[2]) * res_[1] + cell[1]) * res_[0] + cell[0];
        uint32_t first = cell_start_[c], last = cell_start_[c + 1];
        if (first != last && visit(first, last, t_exit)) return;
        if (t_next[a] > t1) return;
        cell[a] += step[a];
        if (cell[a] == out[a]) return;
        t_next[a] += t_delta[a];
    }
}

bool Grid::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    hit.t = ray.tmax;
    RayPrecomputed pre(ray);
    bool found = false;
    walk(ray, ray.tmax, [&](uint32_t first, uint32_t last, float t_exit) {
        found |= geometry_.intersect(cell_prims_.data() + first, last - first, ray, pre, hit);
        // A hit beyond this cell may be beaten by a primitive in a later cell.
        return found && hit.t <= t_exit;
    });
    return found;
}

bool Grid::occluded(const Ray& ray) const {
    RayPrecomputed pre(ray);
    bool found = false;
    walk(ray, ray.tmax, [&](uint32_t first, uint32_t last, float) {
        found = geometry_.occludes(cell_prims_.data() + first, last - first, ray, pre);
        return found;
    });
    return found;
}

}  // namespace svetlo
