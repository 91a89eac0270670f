#include "svetlo/geometry/wide_bvh.h"

#include <immintrin.h>

#include <algorithm>
#include <stdexcept>

#include "svetlo/geometry/bvh.h"
#include "svetlo/geometry/ray_box.h"
#include "svetlo/geometry/triangle.h"

namespace svetlo {

namespace {

#include "svetlo/geometry/wide_bvh_traversal.inc"

/// The watertight test (triangle.h) on four triangles at once, the same operations in the
/// same order. Returns the lanes that hit with 0 < t < tmax (t, u, v, w and det per lane),
/// and in `edge` the lanes where an edge function is exactly zero, which the caller decides
/// with the scalar test and its double-precision fallback.
struct PacketHits {
    alignas(16) float t[4];
    alignas(16) float uvw[3][4];
    alignas(16) float det[4];
};

struct PacketTest {
    __m128 o[3], s[3];  // ray origin and shear (sx, sy, sz), by permuted axis kx, ky, kz
    int k[3];

    PacketTest(const Ray& ray, const RayPrecomputed& pre) {
        k[0] = pre.kx;
        k[1] = pre.ky;
        k[2] = pre.kz;
        for (int a = 0; a < 3; ++a) o[a] = _mm_set1_ps(ray.o[k[a]]);
        s[0] = _mm_set1_ps(pre.sx);
        s[1] = _mm_set1_ps(pre.sy);
        s[2] = _mm_set1_ps(pre.sz);
    }

    int run(const TrianglePacket& p, float tmax, PacketHits& out, int& edge) const {
        __m128 ex[3], ey[3], ez[3];  // per vertex: sheared x, y and the z to scale
        for (int j = 0; j < 3; ++j) {
            __m128 dx = _mm_sub_ps(_mm_load_ps(p.v[3 * j + k[0]]), o[0]);
            __m128 dy = _mm_sub_ps(_mm_load_ps(p.v[3 * j + k[1]]), o[1]);
            __m128 dz = _mm_sub_ps(_mm_load_ps(p.v[3 * j + k[2]]), o[2]);
            ex[j] = _mm_sub_ps(dx, _mm_mul_ps(s[0], dz));
            ey[j] = _mm_sub_ps(dy, _mm_mul_ps(s[1], dz));
            ez[j] = dz;
        }
        // u = cx by - cy bx, v = ax cy - ay cx, w = bx ay - by ax
        __m128 u = _mm_sub_ps(_mm_mul_ps(ex[2], ey[1]), _mm_mul_ps(ey[2], ex[1]));
        __m128 v = _mm_sub_ps(_mm_mul_ps(ex[0], ey[2]), _mm_mul_ps(ey[0], ex[2]));
        __m128 w = _mm_sub_ps(_mm_mul_ps(ex[1], ey[0]), _mm_mul_ps(ey[1], ex[0]));
        __m128 zero = _mm_setzero_ps();
        int valid =
            ~_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(
                _mm_load_si128(reinterpret_cast<const __m128i*>(p.id)), _mm_set1_epi32(-1)))) &
            15;
        __m128 on_edge = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(u, zero), _mm_cmpeq_ps(v, zero)),
                                   _mm_cmpeq_ps(w, zero));
        edge = _mm_movemask_ps(on_edge) & valid;
        __m128 neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(v, zero)),
                               _mm_cmplt_ps(w, zero));
        __m128 pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(v, zero)),
                               _mm_cmpgt_ps(w, zero));
        int inside = ~_mm_movemask_ps(_mm_and_ps(neg, pos)) & valid & ~edge;
        if (!inside) return 0;
        __m128 det = _mm_add_ps(_mm_add_ps(u, v), w);
        __m128 az = _mm_mul_ps(s[2], ez[0]), bz = _mm_mul_ps(s[2], ez[1]),
               cz = _mm_mul_ps(s[2], ez[2]);
        __m128 num =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(u, az), _mm_mul_ps(v, bz)), _mm_mul_ps(w, cz));
        __m128 tt = _mm_div_ps(num, det);
        __m128 ok =
            _mm_and_ps(_mm_cmpneq_ps(det, zero),
                       _mm_and_ps(_mm_cmpgt_ps(tt, zero), _mm_cmplt_ps(tt, _mm_set1_ps(tmax))));
        int hits = _mm_movemask_ps(ok) & inside;
        if (!hits) return 0;
        _mm_store_ps(out.t, tt);
        _mm_store_ps(out.uvw[0], u);
        _mm_store_ps(out.uvw[1], v);
        _mm_store_ps(out.uvw[2], w);
        _mm_store_ps(out.det, det);
        return hits;
    }
};

