#include "svetlo/geometry/bvh.h"

#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>

#include "svetlo/core/parallel.h"
#include "svetlo/geometry/ray_box.h"

namespace svetlo {

namespace {

constexpr int kBins = 16;
constexpr uint32_t kMaxLeaf = 8;
constexpr uint32_t kMinSplit = 4;           // nodes this small become leaves without a SAH test
constexpr float kTraversalCost = 2.0f;      // relative to one primitive test
constexpr int kMedianDepth = 64;            // below this depth, split at the median
constexpr uint32_t kParallelGrain = 4096;   // smaller subtrees are built serially
constexpr uint32_t kParallelSplit = 65536;  // larger nodes bin and partition in parallel
constexpr uint32_t kSplitChunk = 16384;     // references per task there
constexpr int kStackSize = 128;             // > kMedianDepth + log2(2^32)

/// A primitive during the build: its bounds and id, 32 bytes, partitioned in place.
struct BuildRef {
    vec3 min;
    uint32_t id;
    vec3 max;
    float pad;
    vec3 centroid() const { return 0.5f * min + 0.5f * max; }  // no overflow near 3.4e38
};
static_assert(sizeof(BuildRef) == 32 && offsetof(BuildRef, max) == 16);

/// Where a reference's centroid lies along the axis of largest centroid extent, in bins
/// (fractional), and the bin that holds it. The axis is an offset into the reference, so that
/// the per-reference work has no switch on it.
struct BinPosition {
    int axis;
    float cmin, scale;
    explicit BinPosition(const Bounds3& centroids)
        : axis(max_dimension(centroids.extent())),
          cmin(centroids.min[axis]),
          scale(static_cast<float>(kBins) * 0.99999f / centroids.extent()[axis]) {}
    float operator()(const BuildRef& r) const {
        const auto* f = reinterpret_cast<const float*>(&r);  // min at f[0..2], max at f[4..6]
        return (0.5f * f[axis] + 0.5f * f[axis + 4] - cmin) * scale;
    }
    /// The position clamped to [0, kBins - 1] and truncated; maxss returns its second operand
    /// (0) for a NaN position.
    int bin(const BuildRef& r) const {
        __m128 f = _mm_max_ss(_mm_set_ss((*this)(r)), _mm_setzero_ps());
        return _mm_cvttss_si32(_mm_min_ss(f, _mm_set_ss(static_cast<float>(kBins - 1))));
    }
};

/// SAH bins: the bounds (SSE registers; lane 3 unused) and the count of each.
struct Bins {
    __m128 min[kBins], max[kBins];
    uint32_t count[kBins];
    Bins() {
        for (int b = 0; b < kBins; ++b) {
            min[b] = _mm_set1_ps(kInfinity);
            max[b] = _mm_set1_ps(-kInfinity);
            count[b] = 0;
        }
    }
    void merge(const Bins& o) {
        for (int b = 0; b < kBins; ++b) {
            min[b] = _mm_min_ps(min[b], o.min[b]);
            max[b] = _mm_max_ps(max[b], o.max[b]);
            count[b] += o.count[b];
        }
    }
};

class Builder {
public:
    Builder(LargeArray<BuildRef>& refs, BvhNode* nodes)
        : refs_(refs), scratch_(refs.size()), nodes_(nodes) {}

    uint32_t node_count() const { return node_count_.load(); }  // slots used, holes included
    /// The unused slot ranges [first, last) of serial subtrees, in no particular order.
    const std::vector<std::pair<uint32_t, uint32_t>>& holes() const { return holes_; }
    int depth() const { return depth_.load(); }

    void build_root(const Bounds3& bounds, const Bounds3& centroids) {
        node_count_ = 1;
        depth_ = build(0, 0, static_cast<uint32_t>(refs_.size()), bounds, centroids, 1, nullptr);
        group_.wait();
    }

private:
    /// Node slots reserved for a serial subtree: its descendants never touch the shared
    /// counter (which two threads would otherwise bounce between their caches).
    struct Slots {
        uint32_t next;
    };

    void make_leaf(uint32_t node, uint32_t begin, uint32_t end, const Bounds3& bounds) {
        nodes_[node] = BvhNode{bounds.min, begin, bounds.max, end - begin};
    }

