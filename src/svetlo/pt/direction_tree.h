// The directional half of path guiding's SD-tree (Müller, Gross and Novák 2017, "Practical
// Path Guiding for Efficient Light-Transport Simulation", EGSR; docs/path.md, "Path
// guiding"): a quadtree over the square [0,1)^2 that stands for the sphere of directions by
// the cylindrical, area-preserving map x = (cos theta + 1) / 2, y = phi / (2 pi). Each node
// holds, per quadrant, an estimate of the incident radiance integrated over the directions
// of that quadrant. A direction is drawn in proportion to the product of that radiance and
// the cosine about the square's polar axis, max(0, cos theta) = max(0, 2 x - 1): the light a
// diffuse surface facing that axis reflects (Herholz et al. 2016 sample such products with
// mixtures; here the cosine depends on x alone, so each quadrant's share of the product is
// exact, and a leaf draws x in proportion to the cosine and y uniformly). One steradian is
// 1 / (4 pi) of the square.
//
// Two trees take turns (guiding_field.h): a DirectionTree draws directions during one
// training iteration while a DirectionRecorder of a finer layout adds up the radiance the
// paths bring; at the end of the iteration the recorder becomes the next DirectionTree.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "svetlo/core/math.h"

namespace svetlo {

/// The point of the square for unit direction d, and back (world space, z the polar axis).
vec2 direction_to_square(vec3 d);
vec3 square_to_direction(vec2 x);
/// Steradians per unit of the square's area: the sphere's 4 pi over the square's 1.
inline constexpr float kSquareToSolidAngle = 4.0f * kPi;

/// The quadrant of x in a node (bit 0: x.x >= 1/2, bit 1: x.y >= 1/2), and x in the
/// quadrant's own unit square.
inline int quadrant_of(vec2& x) {
    const int qx = x.x >= 0.5f, qy = x.y >= 0.5f;
    x = glm::clamp(2.0f * x - vec2(qx, qy), vec2(0.0f), vec2(1.0f));
    return qx | (qy << 1);
}

class DirectionTree {
public:
    struct Node {
        std::array<float, 4> energy{};    // per quadrant, >= 0
        std::array<uint32_t, 4> child{};  // the quadrant's node, 0: the quadrant is a leaf
    };

    /// One node, no energy: nothing to draw from.
    DirectionTree() : nodes_(1), cells_(1) {}
    explicit DirectionTree(std::vector<Node> nodes);

    /// The energy of the whole sphere.
    float total() const;
    /// The energy times the cosine over the upper hemisphere (the irradiance, in the
    /// energy's units); draws and densities need it above zero.
    float irradiance() const;
    /// A point of the square drawn with density pdf(x) from u in [0,1)^2, and that density:
    /// each level picks its column by u.x and the quadrant in it by u.y, in proportion to
    /// the quadrants' irradiance, and rescales them for the next; the leaf draws x by the
    /// cosine.
    vec2 sample(vec2 u, float& pdf) const;
    /// The density over the square: the product, level by level, of 4 i_q / sum(i), times,
    /// in the leaf, the cosine over its mean there. Zero on the lower half (x < 1/2).
    float pdf(vec2 x) const;

    const std::vector<Node>& nodes() const { return nodes_; }
    /// The depth of the deepest leaf (the root's quadrants are at depth 1).
    int depth() const;

private:
    std::vector<Node> nodes_;  // nodes_[0] is the root
    /// What draws and densities read, a cache line's half per node: per quadrant, the
    /// energy times the cosine integrated over it, and the child (nodes_'s).
    struct alignas(32) Cell {
        std::array<float, 4> irradiance{};
        std::array<uint32_t, 4> child{};
    };
    std::vector<Cell> cells_;
};

class DirectionRecorder {
public:
    struct Node {
        /// Per leaf quadrant, the sum of what was added there, in fixed point
        /// (guiding_field.h); a quadrant with a child keeps 0, its sum is its children's.
        std::array<uint64_t, 4> sum{};
        std::array<uint32_t, 4> child{};
    };

    /// One node: four quadrants.
    DirectionRecorder() : nodes_(1) {}

    /// A recorder whose layout follows the energy of `tree` (Müller et al., section 5.3): a
    /// quadrant holding more than `fraction` of the total is split, to `max_depth` levels;
    /// the rest stay leaves. A quadrant split where the tree had a leaf takes a quarter of
    /// its energy to each child. Its sums start at zero.
    static DirectionRecorder refined(const DirectionTree& tree, float fraction, int max_depth);

    /// Adds `value` (fixed point) to the leaf quadrant that contains x: one atomic add, so
    /// that many threads may call it at once, and the sums do not depend on the order:
    /// integers.
    void add(vec2 x, uint64_t value);
    /// The tree of these sums, each quadrant's the sum of the leaves under it, multiplied
    /// by `unit`.
    DirectionTree to_tree(double unit) const;
    /// The sum of every leaf.
    uint64_t total() const;
    size_t size() const { return nodes_.size(); }

private:
    /// Every quadrant's sum, the leaves' added up to the root.
    std::vector<std::array<uint64_t, 4>> sums() const;

    std::vector<Node> nodes_;
};

}  // namespace svetlo
