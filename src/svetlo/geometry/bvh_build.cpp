#include "svetlo/geometry/bvh_build.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "svetlo/core/parallel.h"
#include "svetlo/geometry/avx2.h"
#include "svetlo/geometry/bvh_sah.h"
#include "svetlo/geometry/ray_box.h"
#if SVETLO_SIMD
#include "svetlo/geometry/bvh_sah_sse.h"
#else
#include "svetlo/geometry/bvh_sah_reference.h"
#endif

namespace svetlo {

namespace {

using namespace sah;
// The SAH's kernels: SSE (and AVX2) with SVETLO_SIMD, else their plain twins.
#if SVETLO_SIMD
namespace K = sah::sse;
#else
namespace K = sah::reference;
#endif

constexpr uint32_t kMaxLeaf = 8;
constexpr uint32_t kMinSplit = 4;       // triangles this few become a leaf without a SAH test
constexpr float kTraversalCost = 2.0f;  // relative to one triangle test
// An analytic shape's test (a quad, a box taken to object space, a quadric) in triangle
// tests (one lane of a packet of four). Measured on the hard scenes' rooms of quads and
// boxes: 4 and 8 trace as fast, 2 gives back most of the gain (docs/performance.md, "Leaves
// of analytic shapes").
constexpr float kShapeCost = 4.0f;
constexpr int kMedianDepth = 64;            // below this depth, split at the median
constexpr uint32_t kParallelGrain = 4096;   // smaller subtrees are built serially
constexpr uint32_t kParallelSplit = 65536;  // larger nodes bin and partition in parallel
constexpr uint32_t kSplitChunk = 16384;     // references per task there

/// A node's references: indices [begin, end) of one of the two buffers, with their bounds and
/// the bounds of their centroids (or a box holding them all).
struct Span {
    uint32_t begin, end;
    int buffer;
    Bounds3 bounds, centroids;
    uint32_t size() const { return end - begin; }
};

class Builder {
public:
    /// Ids from `first_shape` on are analytic shapes (geometry.h), the rest triangles.
    Builder(LargeArray<BuildRef>& refs, uint32_t first_shape, BvhNode* nodes, uint32_t* prims)
        : first_shape_(first_shape),
          scratch_(refs.size()),
          buffers_{refs.data(), scratch_.data()},
          nodes_(nodes),
          prims_(prims),
          size_(static_cast<uint32_t>(refs.size())) {}

    uint32_t node_count() const { return node_count_.load(); }  // slots used, holes included
    /// The unused slot ranges [first, last) of serial subtrees, in no particular order.
    const std::vector<std::pair<uint32_t, uint32_t>>& holes() const { return holes_; }
    int depth() const { return depth_.load(); }

    /// Builds the tree; `serial` (one thread) takes every node's slot in depth-first order,
    /// leaving no holes, where threads reserve room for their subtrees.
    void build_root(const Bounds3& bounds, const Bounds3& centroids, bool serial) {
        const Span root{0, size_, 0, bounds, centroids};
        if (serial) {
            Slots all{1};
            depth_ = build(0, root, 1, &all);
            node_count_ = all.next;
            return;
        }
        node_count_ = 1;
        depth_ = build(0, root, 1, nullptr);
        group_.wait();
    }

private:
    /// Node slots reserved for a serial subtree: its descendants never touch the shared
    /// counter (which two threads would otherwise bounce between their caches).
    struct Slots {
        uint32_t next;
    };

    void make_leaf(uint32_t node, const Span& s) {
        nodes_[node] = BvhNode{s.bounds.min, s.begin, s.bounds.max, s.size()};
        for (uint32_t k = s.begin; k < s.end; ++k) prims_[k] = buffers_[s.buffer][k].id;
    }