    /// Builds the subtree of refs [begin, end) into `node`; returns its depth.
    int build(uint32_t node, uint32_t begin, uint32_t end, Bounds3 bounds, Bounds3 centroids,
              int depth, Slots* slots) {
        uint32_t n = end - begin;
        if (n <= kMinSplit) {
            make_leaf(node, begin, end, bounds);
            return depth;
        }
        vec3 extent = centroids.extent();
        uint32_t mid = begin;
        Bounds3 lb, rb, lc, rc;
        if (max_component(extent) <= 0.0f) {
            // All centroids coincide: no split can separate them.
            if (n <= kMaxLeaf) {
                make_leaf(node, begin, end, bounds);
                return depth;
            }
            mid = begin + n / 2;
            bounds_of(begin, mid, lb, lc);
            bounds_of(mid, end, rb, rc);
        } else if (depth >= kMedianDepth) {
            int axis = max_dimension(extent);
            mid = begin + n / 2;
            std::nth_element(refs_.begin() + begin, refs_.begin() + mid, refs_.begin() + end,
                             [axis](const BuildRef& a, const BuildRef& b) {
                                 return a.centroid()[axis] < b.centroid()[axis];
                             });
            bounds_of(begin, mid, lb, lc);
            bounds_of(mid, end, rb, rc);
        } else if (!sah_split(begin, end, bounds, centroids, mid, lb, rb, lc, rc)) {
            make_leaf(node, begin, end, bounds);
            return depth;
        }
        Slots local{0};
        if (!slots && n < kParallelGrain) {
            // A subtree of n primitives has at most 2 n - 2 descendants; those it does not use
            // are a hole at the end of its range, recorded for the compaction.
            local.next = node_count_.fetch_add(2 * n - 2);
            uint32_t start = local.next;
            int d = build_split(node, begin, end, mid, bounds, lb, rb, lc, rc, depth, &local);
            std::lock_guard<std::mutex> lock(holes_mutex_);
            holes_.push_back({local.next, start + 2 * n - 2});
            return d;
        }
        return build_split(node, begin, end, mid, bounds, lb, rb, lc, rc, depth, slots);
    }

    /// Makes `node` an inner node over the split at `mid` and builds its two children.
    int build_split(uint32_t node, uint32_t begin, uint32_t end, uint32_t mid,
                    const Bounds3& bounds, const Bounds3& lb, const Bounds3& rb, const Bounds3& lc,
                    const Bounds3& rc, int depth, Slots* slots) {
        uint32_t n = end - begin;
        uint32_t left = slots ? slots->next : node_count_.fetch_add(2);
        if (slots) slots->next += 2;
        nodes_[node] = BvhNode{bounds.min, left, bounds.max, 0};
        if (n >= kParallelGrain) {
            group_.run([=, this] {
                int d = build(left, begin, mid, lb, lc, depth + 1, nullptr);
                int seen = depth_.load();
                while (d > seen && !depth_.compare_exchange_weak(seen, d)) {
                }
            });
            return build(left + 1, mid, end, rb, rc, depth + 1, nullptr);
        }
        int dl = build(left, begin, mid, lb, lc, depth + 1, slots);
        int dr = build(left + 1, mid, end, rb, rc, depth + 1, slots);
        return std::max(dl, dr);
    }

    void bounds_of(uint32_t begin, uint32_t end, Bounds3& bounds, Bounds3& centroids) const {
        bounds = Bounds3{};
        centroids = Bounds3{};
        for (uint32_t k = begin; k < end; ++k) {
            bounds.extend(refs_[k].min);
            bounds.extend(refs_[k].max);
            centroids.extend(refs_[k].centroid());
        }
    }

    /// Adds refs [begin, end) to `out`, through two interleaved sets of bins: consecutive
    /// primitives of a mesh often fall into the same bin, and one set would chain every
    /// update on the previous one.
    template <class BinOf>
    void bin_range(uint32_t begin, uint32_t end, const BinOf& bin_of, Bins& out) const {
        Bins second;
        const BuildRef* refs = refs_.data();
        uint32_t k = begin;
        for (; k + 1 < end; k += 2) {
            // Lane 3 holds the id or padding bits: never read back.
            const BuildRef& r0 = refs[k];
            const BuildRef& r1 = refs[k + 1];
            int b0 = bin_of(r0), b1 = bin_of(r1);
            out.min[b0] = _mm_min_ps(out.min[b0], _mm_loadu_ps(&r0.min.x));
            out.max[b0] = _mm_max_ps(out.max[b0], _mm_loadu_ps(&r0.max.x));
            out.count[b0]++;
            second.min[b1] = _mm_min_ps(second.min[b1], _mm_loadu_ps(&r1.min.x));
            second.max[b1] = _mm_max_ps(second.max[b1], _mm_loadu_ps(&r1.max.x));
            second.count[b1]++;
        }
        if (k < end) {
            int b0 = bin_of(refs[k]);
            out.min[b0] = _mm_min_ps(out.min[b0], _mm_loadu_ps(&refs[k].min.x));
            out.max[b0] = _mm_max_ps(out.max[b0], _mm_loadu_ps(&refs[k].max.x));
            out.count[b0]++;
        }
        out.merge(second);
    }

