#include "svetlo/pt/direction_tree.h"

#include <atomic>
#include <cmath>

#include "svetlo/core/atomic_add.h"

namespace svetlo {

namespace {

/// The largest float below 1: where a rescaled sample value must stay.
constexpr float kBelowOne = 0x1.fffffep-1f;

/// Picks side 1 with probability b / (a + b) by u, and rescales u to [0,1) within the side.
int pick(float a, float b, float& u) {
    const float sum = a + b;
    const float p0 = sum > 0.0f ? a / sum : 0.5f;
    if (u < p0) {
        u = std::min(u / p0, kBelowOne);
        return 0;
    }
    u = std::min((u - p0) / (1.0f - p0), kBelowOne);
    return 1;
}

}  // namespace

vec2 direction_to_square(vec3 d) {
    const float cos_theta = glm::clamp(d.z, -1.0f, 1.0f);
    float phi = std::atan2(d.y, d.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    return glm::clamp(vec2(0.5f * (cos_theta + 1.0f), phi / (2.0f * kPi)), vec2(0.0f),
                      vec2(kBelowOne));
}

vec3 square_to_direction(vec2 x) {
    const float cos_theta = 2.0f * x.x - 1.0f;
    const float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    const float phi = 2.0f * kPi * x.y;
    return vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

namespace {

/// The mean of max(0, 2 x - 1) over [x0, x0 + size], a column of a quadrant. No quadrant
/// below the root's straddles x = 1/2: the cosine is either zero on it or 2 x - 1 all over.
float mean_cosine(float x0, float size) {
    return x0 >= 0.5f ? 2.0f * (x0 + 0.5f * size) - 1.0f : 0.0f;
}

}  // namespace

DirectionTree::DirectionTree(std::vector<Node> nodes)
    : nodes_(std::move(nodes)), cells_(nodes_.size()) {
    // Each node's column (its left edge in x) and width; children come after their parents.
    std::vector<float> x0(nodes_.size(), 0.0f), width(nodes_.size(), 1.0f);
    for (size_t k = 0; k < nodes_.size(); ++k) {
        cells_[k].child = nodes_[k].child;
        for (int q = 0; q < 4; ++q) {
            const uint32_t c = nodes_[k].child[static_cast<size_t>(q)];
            if (!c) continue;
            width[c] = 0.5f * width[k];
            x0[c] = x0[k] + width[c] * static_cast<float>(q & 1);
        }
    }
    for (size_t k = nodes_.size(); k-- > 0;) {
        for (size_t q = 0; q < 4; ++q) {
            const uint32_t c = nodes_[k].child[q];
            if (c) {
                const std::array<float, 4>& i = cells_[c].irradiance;
                cells_[k].irradiance[q] = i[0] + i[1] + i[2] + i[3];
            } else {
                const float half = 0.5f * width[k];
                cells_[k].irradiance[q] =
                    nodes_[k].energy[q] *
                    mean_cosine(x0[k] + half * static_cast<float>(q & 1), half);
            }
        }
    }
}

float DirectionTree::irradiance() const {
    const std::array<float, 4>& e = cells_[0].irradiance;
    return e[0] + e[1] + e[2] + e[3];
}

vec2 DirectionTree::sample(vec2 u, float& pdf) const {
    vec2 origin(0.0f);
    float size = 1.0f, p = 1.0f;
    uint32_t index = 0;
    for (;;) {
        const Cell& cell = cells_[index];
        const std::array<float, 4>& e = cell.irradiance;
        const int qx = pick(e[0] + e[2], e[1] + e[3], u.x);
        const int qy = pick(e[qx], e[qx + 2], u.y);
        const int q = qx | (qy << 1);
        size *= 0.5f;
        origin += size * vec2(qx, qy);
        p *= 4.0f * e[static_cast<size_t>(q)] / (e[0] + e[1] + e[2] + e[3]);
        const uint32_t child = cell.child[static_cast<size_t>(q)];
        if (child == 0) {
            // In the leaf, x with density in proportion to t = 2 x - 1 on [t0, t1]: its
            // inverse CDF, t = sqrt(t0^2 + u (t1^2 - t0^2)).
            const float t0 = 2.0f * origin.x - 1.0f, t1 = t0 + 2.0f * size;
            const float t = std::sqrt(std::max(0.0f, t0 * t0 + u.x * (t1 * t1 - t0 * t0)));
            // Rounding must not carry x onto the next leaf's edge, where pdf() would find
            // that leaf's density: x stays below the leaf's upper edges.
            const vec2 top(std::nextafter(origin.x + size, 0.0f),
                           std::nextafter(origin.y + size, 0.0f));
            const vec2 x = glm::clamp(vec2(0.5f * (t + 1.0f), origin.y + size * u.y), origin, top);
            pdf = p * (2.0f * x.x - 1.0f) / mean_cosine(origin.x, size);
            return x;
        }
        index = child;
    }
}

float DirectionTree::pdf(vec2 x) const {
    const float t = 2.0f * x.x - 1.0f;
    if (!(t > 0.0f)) return 0.0f;
    float p = 1.0f, x0 = 0.0f, size = 1.0f;
    uint32_t index = 0;
    for (;;) {
        const Cell& cell = cells_[index];
        const std::array<float, 4>& e = cell.irradiance;
        const float sum = e[0] + e[1] + e[2] + e[3];
        if (!(sum > 0.0f)) return 0.0f;
        const int q = quadrant_of(x);
        size *= 0.5f;
        x0 += size * static_cast<float>(q & 1);
        p *= 4.0f * e[static_cast<size_t>(q)] / sum;
        const uint32_t child = cell.child[static_cast<size_t>(q)];
        if (p == 0.0f) return 0.0f;
        if (child == 0) return p * t / mean_cosine(x0, size);
        index = child;
    }
}

float DirectionTree::total() const {
    const Node& root = nodes_[0];
    return root.energy[0] + root.energy[1] + root.energy[2] + root.energy[3];
}

int DirectionTree::depth() const {
    std::vector<int> level(nodes_.size(), 1);  // children come after their parents
    int deepest = 1;
    for (size_t k = 0; k < nodes_.size(); ++k) {
        deepest = std::max(deepest, level[k]);
        for (uint32_t c : nodes_[k].child)
            if (c) level[c] = level[k] + 1;
    }
    return deepest;
}

namespace {

/// Gives node `at` of `out` children where `energy` (its quadrants', from `from`, a node of
/// `tree`, or inherited when null) exceeds `threshold`.
void split(const DirectionTree& tree, const DirectionTree::Node* from,
           const std::array<float, 4>& energy, float threshold, int depth, int max_depth,
           uint32_t at, std::vector<DirectionRecorder::Node>& out) {
    for (int q = 0; q < 4; ++q) {
        if (depth >= max_depth || !(energy[q] > threshold)) continue;
        const DirectionTree::Node* sub =
            from && from->child[q] ? &tree.nodes()[from->child[q]] : nullptr;
        const std::array<float, 4> quarter{energy[q] / 4, energy[q] / 4, energy[q] / 4,
                                           energy[q] / 4};
        const auto index = static_cast<uint32_t>(out.size());
        out.emplace_back();
        out[at].child[static_cast<size_t>(q)] = index;
        split(tree, sub, sub ? sub->energy : quarter, threshold, depth + 1, max_depth, index, out);
    }
}

}  // namespace

DirectionRecorder DirectionRecorder::refined(const DirectionTree& tree, float fraction,
                                             int max_depth) {
    DirectionRecorder r;
    const float total = tree.total();
    if (total > 0.0f) {
        const DirectionTree::Node& root = tree.nodes()[0];
        split(tree, &root, root.energy, fraction * total, 1, max_depth, 0, r.nodes_);
    }
    return r;
}

void DirectionRecorder::add(vec2 x, uint64_t value) {
    // The layout is fixed while a recorder adds: only the leaf's sum is written.
    uint32_t index = 0;
    for (;;) {
        Node& n = nodes_[index];
        const auto q = static_cast<size_t>(quadrant_of(x));
        if (n.child[q] == 0) {
            atomic_add_relaxed(n.sum[q], value);
            return;
        }
        index = n.child[q];
    }
}

std::vector<std::array<uint64_t, 4>> DirectionRecorder::sums() const {
    std::vector<std::array<uint64_t, 4>> s(nodes_.size());
    for (size_t k = nodes_.size(); k-- > 0;) {  // children come after their parents
        for (size_t q = 0; q < 4; ++q) {
            const uint32_t c = nodes_[k].child[q];
            s[k][q] = c ? s[c][0] + s[c][1] + s[c][2] + s[c][3] : nodes_[k].sum[q];
        }
    }
    return s;
}

DirectionTree DirectionRecorder::to_tree(double unit) const {
    const std::vector<std::array<uint64_t, 4>> s = sums();
    std::vector<DirectionTree::Node> nodes(nodes_.size());
    for (size_t k = 0; k < nodes_.size(); ++k) {
        for (size_t q = 0; q < 4; ++q)
            nodes[k].energy[q] = static_cast<float>(static_cast<double>(s[k][q]) * unit);
        nodes[k].child = nodes_[k].child;
    }
    return DirectionTree(std::move(nodes));
}

uint64_t DirectionRecorder::total() const {
    uint64_t t = 0;
    for (const Node& n : nodes_)
        for (size_t q = 0; q < 4; ++q)
            if (n.child[q] == 0) t += n.sum[q];
    return t;
}

}  // namespace svetlo