/// Lane `lane` of a packet as a triangle, for the scalar test.
inline bool packet_lane_hit(const TrianglePacket& p, int lane, const Ray& ray,
                            const RayPrecomputed& pre, float tmax, float& t, float& b1, float& b2) {
    vec3 v0(p.v[0][lane], p.v[1][lane], p.v[2][lane]), v1(p.v[3][lane], p.v[4][lane], p.v[5][lane]),
        v2(p.v[6][lane], p.v[7][lane], p.v[8][lane]);
    return intersect_triangle(ray, pre, v0, v1, v2, tmax, t, b1, b2);
}

/// The closest hit among `count` packets; updates hit (t, prim, u, v) as a sequential loop
/// over the triangles would, ties to the first.
inline bool packets_closest(const PacketTest& test, const TrianglePacket* packets, uint32_t count,
                            const Ray& ray, const RayPrecomputed& pre, Hit& hit) {
    bool found = false;
    for (uint32_t k = 0; k < count; ++k) {
        const TrianglePacket& p = packets[k];
        PacketHits h;
        int edge = 0;
        int hits = test.run(p, hit.t, h, edge);
        for (int mask = hits | edge; mask; mask &= mask - 1) {
            int lane = __builtin_ctz(static_cast<unsigned>(mask));
            if ((edge >> lane) & 1) {
                float tt, b1, b2;
                if (!packet_lane_hit(p, lane, ray, pre, hit.t, tt, b1, b2)) continue;
                hit.t = tt;
                hit.u = b1;
                hit.v = b2;
            } else if (h.t[lane] < hit.t) {
                hit.t = h.t[lane];
                hit.u = h.uvw[1][lane] / h.det[lane];
                hit.v = h.uvw[2][lane] / h.det[lane];
            } else {
                continue;
            }
            hit.prim = p.id[lane];
            hit.part = 0;
            hit.sub = 0;
            found = true;
        }
    }
    return found;
}

/// Whether any of `count` packets is hit before ray.tmax.
inline bool packets_any(const PacketTest& test, const TrianglePacket* packets, uint32_t count,
                        const Ray& ray, const RayPrecomputed& pre) {
    for (uint32_t k = 0; k < count; ++k) {
        const TrianglePacket& p = packets[k];
        PacketHits h;
        int edge = 0;
        if (test.run(p, ray.tmax, h, edge)) return true;
        for (; edge; edge &= edge - 1) {
            float tt, b1, b2;
            if (packet_lane_hit(p, __builtin_ctz(static_cast<unsigned>(edge)), ray, pre, ray.tmax,
                                tt, b1, b2))
                return true;
        }
    }
    return false;
}

float half_area(const BvhNode& n) {
    vec3 e = n.max - n.min;
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

/// A ray against the four boxes of a node (SSE): returns the mask of children hit and their
/// entry distances.
struct RayBoxes4 {
    static constexpr int kWidth = 4;
    __m128 o[3], inv[3];
    int near[3], far[3];  // box rows of the near and far planes per axis

    explicit RayBoxes4(const Ray& ray) {
        vec3 inv_d = safe_inverse(ray.d);
        for (int a = 0; a < 3; ++a) {
            o[a] = _mm_set1_ps(ray.o[a]);
            inv[a] = _mm_set1_ps(inv_d[a]);
            near[a] = inv_d[a] >= 0.0f ? a : a + 3;
            far[a] = inv_d[a] >= 0.0f ? a + 3 : a;
        }
    }

    int test(const WideBvhNode<4>& n, float tmax, float* t_enter) const {
        __m128 tn0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[0]]), o[0]), inv[0]);
        __m128 tn1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[1]]), o[1]), inv[1]);
        __m128 tn2 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[2]]), o[2]), inv[2]);
        __m128 tf0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[0]]), o[0]), inv[0]);
        __m128 tf1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[1]]), o[1]), inv[1]);
        __m128 tf2 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[2]]), o[2]), inv[2]);
        __m128 enter = _mm_max_ps(_mm_max_ps(tn0, tn1), _mm_max_ps(tn2, _mm_setzero_ps()));
        __m128 exit = _mm_min_ps(_mm_min_ps(tf0, tf1), _mm_min_ps(tf2, _mm_set1_ps(tmax)));
        exit = _mm_mul_ps(exit, _mm_set1_ps(kSlabRobust));
        _mm_store_ps(t_enter, enter);
        return _mm_movemask_ps(_mm_cmple_ps(enter, exit));
    }
};

}  // namespace

