#include "svetlo/geometry/tessellate.h"

#include <algorithm>

#include "svetlo/geometry/csg.h"
#include "svetlo/geometry/sdf.h"
#include "svetlo/scene/instances.h"

namespace svetlo {

namespace {

/// Appends a vertex; returns its index.
uint32_t vertex(Mesh& m, vec3 p, vec3 n, vec2 uv) {
    m.positions.push_back(p);
    m.normals.push_back(n);
    m.uvs.push_back(uv);
    return static_cast<uint32_t>(m.positions.size() - 1);
}

void triangle(Mesh& m, uint32_t a, uint32_t b, uint32_t c) {
    m.indices.insert(m.indices.end(), {a, b, c});
}

/// A grid of (nu + 1) x (nv + 1) vertices from `f(u, v)` -> (p, n) over [0,1]^2, as quads
/// split in two, wound so that (dp/du x dp/dv) faces out when `flip` is false.
template <class F>
void parametric(Mesh& m, int nu, int nv, bool flip, F&& f) {
    auto base = static_cast<uint32_t>(m.positions.size());
    for (int j = 0; j <= nv; ++j) {
        for (int i = 0; i <= nu; ++i) {
            vec2 uv(static_cast<float>(i) / nu, static_cast<float>(j) / nv);
            vec3 p, n;
            f(uv, p, n);
            vertex(m, p, n, uv);
        }
    }
    auto at = [&](int i, int j) { return base + static_cast<uint32_t>(j * (nu + 1) + i); };
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            if (flip) {
                triangle(m, a, c, b);
                triangle(m, a, d, c);
            } else {
                triangle(m, a, b, c);
                triangle(m, a, c, d);
            }
        }
    }
}

void sphere(Mesh& m, const Sphere& s, const TessellationOptions& o) {
    // u: longitude from +z toward +x, v: latitude from the south pole (shapes.cpp).
    parametric(m, o.segments, o.rings, false, [&](vec2 uv, vec3& p, vec3& n) {
        // The seam's two columns and each pole's row share their positions bit for bit.
        float u = uv.x == 1.0f ? 0.0f : uv.x;
        float phi = 2.0f * kPi * (u - 0.5f), theta = kPi * (uv.y - 0.5f);
        float c = uv.y == 0.0f || uv.y == 1.0f ? 0.0f : std::cos(theta);
        float y = uv.y == 0.0f ? -1.0f : uv.y == 1.0f ? 1.0f : std::sin(theta);
        n = vec3(c * std::sin(phi), y, c * std::cos(phi));
        p = s.center + s.radius * n;
    });
}

void quad(Mesh& m, vec3 corner, vec3 eu, vec3 ev, int nu = 1, int nv = 1) {
    vec3 n = glm::normalize(glm::cross(eu, ev));
    parametric(m, nu, nv, false, [&](vec2 uv, vec3& p, vec3& nn) {
        p = corner + uv.x * eu + uv.y * ev;
        nn = n;
    });
}

void box(Mesh& m, const Box& b) {
    vec3 e = b.max - b.min;
    // Per axis, the min face (normal -axis) and the max face, with uv along the next two axes
    // as shapes.cpp maps them.
    for (int axis = 0; axis < 3; ++axis) {
        int a = (axis + 1) % 3, c = (axis + 2) % 3;
        vec3 eu(0.0f), ev(0.0f);
        eu[a] = e[a];
        ev[c] = e[c];
        vec3 lo = b.min, hi = b.min;
        hi[axis] = b.max[axis];
        quad(m, hi, eu, ev);  // eu x ev points along +axis: the max face
        auto base = static_cast<uint32_t>(m.positions.size());
        quad(m, lo, eu, ev);
        for (uint32_t k = base; k < m.positions.size(); ++k) m.normals[k] = -m.normals[k];
        // Reverse the winding of the min face.
        for (size_t k = m.indices.size() - 6; k < m.indices.size(); k += 3)
            std::swap(m.indices[k + 1], m.indices[k + 2]);
    }
}