    /// Bins the centroids along the axis of largest centroid extent, chooses the cheapest of
    /// the kBins - 1 bin boundaries by SAH and partitions refs there. Returns false when a
    /// leaf is cheaper and allowed. Binning one axis (Wald 2007) costs a third of binning
    /// three and loses little quality; the bins' bounds are kept in SSE registers.
    bool sah_split(uint32_t begin, uint32_t end, const Bounds3& bounds, const Bounds3& centroids,
                   uint32_t& mid, Bounds3& lb, Bounds3& rb, Bounds3& lc, Bounds3& rc) {
        uint32_t n = end - begin;
        const BinPosition position(centroids);
        // Centroids past the float range (a generated vertex at inf) give NaN or inf
        // positions: they go to the end bins instead of indexing with an undefined conversion.
        auto bin_of = [position](const BuildRef& r) { return position.bin(r); };
        Bins bins;
        if (n >= kParallelSplit) {
            // The top levels: bins of chunks in parallel, merged (min, max and sums are exact in
            // any order, so the result does not depend on the threads).
            bins = tbb::parallel_reduce(
                tbb::blocked_range<uint32_t>(begin, end, kSplitChunk), Bins{},
                [&](const tbb::blocked_range<uint32_t>& r, Bins acc) {
                    bin_range(r.begin(), r.end(), bin_of, acc);
                    return acc;
                },
                [](Bins x, const Bins& y) {
                    x.merge(y);
                    return x;
                });
        } else {
            bin_range(begin, end, bin_of, bins);
        }
        // Sweep from the right, then from the left: cost of splitting after bin b.
        float right_cost[kBins];
        __m128 acc_min = _mm_set1_ps(kInfinity), acc_max = _mm_set1_ps(-kInfinity);
        auto area = [](__m128 lo, __m128 hi) {
            alignas(16) float e[4];
            _mm_store_ps(e, _mm_sub_ps(hi, lo));
            return e[0] < 0.0f ? 0.0f : 2.0f * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
        };
        uint32_t count = 0;
        for (int b = kBins - 1; b > 0; --b) {
            acc_min = _mm_min_ps(acc_min, bins.min[b]);
            acc_max = _mm_max_ps(acc_max, bins.max[b]);
            count += bins.count[b];
            right_cost[b] = count ? area(acc_min, acc_max) * static_cast<float>(count) : 0.0f;
        }
        float best_cost = kInfinity;
        int best_bin = -1;
        acc_min = _mm_set1_ps(kInfinity);
        acc_max = _mm_set1_ps(-kInfinity);
        count = 0;
        for (int b = 0; b < kBins - 1; ++b) {
            acc_min = _mm_min_ps(acc_min, bins.min[b]);
            acc_max = _mm_max_ps(acc_max, bins.max[b]);
            count += bins.count[b];
            if (count == 0 || count == n) continue;
            float cost = area(acc_min, acc_max) * static_cast<float>(count) + right_cost[b + 1];
            if (cost < best_cost) {
                best_cost = cost;
                best_bin = b;
            }
        }
        float node_area = bounds.surface_area();
        float split_cost = kTraversalCost + (node_area > 0.0f ? best_cost / node_area : kInfinity);
        float leaf_cost = static_cast<float>(n);
        if (best_bin < 0 || (n <= kMaxLeaf && leaf_cost <= split_cost)) {
            if (n <= kMaxLeaf) return false;
            // No useful split but too many for a leaf: split at the median index.
            mid = begin + n / 2;
            bounds_of(begin, mid, lb, lc);
            bounds_of(mid, end, rb, rc);
            return true;
        }
        // bin_of(r) <= best_bin, as one comparison of the same position: a NaN or
        // non-positive one goes to bin 0 (left), and int(f) <= best_bin exactly when
        // f < best_bin + 1.
        const float split_at = static_cast<float>(best_bin + 1);
        auto goes_left = [position, split_at](const BuildRef& r) {
            return !(position(r) >= split_at);
        };
        const BuildRef* refs = refs_.data();
        BuildRef* scratch = scratch_.data();
        if (n >= kParallelSplit) {
            // In parallel and stable: count the left references of each chunk, then every chunk
            // writes its own at known offsets.
            uint32_t chunks = (n + kSplitChunk - 1) / kSplitChunk;
            std::vector<uint32_t> lefts(chunks + 1, 0);
            tbb::parallel_for(0u, chunks, [&](uint32_t c) {
                uint32_t in_left = 0;
                for (uint32_t j = begin + c * kSplitChunk;
                     j < std::min(end, begin + (c + 1) * kSplitChunk); ++j) {
                    in_left += goes_left(refs[j]) ? 1u : 0u;
                }
                lefts[c + 1] = in_left;
            });
            for (uint32_t c = 0; c < chunks; ++c) lefts[c + 1] += lefts[c];
            mid = begin + lefts[chunks];
            tbb::parallel_for(0u, chunks, [&](uint32_t c) {
                uint32_t first = begin + c * kSplitChunk,
                         last = std::min(end, begin + (c + 1) * kSplitChunk);
                uint32_t l = begin + lefts[c], r = mid + (first - begin - lefts[c]);
                for (uint32_t j = first; j < last; ++j) {
                    if (goes_left(refs[j]))
                        scratch[l++] = refs[j];
                    else
                        scratch[r++] = refs[j];
                }
            });
            tbb::parallel_for(0u, chunks, [&](uint32_t c) {
                uint32_t first = begin + c * kSplitChunk,
                         last = std::min(end, begin + (c + 1) * kSplitChunk);
                std::copy(scratch + first, scratch + last, refs_.data() + first);
            });
        } else {
            // Branch-free, through a scratch buffer: each reference is written to the next slot
            // at the left or at the right end (a branch here mispredicts half the time).
            // The slot is chosen with a mask: written as a conditional, the compiler makes it a
            // branch again.
            uint32_t next_left = begin, next_right = end - 1;
            for (uint32_t j = begin; j < end; ++j) {
                uint32_t left = goes_left(refs[j]) ? 1u : 0u;
                uint32_t slot = next_right + ((next_left - next_right) & (0u - left));
                scratch[slot] = refs[j];
                next_left += left;
                next_right -= 1u - left;
            }
            std::copy(scratch + begin, scratch + end, refs_.data() + begin);
            mid = next_left;
        }
        // Children's bounds from the bins; their centroid bounds are approximated by the
        // primitive bounds, which contain every centroid (binning only needs a range).
        __m128 l_min = _mm_set1_ps(kInfinity), l_max = _mm_set1_ps(-kInfinity);
        __m128 r_min = l_min, r_max = l_max;
        for (int b = 0; b < kBins; ++b) {
            if (b <= best_bin) {
                l_min = _mm_min_ps(l_min, bins.min[b]);
                l_max = _mm_max_ps(l_max, bins.max[b]);
            } else {
                r_min = _mm_min_ps(r_min, bins.min[b]);
                r_max = _mm_max_ps(r_max, bins.max[b]);
            }
        }
        auto to_bounds = [](__m128 lo, __m128 hi) {
            alignas(16) float l[4], h[4];
            _mm_store_ps(l, lo);
            _mm_store_ps(h, hi);
            return Bounds3{vec3(l[0], l[1], l[2]), vec3(h[0], h[1], h[2])};
        };
        lb = lc = to_bounds(l_min, l_max);
        rb = rc = to_bounds(r_min, r_max);
        return true;
    }

