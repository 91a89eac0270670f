#include "svetlo/radiosity/adaptive_subdivision.h"

#include <algorithm>

#include "svetlo/core/parallel.h"
#include "svetlo/radiosity/light_shooting.h"
#include "svetlo/radiosity/solver.h"

namespace svetlo {

uint64_t subdivide_adaptive(PatchMesh& mesh, int samples, uint64_t seed, int threads) {
    const RadiositySettings& settings = mesh.settings;
    if (!(settings.adaptive > 0.0f) || settings.max_subdivision == 0) return 0;
    ElementTree& tree = *mesh.tree;
    std::vector<int> base(tree.root_count());
    for (uint32_t r = 0; r < tree.root_count(); ++r)
        base[r] = tree.level_for(r, settings.element_size);

    uint64_t rays = 0;
    float floor = -1.0f;
    for (int round = 0; round < settings.max_subdivision; ++round) {
        std::vector<uint32_t> leaves;
        for (uint32_t id : tree.leaves()) {
            const ElementNode& e = tree.node(id);
            if (e.level < base[e.root] + settings.max_subdivision) leaves.push_back(id);
        }
        // Per leaf and side, the lowest, highest and mean direct irradiance of its 4 points.
        struct Span {
            float lo[2], hi[2], mean[2];
        };
        std::vector<Span> span(leaves.size());
        std::vector<uint64_t> leaf_rays(leaves.size(), 0);
        parallel_ranges(
            leaves.size(), threads,
            [&](size_t begin, size_t end) {
                for (size_t k = begin; k < end; ++k) {
                    const ElementNode& e = tree.node(leaves[k]);
                    Rng rng(mix64(seed + static_cast<uint64_t>(round)), leaves[k]);
                    // The corners pulled 2 % toward the centroid: off the edges where walls meet.
                    const vec3 points[4] = {glm::mix(e.p[0], e.centroid, 0.02f),
                                            glm::mix(e.p[1], e.centroid, 0.02f),
                                            glm::mix(e.p[2], e.centroid, 0.02f), e.centroid};
                    Span s{};
                    for (int side = 0; side < 2; ++side) {
                        vec3 n = side == 0 ? tree.normal(leaves[k]) : -tree.normal(leaves[k]);
                        s.lo[side] = kInfinity;
                        s.hi[side] = 0.0f;
                        s.mean[side] = 0.0f;
                        for (vec3 x : points) {
                            float E = channel_sum(light_irradiance(mesh.lights, *mesh.accel, x, n,
                                                                   LightSources::All, samples, rng,
                                                                   leaf_rays[k]));
                            s.lo[side] = std::min(s.lo[side], E);
                            s.hi[side] = std::max(s.hi[side], E);
                            s.mean[side] += 0.25f * E;
                        }
                    }
                    span[k] = s;
                }
            },
            16);
        for (uint64_t r : leaf_rays) rays += r;
        if (floor < 0.0f) {
            float brightest = 0.0f;
            for (const Span& s : span) brightest = std::max({brightest, s.hi[0], s.hi[1]});
            floor = 0.01f * brightest;
        }
        bool any = false;
        for (size_t k = 0; k < leaves.size(); ++k) {
            bool split = false;
            for (int side = 0; side < 2; ++side) {
                float scale = std::max(span[k].mean[side], floor);
                if (span[k].hi[side] - span[k].lo[side] > settings.adaptive * scale) split = true;
            }
            if (!split) continue;
            if (tree.nodes().size() + 4 > kMaxRadiosityNodes) return rays;
            tree.split(leaves[k]);
            any = true;
        }
        if (!any) break;
    }
    return rays;
}

}  // namespace svetlo