/// Cylinder (cone = false) or cone: the lateral surface and the caps, in the axis frame.
void quadric(Mesh& m, vec3 base, vec3 axis, float r, bool cone, const TessellationOptions& o) {
    float h = glm::length(axis);
    Frame f = Frame::from_normal(axis / h);
    float k = cone ? r / h : 0.0f;  // slope of the normal along the axis for a cone
    auto lateral = [&](vec2 uv, vec3& p, vec3& n) {
        float phi = 2.0f * kPi * (uv.x == 1.0f ? 0.0f : uv.x);
        float z = h * uv.y;
        float rad = cone ? r * (1.0f - uv.y) : r;
        vec3 dir = f.to_world(vec3(std::cos(phi), std::sin(phi), 0.0f));
        p = base + rad * dir + z * f.n;
        n = glm::normalize(dir + k * f.n);
    };
    parametric(m, o.segments, cone ? o.segments / 2 : 1, false, lateral);
    // Caps: fans around the centre, facing -axis (base) and +axis (top, cylinder only). Their
    // rims are the lateral surface's first and last rows, bit for bit: the solid is closed.
    for (int cap = 0; cap < (cone ? 1 : 2); ++cap) {
        vec3 c = cap == 0 ? base : base + axis;
        vec3 n = cap == 0 ? -f.n : f.n;
        uint32_t centre = vertex(m, c, n, vec2(0.5f));
        auto first = static_cast<uint32_t>(m.positions.size());
        for (int i = 0; i <= o.segments; ++i) {
            float phi = 2.0f * kPi * static_cast<float>(i % o.segments) / o.segments;
            vec2 q(std::cos(phi), std::sin(phi));
            vec3 p, unused;
            lateral(vec2(static_cast<float>(i) / o.segments, cap == 0 ? 0.0f : 1.0f), p, unused);
            vertex(m, p, n, vec2(0.5f) + 0.5f * q);
        }
        for (int i = 0; i < o.segments; ++i) {
            uint32_t a = first + static_cast<uint32_t>(i), b = a + 1;
            if (cap == 0)
                triangle(m, centre, b, a);
            else
                triangle(m, centre, a, b);
        }
    }
}

/// The grid of surface nets: cubic cells of side `cell` from `min`, n[a] cells along axis a;
/// corners and cells indexed x fastest.
struct NetGrid {
    vec3 min;
    float cell;
    int n[3];

    vec3 corner(int i, int j, int k) const { return min + cell * vec3(i, j, k); }
    size_t corner_index(int i, int j, int k) const {
        return (static_cast<size_t>(k) * (n[1] + 1) + j) * (n[0] + 1) + i;
    }
    size_t cell_index(int i, int j, int k) const {
        return (static_cast<size_t>(k) * n[1] + j) * n[0] + i;
    }
    size_t corner_count() const { return (n[0] + 1) * static_cast<size_t>(n[1] + 1) * (n[2] + 1); }
    size_t cell_count() const { return static_cast<size_t>(n[0]) * n[1] * n[2]; }
};