    LargeArray<BuildRef>& refs_;
    LargeArray<BuildRef> scratch_;  // for partitioning, same indices as refs_
    BvhNode* nodes_;                // room for 2 n - 1 nodes
    std::atomic<uint32_t> node_count_{0};
    std::atomic<int> depth_{0};
    std::mutex holes_mutex_;
    std::vector<std::pair<uint32_t, uint32_t>> holes_;
    tbb::task_group group_;
};

inline float node_entry(const BvhNode& node, vec3 o, vec3 inv_d, float tmax) {
    return box_entry(node.min, node.max, o, inv_d, tmax);
}

}  // namespace

Bvh::Bvh(const Geometry& geometry, int threads) : geometry_(geometry) {
    // Every triangle, then the bounded shapes (infinite planes are tested apart).
    const uint32_t triangles = geometry.triangle_count();
    std::vector<uint32_t> shapes;
    for (uint32_t id : geometry.bounded_primitives_from(triangles)) shapes.push_back(id);
    const size_t n = triangles + shapes.size();
    if (n == 0) return;
    LargeArray<BuildRef> refs(n);
    int workers = resolve_threads(threads);
    tbb::task_arena arena(workers);
    // The references and their bounds, in chunks merged in order.
    size_t chunks = std::min<size_t>(static_cast<size_t>(workers) * 4, (n + 4095) / 4096);
    std::vector<Bounds3> chunk_bounds(chunks), chunk_centroids(chunks);
    arena.execute([&] {
        tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
            Bounds3 b, cb;
            const vec3* p = geometry.positions.data();
            const uint32_t* index = geometry.indices.data();
            for (size_t k = c * n / chunks; k < (c + 1) * n / chunks; ++k) {
                Bounds3 pb;
                uint32_t id;
                if (k < triangles) {  // inline: the common case, 3 vertices
                    id = static_cast<uint32_t>(k);
                    vec3 a = p[index[3 * k]], v1 = p[index[3 * k + 1]], v2 = p[index[3 * k + 2]];
                    pb = Bounds3{glm::min(a, glm::min(v1, v2)), glm::max(a, glm::max(v1, v2))};
                } else {
                    id = shapes[k - triangles];
                    pb = geometry.primitive_bounds(id);
                }
                refs[k] = BuildRef{pb.min, id, pb.max, 0.0f};
                b.extend(pb);
                cb.extend(refs[k].centroid());
            }
            chunk_bounds[c] = b;
            chunk_centroids[c] = cb;
        });
    });
    Bounds3 bounds, centroids;
    for (size_t c = 0; c < chunks; ++c) {
        bounds.extend(chunk_bounds[c]);
        centroids.extend(chunk_centroids[c]);
    }
    // Uninitialised room for the worst case (2 n - 1 nodes): untouched pages cost nothing.
    // About a third of it is written, in runs, so it takes small pages.
    LargeArray<BvhNode> room(2 * refs.size(), false);
    Builder builder(refs, room.data());
    arena.execute([&] { builder.build_root(bounds, centroids); });
    depth_ = builder.depth();
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
    nodes_ = LargeArray<BvhNode>(count);
    auto moved = [&](uint32_t old) {
        size_t k = static_cast<size_t>(std::upper_bound(run_start.begin(), run_start.end(), old) -
                                       run_start.begin()) -
                   1;
        return old - shift[k];
    };
    arena.execute([&] {
        tbb::parallel_for(size_t{0}, run_start.size(), [&](size_t k) {
            uint32_t first = run_start[k];
            uint32_t last = k + 1 < run_start.size() ? holes[k].first : total;
            for (uint32_t i = first; i < last; ++i) {
                BvhNode node = room[i];
                if (node.count == 0) node.first = moved(node.first);
                nodes_[i - shift[k]] = node;
            }
        });
    });
    nodes_.truncate(count);
    prims_ = LargeArray<uint32_t>(refs.size());
    for (size_t k = 0; k < refs.size(); ++k) prims_[k] = refs[k].id;
}

