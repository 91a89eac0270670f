#include "svetlo/radiosity/shot_rows.h"

#include <atomic>

#include "svetlo/core/parallel.h"

namespace svetlo {

ShotRow Shooter::make_row(uint32_t patch, uint32_t node, int side) {
    const ElementTree& tree = in_.tree;
    const ElementNode& p = tree.node(node);
    if (hemicube_) {
        std::fill(hemicube_row_.begin(), hemicube_row_.end(), 0.0f);
        vec3 n = side == 0 ? tree.normal(node) : -tree.normal(node);
        hemicube_->gather(triangles_, p.centroid, n, hemicube_row_, in_.threads);
    }
    std::atomic<uint64_t> rays{0};
    parallel_ranges(
        leaves_.size(), in_.threads,
        [&](size_t begin, size_t end) {
            uint64_t local_rays = 0;
            for (size_t k = begin; k < end; ++k) {
                dense_[k] = FormFactor{};
                const uint32_t leaf = leaves_[k];
                const ElementNode& e = tree.node(leaf);
                if (!mine_[k]) continue;              // another rank's
                if (patch_of_[k] == patch) continue;  // a patch does not light itself
                if (hemicube_) {
                    // Reciprocity: F_ep = A_p F_pe / A_e, onto the side facing the hemicube.
                    dense_[k].F[tree.side_facing(leaf, p.centroid)] =
                        hemicube_row_[k] * p.area / e.area;
                    continue;
                }
                // Only the shooting side's light: the side of the patch that faces e.
                if (tree.side_facing(node, e.centroid) != side) continue;
                dense_[k] = form_factor(in_.ff, leaf, node, in_.seed, local_rays);
            }
            rays += local_rays;
        },
        256);
    rays_ += rays.load();
    // Exactly the room the entries take: the cache's budget counts it.
    size_t entries = 0;
    for (const FormFactor& F : dense_) entries += (F.F[0] > 0.0f) + (F.F[1] > 0.0f);
    ShotRow out;
    out.target.reserve(entries);
    out.factor.reserve(entries);
    for (size_t k = 0; k < leaves_.size(); ++k) {
        for (int s = 0; s < 2; ++s) {
            if (!(dense_[k].F[s] > 0.0f)) continue;
            out.target.push_back(static_cast<uint32_t>(2 * k + s));
            out.factor.push_back(dense_[k].F[s]);
        }
    }
    return out;
}

}  // namespace svetlo
