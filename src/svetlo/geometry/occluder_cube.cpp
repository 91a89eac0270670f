#include "svetlo/geometry/occluder_cube.h"

#include <algorithm>
#include <cmath>

#include "svetlo/core/parallel.h"

namespace svetlo {

namespace {

using dvec3 = glm::dvec3;

/// The distance from the origin to segment [a, b] (a point where a = b).
double distance_to_segment(dvec3 a, dvec3 b) {
    const dvec3 ab = b - a;
    const double length2 = glm::dot(ab, ab);
    const double t = length2 > 0.0 ? std::clamp(-glm::dot(a, ab) / length2, 0.0, 1.0) : 0.0;
    return glm::length(a + t * ab);
}

/// The distance from the origin to triangle (a, b, c): its closest point by the Voronoi
/// regions of the corners, edges and face (Ericson, "Real-Time Collision Detection", 2005,
/// section 5.1.5), in double. A triangle without area (a sphere's pole, two corners alike)
/// is its edges.
double distance_to_triangle(dvec3 a, dvec3 b, dvec3 c) {
    const dvec3 normal = glm::cross(b - a, c - a);
    if (!(glm::dot(normal, normal) > 0.0))
        return std::min(
            {distance_to_segment(a, b), distance_to_segment(b, c), distance_to_segment(c, a)});
    const dvec3 ab = b - a, ac = c - a, ap = -a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return glm::length(a);
    const dvec3 bp = -b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return glm::length(b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return glm::length(a + d1 / (d1 - d3) * ab);
    const dvec3 cp = -c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return glm::length(c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return glm::length(a + d2 / (d2 - d6) * ac);
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
        return glm::length(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b));
    const double denom = va + vb + vc;
    return glm::length(a + (vb / denom) * ab + (vc / denom) * ac);
}

/// The triangle's corners (relative to E) clipped to the half-space z >= z0 of a face whose
/// depth axis is `axis` with sign `sign`: at most four corners, their count returned.
int clip_to_face(const dvec3 (&corner)[3], int axis, double sign, double z0, dvec3 (&out)[4]) {
    int n = 0;
    for (int k = 0; k < 3; ++k) {
        const dvec3 p = corner[k], q = corner[(k + 1) % 3];
        const double zp = sign * p[axis] - z0, zq = sign * q[axis] - z0;
        if (zp >= 0.0) out[n++] = p;
        if ((zp >= 0.0) != (zq >= 0.0)) out[n++] = p + (zp / (zp - zq)) * (q - p);
    }
    return n;
}

/// The cells of a cube face of R x R cells (`axis`, `sign`) that may see triangle p
/// (relative to the centre; none nearer than d > 0): [i0, i1] x [j0, j1], or false where the
/// face sees none of it.
bool seen_cells(const dvec3 (&p)[3], int axis, double sign, double d, int R, int& i0, int& i1,
                int& j0, int& j1) {
    const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
    // The points of the triangle nearer the face's plane than d / 2 lie outside the
    // face's pyramid (|u|, |v| <= z puts a point within sqrt(3) z of E), so the
    // projection of the rest is all of it that the face sees.
    dvec3 clipped[4];
    const int n = clip_to_face(p, axis, sign, 0.5 * d, clipped);
    if (n == 0) return false;
    double u_lo = 1e300, u_hi = -1e300, v_lo = 1e300, v_hi = -1e300;
    for (int k = 0; k < n; ++k) {
        const double z = sign * clipped[k][axis];
        const double u = clipped[k][u_axis] / z, v = clipped[k][v_axis] / z;
        u_lo = std::min(u_lo, u);
        u_hi = std::max(u_hi, u);
        v_lo = std::min(v_lo, v);
        v_hi = std::max(v_hi, v);
    }
    if (u_hi < -1.5 || u_lo > 1.5 || v_hi < -1.5 || v_lo > 1.5) return false;
    // The cells, one more each way (clear's rounding), within the face.
    auto cell = [&](double u) {
        return static_cast<int>(std::floor((std::clamp(u, -2.0, 2.0) + 1.0) * 0.5 * R));
    };
    i0 = std::max(cell(u_lo) - 1, 0);
    i1 = std::min(cell(u_hi) + 1, R - 1);
    j0 = std::max(cell(v_lo) - 1, 0);
    j1 = std::min(cell(v_hi) + 1, R - 1);
    return true;
}

}  // namespace

namespace {

/// Cell i of a face grown by a cell each way: its range [lo, hi] of u (or v).
void grown_cell(int i, double& lo, double& hi) {
    constexpr double kCell = 2.0 / OccluderCube::kResolution;  // a cell's size in u and v
    lo = -1.0 + (i - 1) * kCell;
    hi = lo + 3.0 * kCell;
}

}  // namespace

namespace {

/// Triangle t's corners relative to the end E, in double.
void corners_from(const TriangleList& list, size_t t, vec3 end, dvec3 (&p)[3]) {
    for (int k = 0; k < 3; ++k) p[k] = dvec3(list.positions[list.indices[3 * t + k]]) - dvec3(end);
}

/// Each triangle's distance to the end E (0 where a corner is not finite: no bound but 0, in
/// every cell).
std::vector<double> triangle_distances(const TriangleList& list, vec3 end, int threads) {
    const size_t triangles = list.triangle_count();
    std::vector<double> distance(triangles);
    parallel_ranges(triangles, threads, [&](size_t begin, size_t stop) {
        for (size_t t = begin; t < stop; ++t) {
            dvec3 p[3];
            corners_from(list, t, end, p);
            const double sum =
                p[0].x + p[0].y + p[0].z + p[1].x + p[1].y + p[1].z + p[2].x + p[2].y + p[2].z;
            distance[t] = sum - sum == 0.0 ? distance_to_triangle(p[0], p[1], p[2]) : 0.0;
        }
    });
    return distance;
}

/// Per cell grown by a cell each way (clear() may look a direction up in a neighbour's cell),
/// the least |(u, v, 1)| over it: the same on every face.
std::vector<double> least_lengths() {
    constexpr int R = OccluderCube::kResolution;
    std::vector<double> least_length(static_cast<size_t>(R) * R);
    for (int j = 0; j < R; ++j) {
        for (int i = 0; i < R; ++i) {
            double u0, u1, v0, v1;
            grown_cell(i, u0, u1);
            grown_cell(j, v0, v1);
            const double du = u0 > 0.0 ? u0 : (u1 < 0.0 ? -u1 : 0.0);
            const double dv = v0 > 0.0 ? v0 : (v1 < 0.0 ? -v1 : 0.0);
            least_length[static_cast<size_t>(j) * R + i] = std::sqrt(1.0 + du * du + dv * dv);
        }
    }
    return least_length;
}

}  // namespace

OccluderCube::OccluderCube(const TriangleList& list, vec3 end, int threads)
    : end_(end), objects_(list.objects), convex_(list.convex), centroid_(list.centroid) {
    constexpr int R = kResolution;
    const size_t triangles = list.triangle_count();
    convex_.resize(objects_.size(), 0);  // (a list made without them: no object is convex)
    centroid_.resize(objects_.size(), vec3(0.0f));
    if (!list.w.empty()) return;  // points at infinity: an empty cube, which calls nothing clear
    cells_.assign(6 * static_cast<size_t>(R) * R, Cell{kInfinity, kInfinity, kNoObject});
    // The scale of the coordinates: the ray test's rounding is a few ulps of it.
    const Bounds3 bounds = list.bounds();
    auto largest = [](vec3 v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); };
    float scale = std::max(largest(end), 1.0f);
    if (triangles > 0) scale = std::max({scale, largest(bounds.min), largest(bounds.max)});
    // A shadow ray's origin lies within 2^-13 of the scale of its sample (offset_ray_origin's
    // 256 ulps a coordinate, and a 2^-16 step toward the light): twice that is the slack.
    // Beyond a sixteenth of the scale from E, that hair turns a direction by less than 2^-9,
    // which moves it by at most a third of a cell (each cell's bound holds a cell beyond it).
    slack_ = scale * 0x1p-12f;
    near2_ = scale * scale * 0x1p-8f;
    // The ray test's rounding: a few ulps of the scale.
    const double pad = static_cast<double>(scale) * 0x1p-16;