/// Surface nets' first step: one vertex in each cell that the surface crosses (every cell
/// around a crossed edge is), at the mean of its edges' crossings, then `project`ed;
/// cell_vertex[cell] is its index (~0u: none) and vertex_material its material.
template <class Crossing, class Project>
void place_cell_vertices(Mesh& m, const NetGrid& g, const std::vector<char>& in,
                         Crossing&& crossing, Project&& project, std::vector<uint32_t>& cell_vertex,
                         std::vector<int>& vertex_material) {
    static constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                          {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (int k = 0; k < g.n[2]; ++k) {
        for (int j = 0; j < g.n[1]; ++j) {
            for (int i = 0; i < g.n[0]; ++i) {
                bool c[8];
                int count = 0;
                for (int v = 0; v < 8; ++v) {
                    c[v] =
                        in[g.corner_index(i + (v & 1), j + ((v >> 1) & 1), k + ((v >> 2) & 1))] !=
                        0;
                    count += c[v];
                }
                if (count == 0 || count == 8) continue;
                vec3 sum(0.0f), nsum(0.0f);
                int crossings = 0, material = 0;
                for (const auto& e : kEdges) {
                    if (c[e[0]] == c[e[1]]) continue;
                    int from = c[e[0]] ? e[0] : e[1], to = c[e[0]] ? e[1] : e[0];
                    vec3 ca =
                        g.corner(i + (from & 1), j + ((from >> 1) & 1), k + ((from >> 2) & 1));
                    vec3 cb = g.corner(i + (to & 1), j + ((to >> 1) & 1), k + ((to >> 2) & 1));
                    vec3 p, nn;
                    crossing(ca, cb, p, nn, material);
                    sum += p;
                    nsum += nn;
                    ++crossings;
                }
                vec3 p = sum / static_cast<float>(crossings);
                vec3 nn = glm::length(nsum) > 0.0f ? glm::normalize(nsum) : vec3(0, 1, 0);
                project(p, nn);
                cell_vertex[g.cell_index(i, j, k)] = vertex(m, p, nn, vec2(0.0f));
                vertex_material.push_back(material);
            }
        }
    }
}

/// Surface nets' second step: one quad per crossed grid edge, joining the four cells around
/// it; wound so that its normal points from the inside corner to the outside one. Edges on
/// the grid's border have fewer than four cells, but the margin keeps the surface away from
/// them. `base` is the index of the first cell vertex.
void join_cell_vertices(Mesh& m, const NetGrid& g, const std::vector<char>& in,
                        const std::vector<uint32_t>& cell_vertex,
                        const std::vector<int>& vertex_material, uint32_t base) {
    const int* n = g.n;
    for (int axis = 0; axis < 3; ++axis) {
        int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        int p[3];
        for (p[2] = 0; p[2] <= n[2]; ++p[2]) {
            for (p[1] = 0; p[1] <= n[1]; ++p[1]) {
                for (p[0] = 0; p[0] <= n[0]; ++p[0]) {
                    if (p[axis] >= n[axis] || p[a1] < 1 || p[a1] >= n[a1] || p[a2] < 1 ||
                        p[a2] >= n[a2])
                        continue;
                    int q[3] = {p[0], p[1], p[2]};
                    q[axis] += 1;
                    bool s0 = in[g.corner_index(p[0], p[1], p[2])] != 0;
                    bool s1 = in[g.corner_index(q[0], q[1], q[2])] != 0;
                    if (s0 == s1) continue;
                    // The cells at offsets (-1,-1), (0,-1), (0,0), (-1,0) along (a1, a2): a loop
                    // turning about +axis, since (a1, a2, axis) is right-handed.
                    static constexpr int kOff[4][2] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
                    uint32_t v[4];
                    for (int c = 0; c < 4; ++c) {
                        int r[3] = {p[0], p[1], p[2]};
                        r[a1] += kOff[c][0];
                        r[a2] += kOff[c][1];
                        v[c] = cell_vertex[g.cell_index(r[0], r[1], r[2])];
                    }
                    int material = vertex_material[v[0] - base];
                    if (s0) {  // inside at the low end: outward is +axis
                        triangle(m, v[0], v[1], v[2]);
                        triangle(m, v[0], v[2], v[3]);
                    } else {
                        triangle(m, v[0], v[2], v[1]);
                        triangle(m, v[0], v[3], v[2]);
                    }
                    m.face_material.push_back(material);
                    m.face_material.push_back(material);
                }
            }
        }
    }
}

/// Surface nets over a grid covering `bounds`: `inside(p)` classifies the corners,
/// `crossing(a, b, p, n, material)` finds where the segment from an inside corner to an
/// outside one meets the surface, and `project(p, n)` may move a cell's vertex onto the
/// surface (implicit surfaces) or leave it at the mean of its crossings (CSG).
template <class Inside, class Crossing, class Project>
void surface_nets(Mesh& m, Bounds3 bounds, int grid, Inside&& inside, Crossing&& crossing,
                  Project&& project) {
    vec3 extent = bounds.extent();
    float cell = max_component(extent) / static_cast<float>(grid);
    if (!(cell > 0.0f)) return;
    // One cell of margin on each side, so the surface never touches the grid's border.
    NetGrid g{bounds.min - vec3(cell), cell, {}};
    for (int a = 0; a < 3; ++a)
        g.n[a] = std::max(1, static_cast<int>(std::ceil(extent[a] / cell)) + 2);
    std::vector<char> in(g.corner_count());
    for (int k = 0; k <= g.n[2]; ++k)
        for (int j = 0; j <= g.n[1]; ++j)
            for (int i = 0; i <= g.n[0]; ++i)
                in[g.corner_index(i, j, k)] = inside(g.corner(i, j, k)) ? 1 : 0;
    auto base = static_cast<uint32_t>(m.positions.size());
    std::vector<uint32_t> cell_vertex(g.cell_count(), ~0u);
    std::vector<int> vertex_material;
    place_cell_vertices(m, g, in, crossing, project, cell_vertex, vertex_material);
    join_cell_vertices(m, g, in, cell_vertex, vertex_material, base);
}

void transform_mesh(Mesh& m, size_t first_vertex, const Transform& t) {
    if (t.is_identity) return;
    mat3 nm = normal_matrix(t.matrix);
    bool mirror = glm::determinant(mat3(t.matrix)) < 0.0f;
    for (size_t k = first_vertex; k < m.positions.size(); ++k) {
        m.positions[k] = t.point(m.positions[k]);
        if (k < m.normals.size() && glm::length(m.normals[k]) > 0.0f)
            m.normals[k] = glm::normalize(nm * m.normals[k]);
    }
    // A mirroring transform reverses the winding; keep counter-clockwise from outside.
    if (mirror) {
        for (size_t k = 0; k + 2 < m.indices.size(); k += 3)
            std::swap(m.indices[k + 1], m.indices[k + 2]);
    }
}

/// A CSG or implicit surface polygonised by surface nets, in world space (transforms are
/// inside the shape), with face materials.
Mesh polygonise(const Object& obj, const TessellationOptions& o) {
    Mesh m;
    m.smooth = true;
    AnalyticShape shape = make_analytic_shape(obj.shape, obj.transform,
                                              static_cast<uint32_t>(std::max(obj.material, 0)));
    Bounds3 bounds = shape_bounds(shape);
    if (!std::isfinite(bounds.min.x + bounds.min.y + bounds.min.z + bounds.max.x + bounds.max.y +
                       bounds.max.z)) {
        // An unbounded implicit surface (a plane in it): polygonise a cube about the origin.
        bounds = Bounds3{vec3(-o.plane_extent), vec3(o.plane_extent)};
    }
    if (shape.kind == ShapeKind::Implicit) {
        const SdfShape& sdf = *shape.sdf;
        surface_nets(
            m, bounds, o.grid, [&](vec3 p) { return sdf.eval(p) < 0.0f; },
            [&](vec3 in, vec3 out, vec3& p, vec3& n, int& material) {
                for (int k = 0; k < 24; ++k) {  // bisection
                    vec3 mid = 0.5f * (in + out);
                    (sdf.eval(mid) < 0.0f ? in : out) = mid;
                }
                p = 0.5f * (in + out);
                n = sdf.normal(p);
                material = obj.material;
            },
            [&](vec3& p, vec3& n) {
                for (int k = 0; k < 4; ++k) p -= sdf.eval(p) * sdf.normal(p);  // onto the surface
                n = sdf.normal(p);
            });
    } else {
        const CsgShape& csg = *shape.csg;
        surface_nets(
            m, bounds, o.grid, [&](vec3 p) { return csg.contains(p); },
            [&](vec3 in, vec3 out, vec3& p, vec3& n, int& material) {
                // The exact crossing: a ray from the inside corner to the outside one.
                // (A little past 1: the outside corner may lie on the surface itself.)
                Ray ray{in, out - in, 1.001f};
                ShapeHit h;
                if (csg.intersect(ray, ray.tmax, h)) {
                    ShapeSurface sf = csg.surface(ray, h);
                    p = sf.p;
                    n = sf.n;
                    material = static_cast<int>(sf.material);
                } else {
                    p = 0.5f * (in + out);
                    n = glm::normalize(out - in);
                    material = obj.material;
                }
            },
            [](vec3&, vec3&) {});
    }
    return m;
}

}  // namespace

