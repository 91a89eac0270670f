#include "svetlo/geometry/box_tree.h"

#include <algorithm>
#include <stdexcept>

#include "svetlo/geometry/ray_box.h"

namespace svetlo {

namespace {

constexpr int kBins = 16;
/// Wide levels built by the SAH; below them each split is at the median, so that no input
/// (boxes at exponentially spaced places, which the SAH peels off one at a time) makes the
/// tree deeper than the traversal's stack allows (kStackSize: 36 levels of seven entries).
constexpr int kSahLevels = 12;

float half_area(const Bounds3& b) {
    const vec3 e = b.extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

Bounds3 bounds_of(std::span<const uint32_t> part, std::span<const Bounds3> boxes) {
    Bounds3 b;
    for (uint32_t k : part) b.extend(boxes[k]);
    return b;
}

/// Splits `part` (at least two boxes) in two and returns the size of the first part (1 to
/// size - 1): by the binned SAH over the boxes' centres along the axis where they spread
/// most, or at the median along it when `sah` is false or the centres coincide.
size_t split(std::span<uint32_t> part, std::span<const Bounds3> boxes, bool sah) {
    Bounds3 centres;
    for (uint32_t k : part) centres.extend(boxes[k].center());
    const int axis = max_dimension(centres.extent());
    const float lo = centres.min[axis], extent = centres.extent()[axis];
    const size_t n = part.size();
    const auto median = [&] {
        std::nth_element(part.begin(), part.begin() + n / 2, part.end(),
                         [&](uint32_t a, uint32_t b) {
                             return boxes[a].center()[axis] < boxes[b].center()[axis];
                         });
        return n / 2;
    };
    if (!sah || !(extent > 0.0f)) return median();
    const float scale = static_cast<float>(kBins) / extent;
    const auto bin_of = [&](uint32_t k) {
        const float f = (boxes[k].center()[axis] - lo) * scale;
        return f > 0.0f ? std::min(static_cast<int>(f), kBins - 1) : 0;
    };
    Bounds3 bin_box[kBins];
    size_t bin_count[kBins] = {};
    for (uint32_t k : part) {
        const int b = bin_of(k);
        bin_box[b].extend(boxes[k]);
        ++bin_count[b];
    }
    // The cost of a split after bin b: each side's half area times its boxes.
    float right_cost[kBins] = {};
    Bounds3 side;
    size_t count = 0;
    for (int b = kBins - 1; b > 0; --b) {
        side.extend(bin_box[b]);
        count += bin_count[b];
        right_cost[b] = count > 0 ? half_area(side) * static_cast<float>(count) : 0.0f;
    }
    side = Bounds3{};
    count = 0;
    int best_bin = -1;
    float best = kInfinity;
    for (int b = 0; b + 1 < kBins; ++b) {
        side.extend(bin_box[b]);
        count += bin_count[b];
        if (count == 0 || count == n) continue;
        const float cost = half_area(side) * static_cast<float>(count) + right_cost[b + 1];
        if (cost < best) {
            best = cost;
            best_bin = b;
        }
    }
    if (best_bin < 0) return median();
    const auto middle =
        std::partition(part.begin(), part.end(), [&](uint32_t k) { return bin_of(k) <= best_bin; });
    return static_cast<size_t>(middle - part.begin());
}

}  // namespace

BoxTree::BoxTree(std::span<const Bounds3> boxes, int width) {
    width_ = width != 4 && WideBvh::eight_wide_available() ? 8 : 4;
    std::vector<uint32_t> order;
    for (uint32_t k = 0; k < boxes.size(); ++k)
        if (!boxes[k].empty()) order.push_back(k);
    if (order.empty()) return;
    if (boxes.size() > kWideLeaf) throw std::length_error("a box tree holds at most 2^31 boxes");
    if (width_ == 8) {
        nodes8_.reserve(order.size());
        build<8>(order, boxes, nodes8_, 0);
    } else {
        nodes4_.reserve(order.size());
        build<4>(order, boxes, nodes4_, 0);
    }
}

// A node over `order`: its W parts found by splitting the largest part (by box area) of more
// than one box until there are W; a part of one box is a leaf, a larger one a node below.
template <int W>
uint32_t BoxTree::build(std::span<uint32_t> order, std::span<const Bounds3> boxes,
                        std::vector<WideBvhNode<W>>& nodes, int level) {
    const auto index = static_cast<uint32_t>(nodes.size());
    nodes.emplace_back();
    depth_ = std::max(depth_, level + 1);
    std::span<uint32_t> parts[W] = {order};
    Bounds3 part_box[W] = {bounds_of(order, boxes)};
    int n = 1;
    while (n < W) {
        // (Any part that can be split is taken, whatever its area: a box reaching infinity
        // has area NaN (inf times 0), and a node of one unsplit part would never end.)
        int largest = -1;
        float largest_area = 0.0f;
        for (int k = 0; k < n; ++k) {
            if (parts[k].size() < 2) continue;
            const float area = half_area(part_box[k]);
            if (largest < 0 || area > largest_area) {
                largest = k;
                largest_area = area;
            }
        }
        if (largest < 0) break;
        const std::span<uint32_t> whole = parts[largest];
        const size_t first = split(whole, boxes, level < kSahLevels);
        parts[largest] = whole.first(first);
        parts[n] = whole.subspan(first);
        part_box[largest] = bounds_of(parts[largest], boxes);
        part_box[n] = bounds_of(parts[n], boxes);
        ++n;
    }
    WideBvhNode<W> node;
    for (int k = 0; k < n; ++k) widen_box(part_box[k].min, part_box[k].max);  // as every structure
    for (int k = 0; k < W; ++k) {
        for (int a = 0; a < 3; ++a) {
            node.box[a][k] = k < n ? part_box[k].min[a] : kInfinity;
            node.box[a + 3][k] = k < n ? part_box[k].max[a] : -kInfinity;
        }
        node.child[k] = kWideEmpty;
    }
    for (int k = 0; k < n; ++k)
        node.child[k] = parts[k].size() == 1 ? kWideLeaf | parts[k][0]
                                             : build<W>(parts[k], boxes, nodes, level + 1);
    nodes[index] = node;
    return index;
}

bool BoxTree::closest(const Ray& ray, Hit& hit, BoxLeafTest leaf, uint32_t* visited) const {
    if (width_ == 8)
        return !nodes8_.empty() && wide::boxes_closest8(nodes8_.data(), ray, hit, leaf, visited);
    return !nodes4_.empty() && wide::boxes_closest4(nodes4_.data(), ray, hit, leaf, visited);
}

bool BoxTree::any(const Ray& ray, BoxLeafTest leaf) const {
    if (width_ == 8) return !nodes8_.empty() && wide::boxes_any8(nodes8_.data(), ray, leaf);
    return !nodes4_.empty() && wide::boxes_any4(nodes4_.data(), ray, leaf);
}

}  // namespace svetlo