    /// Builds the subtree of span `s` into `node`; returns its depth.
    int build(uint32_t node, const Span& s, int depth, Slots* slots) {
        const uint32_t n = s.size();
        // Only a span that may become a leaf needs its cost (larger ones are always split).
        const float leaf = n <= kMaxLeaf ? leaf_cost(s) : kInfinity;
        if (n <= kMinSplit && leaf <= static_cast<float>(n)) {
            make_leaf(node, s);
            return depth;
        }
        Span left, right;
        if (max_component(s.centroids.extent()) <= 0.0f) {
            // All centroids coincide: no split can separate them.
            if (n <= kMaxLeaf) {
                make_leaf(node, s);
                return depth;
            }
            split_at_index(s, s.begin + n / 2, left, right);
        } else if (depth >= kMedianDepth) {
            const int axis = max_dimension(s.centroids.extent());
            BuildRef* refs = buffers_[s.buffer];
            std::nth_element(refs + s.begin, refs + s.begin + n / 2, refs + s.end,
                             [axis](const BuildRef& a, const BuildRef& b) {
                                 return a.centroid()[axis] < b.centroid()[axis];
                             });
            split_at_index(s, s.begin + n / 2, left, right);
        } else if (!sah_split(s, leaf, left, right)) {
            make_leaf(node, s);
            return depth;
        }
        Slots local{0};
        if (!slots && n < kParallelGrain) {
            // A subtree of n primitives has at most 2 n - 2 descendants; those it does not use
            // are a hole at the end of its range, recorded for the compaction.
            local.next = node_count_.fetch_add(2 * n - 2);
            uint32_t start = local.next;
            int d = build_children(node, s, left, right, depth, &local);
            std::lock_guard<std::mutex> lock(holes_mutex_);
            holes_.push_back({local.next, start + 2 * n - 2});
            return d;
        }
        return build_children(node, s, left, right, depth, slots);
    }

    /// Makes `node` an inner node over its two children and builds them.
    int build_children(uint32_t node, const Span& s, const Span& left, const Span& right, int depth,
                       Slots* slots) {
        uint32_t first = slots ? slots->next : node_count_.fetch_add(2);
        if (slots) slots->next += 2;
        nodes_[node] = BvhNode{s.bounds.min, first, s.bounds.max, 0};
        if (!slots) {  // a subtree of kParallelGrain references or more, on several threads
            group_.run([=, this] {
                int d = build(first, left, depth + 1, nullptr);
                int seen = depth_.load();
                while (d > seen && !depth_.compare_exchange_weak(seen, d)) {
                }
            });
            return build(first + 1, right, depth + 1, nullptr);
        }
        int dl = build(first, left, depth + 1, slots);
        int dr = build(first + 1, right, depth + 1, slots);
        return std::max(dl, dr);
    }

    /// The span of refs [begin, end) of `buffer`, with its exact bounds and centroid bounds.
    Span span_of(uint32_t begin, uint32_t end, int buffer) const {
        Span s{begin, end, buffer, Bounds3{}, Bounds3{}};
        for (uint32_t k = begin; k < end; ++k) {
            const BuildRef& r = buffers_[buffer][k];
            s.bounds.extend(r.min);
            s.bounds.extend(r.max);
            s.centroids.extend(r.centroid());
        }
        return s;
    }

    /// Splits `s` where it lies, at index `mid`.
    void split_at_index(const Span& s, uint32_t mid, Span& left, Span& right) const {
        left = span_of(s.begin, mid, s.buffer);
        right = span_of(mid, s.end, s.buffer);
    }

    /// Bins the centroids along the axis of largest centroid extent, chooses the cheapest of
    /// the kBins - 1 bin boundaries by SAH and moves the references into the other buffer,
    /// in order, the left child's first. Returns false when a leaf (costing `leaf` triangle
    /// tests; a span of more than kMaxLeaf is never one) is cheaper and allowed; the
    /// children's tests are weighed as the span's mean primitive.
    /// Spans of at most kBins references are sorted instead, every reference its own bin.
    /// Binning one axis (Wald 2007) costs a third of binning three and loses little quality.
    /// Large spans are binned and partitioned in chunks in parallel: each chunk's bins give
    /// it its place in the other buffer, and min, max and sums are exact in any order, so the
    /// tree does not depend on the threads.
    bool sah_split(const Span& s, float leaf, Span& left, Span& right) {
        const uint32_t n = s.size();
        const BinPosition position(s.centroids);
        BuildRef* src = buffers_[s.buffer];
        BuildRef* dst = buffers_[1 - s.buffer];
        const bool sorted = n <= kBins;
        std::vector<K::Bins> chunk_bins;
        const K::Sweep sweep = sorted ? sorted_sweep(src, dst, s, position)
                                      : binned_sweep(src, s, position, chunk_bins);
        float best_cost = kInfinity;
        const int best_bin = sweep.cheapest(best_cost);
        const float node_area = s.bounds.surface_area();
        const float split_cost =
            n <= kMaxLeaf && node_area > 0.0f
                ? kTraversalCost + best_cost / node_area * (leaf / static_cast<float>(n))
                : kInfinity;
        if (best_bin < 0 || (n <= kMaxLeaf && leaf <= split_cost)) {
            if (n <= kMaxLeaf) return false;
            // No useful split but too many for a leaf: split at the median index.
            split_at_index(s, s.begin + n / 2, left, right);
            return true;
        }
        const uint32_t mid = s.begin + static_cast<uint32_t>(sweep.left_count[best_bin]);
        const auto last_left = static_cast<uint32_t>(best_bin);
        if (sorted) {
            // Already in the other buffer, in order.
        } else if (chunk_bins.empty()) {
            K::partition_range(src, dst, s.begin, s.end, s.begin, mid, last_left, avx2_);
        } else {
            const auto chunks = static_cast<uint32_t>(chunk_bins.size());
            std::vector<uint32_t> lefts(chunks + 1, 0);  // left references before each chunk
            for (uint32_t c = 0; c < chunks; ++c) {
                uint32_t in_left = 0;
                for (int b = 0; b <= best_bin; ++b) in_left += chunk_bins[c].count[b];
                lefts[c + 1] = lefts[c] + in_left;
            }
            parallel_for_each(chunks, [&](size_t chunk) {
                const auto c = static_cast<uint32_t>(chunk);
                const uint32_t first = s.begin + c * kSplitChunk;
                K::partition_range(src, dst, first, std::min(s.end, first + kSplitChunk),
                                   s.begin + lefts[c], mid + (first - s.begin - lefts[c]),
                                   last_left, avx2_);
            });
        }
        // The children's bounds from the sweep; their centroid bounds are approximated by the
        // primitive bounds, which contain every centroid (binning only needs a range).
        const Bounds3 lb = K::to_bounds(sweep.left_min[best_bin], sweep.left_max[best_bin]);
        const Bounds3 rb =
            K::to_bounds(sweep.right_min[best_bin + 1], sweep.right_max[best_bin + 1]);
        left = Span{s.begin, mid, 1 - s.buffer, lb, lb};
        right = Span{mid, s.end, 1 - s.buffer, rb, rb};
        return true;
    }