float sphere_tessellation_error(float r, const TessellationOptions& o) {
    // No point of a cell is farther than half its diagonal (in angle) from a corner.
    float dphi = 2.0f * kPi / static_cast<float>(o.segments),
          dtheta = kPi / static_cast<float>(o.rings);
    return r * (1.0f - std::cos(0.5f * std::sqrt(dphi * dphi + dtheta * dtheta)));
}

uint64_t tessellated_triangles(const Scene& scene, const TessellationOptions& options) {
    const auto count = [&](const Object& obj) { return tessellated_triangles(obj, options); };
    uint64_t total = 0;
    for (const Object& obj : scene.objects) total += count(obj);
    return total + sum_over_instances(scene, count);
}

uint64_t tessellated_triangles(const Object& obj, const TessellationOptions& o) {
    auto seg = static_cast<uint64_t>(o.segments), rings = static_cast<uint64_t>(o.rings);
    if (std::holds_alternative<Sphere>(obj.shape)) return 2 * seg * rings;
    if (std::holds_alternative<Quad>(obj.shape)) return 2;
    if (std::holds_alternative<Plane>(obj.shape)) return 2 * 16 * 16;
    if (std::holds_alternative<Box>(obj.shape)) return 12;
    if (std::holds_alternative<Cylinder>(obj.shape)) return 4 * seg;
    if (std::holds_alternative<Cone>(obj.shape))
        return 2 * seg * std::max<uint64_t>(1, seg / 2) + seg;
    if (const auto* m = std::get_if<Mesh>(&obj.shape)) return m->triangle_count();
    // Surface nets: at most two triangles per grid edge, three edges per grid point.
    auto g = static_cast<uint64_t>(o.grid) + 3;
    return 6 * g * g * g;
}

