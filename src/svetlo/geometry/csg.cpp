#include "svetlo/geometry/csg.h"

#include <algorithm>

#include "svetlo/core/small_vector.h"
#include "svetlo/geometry/ray_box.h"

namespace svetlo {

/// How far apart along a ray two boundaries may lie and still be one surface: a cylinder's
/// cap flush with a box's face is the same plane, but the two t values come from different
/// arithmetic (the cylinder's frame, the box's slabs) and differ by rounding. The tolerance
/// is kCoincident times the magnitude of the point's coordinates (16 to 32 ULPs of them), in
/// units of t: wide enough for the slivers measured (a flush cylinder under rotation, scale
/// and translation), narrow enough that an object 10^4 times smaller than its distance from
/// the origin keeps its shape.
struct CsgShape::Coincidence {
    static constexpr float kCoincident = 1.0f / 524288.0f;
    float origin, direction;  // max |o_k| and max |d_k|, both over |d|

    explicit Coincidence(const Ray& ray) {
        float len = glm::length(ray.d);
        origin = max_component(glm::abs(ray.o)) / len;
        direction = max_component(glm::abs(ray.d)) / len;
    }
    float operator()(float t) const { return kCoincident * (origin + std::abs(t) * direction); }
};

namespace {

using Boundary = CsgShape::Boundary;
using Span = CsgShape::Span;
using Coincidence = CsgShape::Coincidence;
using Spans = SmallVector<Span, 8>;

bool inside(CsgOp op, bool a, bool b) {
    switch (op) {
        case CsgOp::Union:
            return a || b;
        case CsgOp::Intersection:
            return a && b;
        case CsgOp::Difference:
            return a && !b;
    }
    return false;
}

/// Combines two sorted lists of disjoint spans with `op` by sweeping their boundaries in
/// order of t (entries first on ties, A before B). A result span no longer than the
/// coincidence tolerance is a sliver between two coincident surfaces and is dropped; a gap no
/// wider than it between two result spans is closed, so the surfaces inside do not show.
void combine(const Spans& a, const Spans& b, CsgOp op, const Coincidence& tolerance, Spans& out) {
    out.clear();
    size_t i = 0, j = 0;
    bool in_a = false, in_b = false, in_r = false;
    Boundary start{};
    for (;;) {
        bool has_a = i < a.size(), has_b = j < b.size();
        if (!has_a && !has_b) break;
        bool take_a;
        if (!has_b) {
            take_a = true;
        } else if (!has_a) {
            take_a = false;
        } else {
            float ta = in_a ? a[i].out.t : a[i].in.t, tb = in_b ? b[j].out.t : b[j].in.t;
            // Entries first on ties; A before B when both are the same kind.
            take_a = ta != tb ? ta < tb : (!in_a || in_b);
        }
        Boundary e;
        if (take_a) {
            e = in_a ? a[i].out : a[i].in;
            if (in_a) ++i;
            in_a = !in_a;
        } else {
            e = in_b ? b[j].out : b[j].in;
            if (op == CsgOp::Difference) e.flip = !e.flip;  // the cutter's surface faces inward
            if (in_b) ++j;
            in_b = !in_b;
        }
        bool r = inside(op, in_a, in_b);
        if (r == in_r) continue;
        if (r && !out.empty() && e.t - out.back().out.t <= tolerance(e.t)) {
            start = out.back().in;  // a gap between coincident surfaces: reopen the last span
            out.pop_back();
        } else if (r) {
            start = e;
        } else if (e.t - start.t > tolerance(e.t)) {
            out.push_back(Span{start, e});
        }
        in_r = r;
    }
}

bool line_overlaps(const Bounds3& b, const Ray& ray, vec3 inv_d, float tmax) {
    float t0, t1;
    return ray_box(b.min, b.max, ray.o, inv_d, tmax, t0, t1);
}

/// A closed mesh's spans along a ray from its crossings (an exit has flip set, cleared in
/// the spans), those that lie in (0, tmax).
template <class Crossings, class List>
void spans_of_crossings(Crossings& crossings, float tmax, List& out) {
    // Insertion sort: a ray crosses a closed mesh a handful of times.
    for (size_t k = 1; k < crossings.size(); ++k) {
        Boundary b = crossings[k];
        size_t j = k;
        while (j > 0 && crossings[j - 1].t > b.t) {
            crossings[j] = crossings[j - 1];
            --j;
        }
        crossings[j] = b;
    }
    // Nesting depth: entries raise it, exits lower it; the solid is where it is positive. A
    // first crossing that is an exit means the origin is inside.
    int depth = 0;
    for (size_t k = 0; k < crossings.size(); ++k) {
        if (crossings[k].flip) {
            if (depth == 0 && out.empty() && k == 0) {
                depth = 1;
                Boundary open{-kInfinity, CsgShape::kNoLeaf, 0, 0.0f, 0.0f, false};
                out.push_back(Span{open, open});
            }
            if (depth == 0) continue;  // an unmatched exit (open mesh): ignored
            if (--depth == 0) {
                out.back().out = crossings[k];
                out.back().out.flip = false;
            }
        } else {
            if (depth++ == 0) {
                Boundary in = crossings[k];
                out.push_back(Span{in, in});
            }
        }
    }
    if (depth > 0) out.back().out.t = kInfinity;  // an open mesh: the span never closes
    // Keep what lies in (0, tmax).
    Spans kept;
    for (size_t k = 0; k < out.size(); ++k) {
        if (out[k].out.t > 0.0f && out[k].in.t < tmax && out[k].in.t < out[k].out.t)
            kept.push_back(out[k]);
    }
    out = kept;
}

}  // namespace

CsgShape::CsgShape(const Csg& csg, const Transform& transform, uint32_t material) {
    Object root;
    root.shape = csg;
    add(root, transform.matrix, material);
}

uint32_t CsgShape::add(const Object& obj, const mat4& parent, uint32_t inherited) {
    mat4 to_world = parent * obj.transform.matrix;
    uint32_t material = obj.material >= 0 ? static_cast<uint32_t>(obj.material) : inherited;
    auto index = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    if (const auto* csg = std::get_if<Csg>(&obj.shape)) {
        std::vector<uint32_t> children;
        for (const Object& child : csg->children)
            children.push_back(add(child, to_world, material));
        Node& node = nodes_[index];
        node.op = csg->op;
        node.children = std::move(children);
        Bounds3 b;
        if (node.op == CsgOp::Union) {
            for (uint32_t c : node.children) b.extend(nodes_[c].bounds);
        } else if (node.op == CsgOp::Difference) {
            b = nodes_[node.children[0]].bounds;
        } else {
            b = nodes_[node.children[0]].bounds;
            for (uint32_t c : node.children) {
                b.min = glm::max(b.min, nodes_[c].bounds.min);
                b.max = glm::min(b.max, nodes_[c].bounds.max);
            }
        }
        node.bounds = b;
        return index;
    }
    Leaf leaf;
    Transform t;
    t.matrix = to_world;
    t.is_identity = to_world == mat4(1.0f);
    if (const auto* mesh = std::get_if<Mesh>(&obj.shape)) {
        auto g = std::make_unique<Geometry>();
        mat3 nm = normal_matrix(to_world);
        for (vec3 p : mesh->positions) g->positions.push_back(t.point(p));
        for (vec3 n : mesh->normals) g->normals.push_back(glm::normalize(nm * n));
        g->uvs = mesh->uvs;
        g->indices = mesh->indices;
        for (size_t k = 0; k < mesh->triangle_count(); ++k) {
            int m = obj.material >= 0 || mesh->face_material.empty() ? static_cast<int>(material)
                                                                     : mesh->face_material[k];
            g->triangle_material.push_back(static_cast<uint32_t>(m));
        }
        leaf.bvh = std::make_unique<Bvh>(*g, 1);
        leaf.mesh = std::move(g);
    } else {
        leaf.shape = make_analytic_shape(obj.shape, t, material);
    }
    Node& node = nodes_[index];
    node.leaf = static_cast<int>(leaves_.size());
    if (leaf.mesh) {
        for (vec3 p : leaf.mesh->positions) node.bounds.extend(p);
    } else {
        node.bounds = shape_bounds(leaf.shape);
    }
    leaves_.push_back(std::move(leaf));
    return index;
}

template <class List>
void CsgShape::leaf_spans(uint32_t index, const Ray& ray, float tmax, List& out) const {
    out.clear();
    const Leaf& leaf = leaves_[index];
    if (!leaf.mesh) {
        float t0, t1;
        int p0, p1;
        if (shape_interval(leaf.shape, ray, t0, p0, t1, p1) && t1 > 0.0f && t0 < tmax && t0 < t1) {
            out.push_back(
                Span{{t0, index, p0, 0.0f, 0.0f, false}, {t1, index, p1, 0.0f, 0.0f, false}});
        }
        return;
    }
    // Every crossing of the closed mesh past the origin, sorted along the ray; a crossing is an
    // entry where the ray meets the triangle's front (outside) and an exit at its back.
    SmallVector<Boundary, 16> crossings;
    const Geometry& g = *leaf.mesh;
    RayPrecomputed pre(ray);
    vec3 inv_d = safe_inverse(ray.d);
    std::span<const BvhNode> nodes = leaf.bvh->nodes();
    std::span<const uint32_t> prims = leaf.bvh->primitives();
    uint32_t stack[128];
    int sp = 0;
    if (!nodes.empty()) stack[sp++] = 0;
    while (sp > 0) {
        const BvhNode& n = nodes[stack[--sp]];
        float t0, t1;
        if (!ray_box(n.min, n.max, ray.o, inv_d, kInfinity, t0, t1)) continue;
        if (n.count == 0) {
            stack[sp++] = n.first;
            stack[sp++] = n.first + 1;
            continue;
        }
        for (uint32_t k = n.first; k < n.first + n.count; ++k) {
            Hit h;
            h.t = kInfinity;
            if (!g.intersect(prims[k], ray, pre, h)) continue;
            const uint32_t* tri = &g.indices[3 * size_t{h.prim}];
            vec3 ng = glm::cross(g.positions[tri[1]] - g.positions[tri[0]],
                                 g.positions[tri[2]] - g.positions[tri[0]]);
            bool entry = glm::dot(ng, ray.d) < 0.0f;
            // flip marks exits here, only to sort them; it is cleared below.
            crossings.push_back(Boundary{h.t, index, static_cast<int>(h.prim), h.u, h.v, !entry});
        }
    }
    spans_of_crossings(crossings, tmax, out);
}

template <class List>
void CsgShape::spans(uint32_t index, const Ray& ray, vec3 inv_d, const Coincidence& tolerance,
                     float tmax, List& out) const {
    out.clear();
    const Node& node = nodes_[index];
    if (!line_overlaps(node.bounds, ray, inv_d, tmax)) return;
    if (node.leaf >= 0) return leaf_spans(static_cast<uint32_t>(node.leaf), ray, tmax, out);
    spans(node.children[0], ray, inv_d, tolerance, tmax, out);
    Spans child, merged;
    for (size_t k = 1; k < node.children.size(); ++k) {
        if (out.empty() && node.op != CsgOp::Union) return;  // nothing left to intersect or cut
        spans(node.children[k], ray, inv_d, tolerance, tmax, child);
        if (child.empty() && node.op != CsgOp::Intersection) continue;
        combine(out, child, node.op, tolerance, merged);
        out = merged;
    }
}

bool CsgShape::intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
    if (nodes_.empty()) return false;
    Spans list;
    spans(0, ray, safe_inverse(ray.d), Coincidence(ray), tmax, list);
    for (size_t k = 0; k < list.size(); ++k) {
        for (const Boundary* b : {&list[k].in, &list[k].out}) {
            if (b->t > 0.0f && b->t < tmax && b->leaf != kNoLeaf) {
                hit.t = b->t;
                hit.part = b->part;
                hit.sub = b->leaf | (b->flip ? 1u << 31 : 0u);
                hit.u = b->u;
                hit.v = b->v;
                return true;
            }
        }
    }
    return false;
}