    /// The sweep over the bins of a span of more than kBins references; a large span is binned
    /// in chunks, whose bins are left in `chunk_bins`.
    K::Sweep binned_sweep(BuildRef* src, const Span& s, const BinPosition& position,
                          std::vector<K::Bins>& chunk_bins) const {
        K::Bins bins;
        if (s.size() < kParallelSplit) {
            K::bin_range(src, s.begin, s.end, position, bins, avx2_);
        } else {
            chunk_bins.resize((s.size() + kSplitChunk - 1) / kSplitChunk);
            parallel_for_each(chunk_bins.size(), [&](size_t c) {
                const uint32_t first = s.begin + static_cast<uint32_t>(c) * kSplitChunk;
                K::bin_range(src, first, std::min(s.end, first + kSplitChunk), position,
                             chunk_bins[c], avx2_);
            });
            for (const K::Bins& b : chunk_bins) bins.merge(b);
        }
        return K::Sweep(kBins, s.size(), [&](int b) {
            return K::Cell{bins.min[b], bins.max[b], bins.count[b]};
        });
    }

    /// The sweep over a span of at most kBins references, written into the other buffer
    /// sorted along the axis, each its own cell: every split between two centroids is tried
    /// (the exact SAH on that axis, cheaper than binning for so few).
    K::Sweep sorted_sweep(const BuildRef* src, BuildRef* dst, const Span& s,
                          const BinPosition& position) const {
        const uint32_t n = s.size();
        // The keys: a NaN counts as -inf; past the span, +inf.
        alignas(32) float key[kBins];
        for (uint32_t k = 0; k < n; ++k) {
            const float f = position(src[s.begin + k]);
            key[k] = f == f ? f : -kInfinity;
        }
        for (uint32_t k = n; k < kBins; ++k) key[k] = kInfinity;
        uint32_t rank[kBins];
        K::rank_keys(key, n, rank, avx2_);
        for (uint32_t k = 0; k < n; ++k) K::copy_ref(src[s.begin + k], dst[s.begin + rank[k]]);
        return K::Sweep(static_cast<int>(n), n,
                        [&](int b) { return K::cell_of(dst[s.begin + b]); });
    }

    /// What testing every primitive of `s` costs, in triangle tests.
    float leaf_cost(const Span& s) const {
        float cost = static_cast<float>(s.size());
        if (first_shape_ >= size_) return cost;  // triangles only: skip the count
        const BuildRef* refs = buffers_[s.buffer];
        for (uint32_t k = s.begin; k < s.end; ++k)
            if (refs[k].id >= first_shape_) cost += kShapeCost - 1.0f;
        return cost;
    }