    // Per triangle: its object, and its distance to E (0 where it is not known).
    std::vector<uint32_t> object(triangles, kNoObject);
    for (size_t k = 0; k < list.objects.size(); ++k)
        for (uint32_t t = list.objects[k].first; t < list.objects[k].end && t < triangles; ++t)
            object[t] = static_cast<uint32_t>(k);
    const std::vector<double> distance = triangle_distances(list, end, threads);
    const std::vector<double> least_length = least_lengths();
    // Face by face (each writes its own cells), every triangle into the cells its projection
    // may touch.
    parallel_indices(6, threads, [&](size_t face) {
        Cell* cells = cells_.data() + face * R * R;
        for (size_t t = 0; t < triangles; ++t) {
            dvec3 p[3];
            corners_from(list, t, end, p);
            add_triangle(cells, static_cast<int>(face), p, distance[t], object[t], pad,
                         least_length);
        }
    });
}

void OccluderCube::add_triangle(Cell* cells, int face, const dvec3 (&p)[3], double d, uint32_t o,
                                double pad, const std::vector<double>& least_length) {
    constexpr int R = kResolution;
    const int axis = face / 2;
    const double sign = face % 2 == 0 ? 1.0 : -1.0;
    const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
    int i0 = 0, i1 = R - 1, j0 = 0, j1 = R - 1;  // the whole face, unless below
    const double z_most = std::max({sign * p[0][axis], sign * p[1][axis], sign * p[2][axis]});
    if (d > 0.0 && z_most < 0.5 * d) return;  // not seen by the face (below)
    if (d > 0.0 && !seen_cells(p, axis, sign, d, R, i0, i1, j0, j1)) return;
    // The triangle's plane n . x = h (h >= 0; relative to E), in the face's (u, v, 1):
    // along a direction w of the cell, the plane is h / (n . w) away, or never met
    // where n . w <= 0.
    dvec3 normal = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double area2 = glm::dot(normal, normal);
    normal = area2 > 0.0 ? normal / std::sqrt(area2) : dvec3(0.0);
    double h = glm::dot(normal, p[0]);
    if (h < 0.0) {
        normal = -normal;
        h = -h;
    }
    const double n_u = normal[u_axis], n_v = normal[v_axis], n_z = sign * normal[axis];
    for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
            // The triangle's distance along the grown cell's directions is at least d,
            // and at least the plane's there: h |(u, v, 1)| / (n_u u + n_v v + n_z),
            // which is least where the denominator is largest (a corner) and the point
            // nearest the face's centre.
            double bound = d;
            if (area2 > 0.0) {
                double u0, u1, v0, v1;
                grown_cell(i, u0, u1);
                grown_cell(j, v0, v1);
                const double m = n_z + std::max(n_u * u0, n_u * u1) + std::max(n_v * v0, n_v * v1);
                if (m <= 0.0) continue;  // the plane is not met in this cell
                bound = std::max(bound, h * least_length[static_cast<size_t>(j) * R + i] / m);
            }
            const double lower_bound = std::max(0.0, bound * (1.0 - 0x1p-16) - pad);
            // (Squared and lowered a hair, within float: a bound beyond its range is
            // the largest float, still a lower bound.)
            const auto lower =
                static_cast<float>(std::min(lower_bound * lower_bound * (1.0 - 0x1p-16), 3.0e38));
            Cell& c = cells[j * R + i];
            // nearest: the least of all; other: the least of the objects but nearest's.
            if (o == c.object) {
                c.nearest2 = std::min(c.nearest2, lower);
            } else if (lower < c.nearest2) {
                c.other2 = c.nearest2;
                c.nearest2 = lower;
                c.object = o;
            } else {
                c.other2 = std::min(c.other2, lower);
            }
        }
    }
}

size_t OccluderCube::empty_cells() const {
    return static_cast<size_t>(std::count_if(
        cells_.begin(), cells_.end(), [](const Cell& c) { return c.nearest2 == kInfinity; }));
}

}  // namespace svetlo