bool WideBvh::eight_wide_available() {
#ifdef SVETLO_HAS_AVX2_BVH
    return __builtin_cpu_supports("avx2") != 0;
#else
    return false;
#endif
}

WideBvh::WideBvh(const Geometry& geometry, int threads, int width) : geometry_(geometry) {
    width_ = (width == 0 || width == 8) && eight_wide_available() ? 8 : 4;
    Bvh bin(geometry, threads);
    if (bin.nodes().empty()) return;
    empty_ = false;
    // Exact room: every binary leaf becomes one wide leaf, with a packet per four triangles;
    // wide nodes are fewer than binary inner nodes.
    size_t inner = 0, leaves = 0, packets = 0, shapes = 0;
    for (const BvhNode& n : bin.nodes()) {
        if (n.count == 0) {
            ++inner;
            continue;
        }
        ++leaves;
        size_t triangles = 0;
        for (uint32_t k = n.first; k < n.first + n.count; ++k)
            triangles += geometry.is_triangle(bin.primitives()[k]);
        packets += (triangles + 3) / 4;
        shapes += n.count - triangles;
    }
    if (leaves >= kLeaf) throw std::runtime_error("the wide BVH holds at most 2^31 leaves");
    leaves_ = LargeArray<Leaf>(leaves);
    packets_ = LargeArray<TrianglePacket>(packets);
    shapes_ = LargeArray<uint32_t>(shapes);
    if (width_ == 8) {
        build<8>(bin, nodes8_, inner);
    } else {
        build<4>(bin, nodes4_, inner);
    }
}

template <int W>
void WideBvh::build(const Bvh& bin, LargeArray<WideBvhNode<W>>& nodes, size_t inner) {
    nodes = LargeArray<WideBvhNode<W>>(std::max<size_t>(inner, 1));
    const BvhNode& root = bin.nodes()[0];
    node_count_ = 1;
    if (root.count > 0) {
        // A single leaf: one wide node with one child.
        WideBvhNode<W> node;
        for (int k = 0; k < W; ++k) {
            for (int a = 0; a < 3; ++a) {
                node.box[a][k] = k == 0 ? root.min[a] : kInfinity;
                node.box[a + 3][k] = k == 0 ? root.max[a] : -kInfinity;
            }
            node.child[k] = kEmpty;
        }
        node.child[0] = add_leaf(bin.primitives().subspan(root.first, root.count));
        nodes[0] = node;
    } else {
        collapse<W>(bin.nodes(), bin.primitives(), 0, 0, nodes);
    }
    nodes.truncate(node_count_);
}

uint32_t WideBvh::add_leaf(std::span<const uint32_t> prims) {
    Leaf leaf{static_cast<uint32_t>(packet_count_), 0, static_cast<uint32_t>(shape_count_), 0};
    int lane = 4;
    TrianglePacket* p = nullptr;
    for (uint32_t id : prims) {
        if (!geometry_.is_triangle(id)) {
            shapes_[shape_count_++] = id;
            ++leaf.shapes;
            continue;
        }
        if (lane == 4) {
            p = &packets_[packet_count_++];
            for (auto& row : p->v) std::fill(row, row + 4, 0.0f);
            std::fill(p->id, p->id + 4, ~0u);
            lane = 0;
            ++leaf.packets;
        }
        for (int j = 0; j < 3; ++j) {
            vec3 q = geometry_.positions[geometry_.indices[3 * size_t{id} + j]];
            for (int c = 0; c < 3; ++c) p->v[3 * j + c][lane] = q[c];
        }
        p->id[lane++] = id;
    }
    leaves_[leaf_count_] = leaf;
    return kLeaf | static_cast<uint32_t>(leaf_count_++);
}