    uint32_t first_shape_;          // ids from here on are analytic shapes
    LargeArray<BuildRef> scratch_;  // the second buffer, same indices as the first
    BuildRef* buffers_[2];          // a node's children lie in the other buffer than it
    BvhNode* nodes_;                // room for 2 n - 1 nodes
    uint32_t* prims_;               // the leaves' primitive ids, same indices as the buffers
    uint32_t size_;
    bool avx2_ = avx2_available();  // bin and partition with AVX2
    std::atomic<uint32_t> node_count_{0};
    std::atomic<int> depth_{0};
    std::mutex holes_mutex_;
    std::vector<std::pair<uint32_t, uint32_t>> holes_;
    TaskGroup group_;
};

}  // namespace

namespace {

/// Every box moved out by one ulp on every side (ray_box.h, widen_box).
void widen(LargeArray<BvhNode>& nodes) {
    for (size_t k = 0; k < nodes.size(); ++k) widen_box(nodes[k].min, nodes[k].max);
}

BvhBuild build_tight(const Geometry& geometry, int threads);

}  // namespace

BvhBuild build_bvh(const Geometry& geometry, int threads) {
    BvhBuild out = build_tight(geometry, threads);
    widen(out.nodes);
    return out;
}

namespace {

/// The BVH with every box the tight union of its primitives' bounds.
BvhBuild build_tight(const Geometry& geometry, int threads) {
    // Every triangle, then the bounded shapes (infinite planes are tested apart).
    const uint32_t triangles = geometry.triangle_count();
    std::vector<uint32_t> shapes;
    for (uint32_t id : geometry.bounded_primitives_from(triangles)) shapes.push_back(id);
    const size_t n = triangles + shapes.size();
    BvhBuild out;
    if (n == 0) return out;
    LargeArray<BuildRef> refs(n);
    int workers = resolve_threads(threads);
    // The references and their bounds, in chunks merged in order.
    size_t chunks = std::min<size_t>(static_cast<size_t>(workers) * 4, (n + 4095) / 4096);
    std::vector<Bounds3> chunk_bounds(chunks), chunk_centroids(chunks);
    with_threads(workers, [&] {
        parallel_for_each(chunks, [&](size_t c) {
            K::make_refs(geometry, shapes, c * n / chunks, (c + 1) * n / chunks, refs.data(),
                         chunk_bounds[c], chunk_centroids[c]);
        });
    });
    Bounds3 bounds, centroids;
    for (size_t c = 0; c < chunks; ++c) {
        bounds.extend(chunk_bounds[c]);
        centroids.extend(chunk_centroids[c]);
    }
    // Uninitialised room for the worst case (2 n - 1 nodes): untouched pages cost nothing.
    // Threads write about a third of it, in runs spread over it, so it takes small pages
    // there; one thread writes it from the start, so huge pages (fewer faults) serve.
    const bool serial = workers == 1;
    LargeArray<BvhNode> room(2 * refs.size(), serial);
    out.prims = LargeArray<uint32_t>(refs.size());
    Builder builder(refs, triangles, room.data(), out.prims.data());
    with_threads(workers, [&] { builder.build_root(bounds, centroids, serial); });
    out.depth = builder.depth();
    if (builder.holes().empty()) {
        // Built on one thread: the room holds the nodes as they are (the pages past them
        // were never touched).
        out.nodes = std::move(room);
        out.nodes.truncate(builder.node_count());
        return out;
    }
    // Serial subtrees leave unused slots at the end of their ranges: copy the used runs in
    // order (each subtree stays contiguous, in the depth-first order it was built in) and move
    // every child index down by the size of the holes before it.
    std::vector<std::pair<uint32_t, uint32_t>> holes = builder.holes();
    std::sort(holes.begin(), holes.end());
    std::vector<uint32_t> run_start = {0}, shift = {0};  // from run_start[k] on, move down shift[k]
    for (auto [first, last] : holes) {
        run_start.push_back(last);
        shift.push_back(shift.back() + (last - first));
    }
    uint32_t total = builder.node_count();
    uint32_t count = total - shift.back();
    out.nodes = LargeArray<BvhNode>(count);
    auto moved = [&](uint32_t old) {
        size_t k = static_cast<size_t>(std::upper_bound(run_start.begin(), run_start.end(), old) -
                                       run_start.begin()) -
                   1;
        return old - shift[k];
    };
    with_threads(workers, [&] {
        parallel_for_each(run_start.size(), [&](size_t k) {
            uint32_t first = run_start[k];
            uint32_t last = k + 1 < run_start.size() ? holes[k].first : total;
            for (uint32_t i = first; i < last; ++i) {
                BvhNode node = room[i];
                // A serial subtree's children lie in its own run: no search for them.
                if (node.count == 0)
                    node.first = node.first - first < last - first ? node.first - shift[k]
                                                                   : moved(node.first);
                out.nodes[i - shift[k]] = node;
            }
        });
    });
    out.nodes.truncate(count);
    return out;
}

}  // namespace

}  // namespace svetlo