bool CsgShape::contains(vec3 p) const {
    if (nodes_.empty()) return false;
    // A ray in a direction no axis-aligned face is parallel to; inside when a span holds t = 0.
    Ray ray{p, glm::normalize(vec3(0.5773f, 0.5871f, 0.5675f)), kInfinity};
    Spans list;
    spans(0, ray, safe_inverse(ray.d), Coincidence(ray), kInfinity, list);
    return !list.empty() && list[0].in.t <= 0.0f && list[0].out.t > 0.0f;
}

ShapeSurface CsgShape::surface(const Ray& ray, const ShapeHit& hit) const {
    const Leaf& leaf = leaves_[hit.sub & ~(1u << 31)];
    bool flip = (hit.sub >> 31) != 0;
    ShapeSurface s;
    if (leaf.mesh) {
        Hit h;
        h.t = hit.t;
        h.prim = static_cast<uint32_t>(hit.part);
        h.u = hit.u;
        h.v = hit.v;
        SurfaceHit m = leaf.mesh->surface(ray, h);
        s.p = m.p;
        s.n = m.ng;
        s.ns = m.ns;
        s.uv = m.uv;
        s.material = m.material;
    } else {
        ShapeHit h;
        h.t = hit.t;
        h.part = hit.part;
        s = shape_surface(leaf.shape, ray, h);
    }
    if (flip) {
        s.n = -s.n;
        s.ns = -s.ns;
    }
    return s;
}

}  // namespace svetlo