bool Bvh::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    hit.t = ray.tmax;
    if (nodes_.empty()) return false;
    RayPrecomputed pre(ray);
    vec3 inv_d = safe_inverse(ray.d);
    struct Entry {
        uint32_t node;
        float t;
    };
    Entry stack[kStackSize];
    int sp = 0;
    if (node_entry(nodes_[0], ray.o, inv_d, hit.t) == kInfinity) return false;
    stack[sp++] = {0, 0.0f};
    bool found = false;
    while (sp > 0) {
        Entry e = stack[--sp];
        if (e.t > hit.t) continue;  // a closer hit was found since this node was pushed
        const BvhNode* node = &nodes_[e.node];
        while (node->count == 0) {
            const BvhNode& l = nodes_[node->first];
            const BvhNode& r = nodes_[node->first + 1];
            float tl = node_entry(l, ray.o, inv_d, hit.t);
            float tr = node_entry(r, ray.o, inv_d, hit.t);
            if (tl == kInfinity && tr == kInfinity) {
                node = nullptr;
                break;
            }
            if (tl <= tr) {
                if (tr != kInfinity) stack[sp++] = {node->first + 1, tr};
                node = &l;
            } else {
                if (tl != kInfinity) stack[sp++] = {node->first, tl};
                node = &r;
            }
        }
        if (!node) continue;
        found |= geometry_.intersect(prims_.data() + node->first, node->count, ray, pre, hit);
    }
    return found;
}

bool Bvh::occluded(const Ray& ray) const {
    if (nodes_.empty()) return false;
    RayPrecomputed pre(ray);
    vec3 inv_d = safe_inverse(ray.d);
    uint32_t stack[kStackSize];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const BvhNode& node = nodes_[stack[--sp]];
        if (node_entry(node, ray.o, inv_d, ray.tmax) == kInfinity) continue;
        if (node.count == 0) {
            stack[sp++] = node.first + 1;
            stack[sp++] = node.first;
            continue;
        }
        if (geometry_.occludes(prims_.data() + node.first, node.count, ray, pre)) return true;
    }
    return false;
}

}  // namespace svetlo