bool tessellates_convex(const Object& obj) {
    return std::holds_alternative<Sphere>(obj.shape) || std::holds_alternative<Box>(obj.shape) ||
           std::holds_alternative<Cylinder>(obj.shape) || std::holds_alternative<Cone>(obj.shape) ||
           std::holds_alternative<Quad>(obj.shape) || std::holds_alternative<Plane>(obj.shape);
}

Mesh tessellate(const Object& obj, const TessellationOptions& o) {
    Mesh m;
    m.smooth = true;
    bool per_face_done = false;
    if (const auto* s = std::get_if<Sphere>(&obj.shape)) {
        sphere(m, *s, o);
    } else if (const auto* q = std::get_if<Quad>(&obj.shape)) {
        quad(m, q->corner, q->edge_u, q->edge_v);
    } else if (const auto* pl = std::get_if<Plane>(&obj.shape)) {
        Frame f = Frame::from_normal(pl->normal);
        float e = o.plane_extent;
        // uv as the ray tracer's plane: distances along the frame's tangents from the point.
        quad(m, pl->point - e * f.t - e * f.b, 2.0f * e * f.t, 2.0f * e * f.b, 16, 16);
        for (size_t k = 0; k < m.uvs.size(); ++k) m.uvs[k] = (m.uvs[k] - vec2(0.5f)) * (2.0f * e);
    } else if (const auto* b = std::get_if<Box>(&obj.shape)) {
        box(m, *b);
    } else if (const auto* cy = std::get_if<Cylinder>(&obj.shape)) {
        quadric(m, cy->base, cy->axis, cy->radius, false, o);
    } else if (const auto* co = std::get_if<Cone>(&obj.shape)) {
        quadric(m, co->base, co->axis, co->radius, true, o);
    } else if (const auto* mesh = std::get_if<Mesh>(&obj.shape)) {
        m = *mesh;
        if (obj.material >= 0 || m.face_material.empty()) {
            m.face_material.assign(m.triangle_count(), obj.material);
        }
        per_face_done = true;
    } else {
        return polygonise(obj, o);  // already in world space, with face materials
    }
    if (!per_face_done) m.face_material.assign(m.triangle_count(), obj.material);
    transform_mesh(m, 0, obj.transform);
    return m;
}

}  // namespace svetlo