/// Collapses the binary tree under `b` into wide node `w`: the largest inner child is opened
/// until W children are gathered (or only leaves remain).
template <int W>
void WideBvh::collapse(std::span<const BvhNode> bin, std::span<const uint32_t> prims, uint32_t b,
                       uint32_t w, LargeArray<WideBvhNode<W>>& nodes) {
    uint32_t kids[W] = {bin[b].first, bin[b].first + 1};
    int n = 2;
    while (n < W) {
        int best = -1;
        float best_area = -1.0f;
        for (int k = 0; k < n; ++k) {
            if (bin[kids[k]].count == 0 && half_area(bin[kids[k]]) > best_area) {
                best = k;
                best_area = half_area(bin[kids[k]]);
            }
        }
        if (best < 0) break;
        uint32_t open = kids[best];
        kids[best] = bin[open].first;
        kids[n++] = bin[open].first + 1;
    }
    WideBvhNode<W> node;
    for (int k = 0; k < W; ++k) {
        for (int a = 0; a < 3; ++a) {
            node.box[a][k] = k < n ? bin[kids[k]].min[a] : kInfinity;
            node.box[a + 3][k] = k < n ? bin[kids[k]].max[a] : -kInfinity;
        }
        node.child[k] = kEmpty;
    }
    for (int k = 0; k < n; ++k) {
        const BvhNode& c = bin[kids[k]];
        if (c.count > 0) {
            node.child[k] = add_leaf(prims.subspan(c.first, c.count));
        } else {
            auto index = static_cast<uint32_t>(node_count_++);
            node.child[k] = index;
            collapse<W>(bin, prims, kids[k], index, nodes);
        }
    }
    nodes[w] = node;
}

bool WideBvh::leaf_intersect(uint32_t index, const Ray& ray, const RayPrecomputed& pre,
                             Hit& hit) const {
    const Leaf& leaf = leaves_[index];
    bool found = packets_closest(PacketTest(ray, pre), packets_.data() + leaf.first_packet,
                                 leaf.packets, ray, pre, hit);
    if (leaf.shapes == 0) return found;
    return geometry_.intersect(shapes_.data() + leaf.first_shape, leaf.shapes, ray, pre, hit) ||
           found;
}

bool WideBvh::leaf_occluded(uint32_t index, const Ray& ray, const RayPrecomputed& pre) const {
    const Leaf& leaf = leaves_[index];
    return packets_any(PacketTest(ray, pre), packets_.data() + leaf.first_packet, leaf.packets, ray,
                       pre) ||
           (leaf.shapes > 0 &&
            geometry_.occludes(shapes_.data() + leaf.first_shape, leaf.shapes, ray, pre));
}

bool WideBvh::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    hit.t = ray.tmax;
    if (empty_) return false;
    if (width_ == 8) return intersect8(ray, hit);
    RayPrecomputed pre(ray);
    return traverse_closest<RayBoxes4>(nodes4_.data(), ray, hit, [&](uint32_t leaf) {
        return leaf_intersect(leaf, ray, pre, hit);
    });
}

bool WideBvh::occluded(const Ray& ray) const {
    if (empty_) return false;
    if (width_ == 8) return occluded8(ray);
    RayPrecomputed pre(ray);
    return traverse_any<RayBoxes4>(nodes4_.data(), ray,
                                   [&](uint32_t leaf) { return leaf_occluded(leaf, ray, pre); });
}

#ifndef SVETLO_HAS_AVX2_BVH
// Never called: width_ is 8 only where eight_wide_available().
bool WideBvh::intersect8(const Ray&, Hit&) const { return false; }
bool WideBvh::occluded8(const Ray&) const { return false; }
#endif

}  // namespace svetlo
