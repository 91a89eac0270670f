// Stages 3 and 4: primitive assembly, clipping, setup, and binning into tiles.
#include <algorithm>
#include <type_traits>

#include "svetlo/core/parallel.h"
#include "svetlo/geometry/avx2.h"
#include "svetlo/raster/fragment.h"
#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

namespace {

/// Stage 3 for one triangle: screen area, culling and bounds. False when it draws nothing.
bool setup_triangle(const PassGeometry& f, const ScreenVertex* sv[3], const uint32_t index[3],
                    uint32_t material, SetupTriangle& t) {
    t.make_empty();  // until set up
    for (int i = 0; i < 3; ++i) {
        t.x[i] = sv[i]->x;
        t.y[i] = sv[i]->y;
        t.z[i] = sv[i]->z;
        t.v[i] = index[i];
    }
    int64_t area = signed_area2(t.x, t.y);
    if (area == 0) return false;  // degenerate on the screen: covers no sample
    t.front = front_facing(area) ? 1 : 0;
    t.inv_area = 1.0f / static_cast<float>(std::abs(area));
    if ((f.cull == CullMode::Back && !t.front) || (f.cull == CullMode::Front && t.front))
        return false;
    if (area < 0) {  // wound so that the area is positive, as the edge functions want
        std::swap(t.x[1], t.x[2]);
        std::swap(t.y[1], t.y[2]);
        std::swap(t.z[1], t.z[2]);
        std::swap(t.v[1], t.v[2]);
    }
    int32_t xmin = std::min({t.x[0], t.x[1], t.x[2]}), xmax = std::max({t.x[0], t.x[1], t.x[2]});
    int32_t ymin = std::min({t.y[0], t.y[1], t.y[2]}), ymax = std::max({t.y[0], t.y[1], t.y[2]});
    // Pixel i's samples lie at i + o, o in [lo, hi] (f.sample_bounds, fixed point): it may hold
    // a covered one when i >= ceil((min - hi) / 256) and i <= floor((max - lo) / 256). The
    // wireframe wants a pixel more on each side (Wu's lines spread to the neighbours, and
    // triangles that cover no sample still have edges).
    const auto& b = f.sample_bounds;
    int32_t x0 = std::max(0, -((b.hi.x - xmin) >> kSubpixelBits) - b.margin),
            y0 = std::max(0, -((b.hi.y - ymin) >> kSubpixelBits) - b.margin);
    int32_t x1 = std::min(f.cam.width, ((xmax - b.lo.x) >> kSubpixelBits) + 1 + b.margin),
            y1 = std::min(f.cam.height, ((ymax - b.lo.y) >> kSubpixelBits) + 1 + b.margin);
    if (x0 >= x1 || y0 >= y1) return false;
    t.bx0 = static_cast<uint16_t>(x0);
    t.by0 = static_cast<uint16_t>(y0);
    t.bx1 = static_cast<uint16_t>(x1 - 1);
    t.by1 = static_cast<uint16_t>(y1 - 1);
    t.material = material;
    // The triangle itself, not its bounds clamped to the film: the edge coefficients grow with it.
    t.small = xmax - xmin <= kSmall * kSubpixel && ymax - ymin <= kSmall * kSubpixel ? 1 : 0;
    return true;
}

/// A triangle to bin: its id and the tiles its bounds touch, [tx0, tx1] x [ty0, ty1].
struct Binned {
    uint32_t id;
    uint16_t tx0, ty0, tx1, ty1;
};

/// From a record's inclusive pixel bounds (a SetupTriangle's or a DepthTriangle's).
template <class Record>
Binned binned(uint32_t id, const Record& t) {
    return {id, static_cast<uint16_t>(t.bx0 / kTile), static_cast<uint16_t>(t.by0 / kTile),
            static_cast<uint16_t>(t.bx1 / kTile), static_cast<uint16_t>(t.by1 / kTile)};
}

/// Whether triangle `te` may cover a sample of tile (tx, ty): for each edge, its value at the
/// corner of the tile's sample positions where it is largest (exact, in 64 bits). A long,
/// thin triangle (a shadow volume's side) crosses its bounds' tiles on a diagonal; the others
/// are left out.
bool reaches(const PassGeometry& f, const TriangleEdges& te, size_t tx, size_t ty) {
    const auto& b = f.sample_bounds;
    const int64_t x0 = static_cast<int64_t>(tx) * kTile * kSubpixel + b.lo.x,
                  y0 = static_cast<int64_t>(ty) * kTile * kSubpixel + b.lo.y;
    const int64_t x1 = static_cast<int64_t>(tx + 1) * kTile * kSubpixel - kSubpixel + b.hi.x,
                  y1 = static_cast<int64_t>(ty + 1) * kTile * kSubpixel - kSubpixel + b.hi.y;
    for (const Edge& e : te.e) {
        if (e.at(e.a > 0 ? x1 : x0, e.b > 0 ? y1 : y0) + e.bias < 0) return false;
    }
    return true;
}

/// Stage 4 for one chunk: its triangles (in drawing order) into the tiles they may cover, as
/// compressed rows: tile k's triangles are b.ids[b.start[k] .. b.start[k + 1]). Triangles
/// whose bounds meet more than two tiles are tested against each (`reaches`; `triangle(id)`
/// gives the SetupTriangle of an id), unless the bounds have a margin (the wireframe draws
/// beside the edges). A depth-only pass's records are small and not tested (`triangle`
/// null).
template <class Triangle = std::nullptr_t>
void bin_chunk(const PassGeometry& f, const std::vector<Binned>& tris, PassGeometry::Bins& b,
               Triangle&& triangle = nullptr) {
    size_t tiles = static_cast<size_t>(f.tiles_x) * f.tiles_y;
    b.start.assign(tiles + 1, 0);
    const bool exact = f.sample_bounds.margin == 0;
    auto each = [&](auto&& visit) {
        for (const Binned& t : tris) {
            if (t.tx0 == t.tx1 && t.ty0 == t.ty1) {  // most: one tile
                visit(static_cast<size_t>(t.ty0) * f.tiles_x + t.tx0, t.id);
                continue;
            }
            if constexpr (!std::is_same_v<std::decay_t<Triangle>, std::nullptr_t>) {
                if (exact && (t.tx1 - t.tx0 + 1) * (t.ty1 - t.ty0 + 1) > 2) {
                    const TriangleEdges te(triangle(t.id));
                    for (size_t ty = t.ty0; ty <= t.ty1; ++ty) {
                        for (size_t tx = t.tx0; tx <= t.tx1; ++tx) {
                            if (reaches(f, te, tx, ty)) visit(ty * f.tiles_x + tx, t.id);
                        }
                    }
                    continue;
                }
            }
            for (size_t ty = t.ty0; ty <= t.ty1; ++ty) {
                for (size_t tx = t.tx0; tx <= t.tx1; ++tx) visit(ty * f.tiles_x + tx, t.id);
            }
        }
    };
    each([&](size_t tile, uint32_t) { b.start[tile + 1]++; });
    for (size_t k = 0; k < tiles; ++k) b.start[k + 1] += b.start[k];
    b.ids.resize(b.start[tiles]);
    std::vector<uint32_t> fill(b.start.begin(), b.start.end() - 1);
    each([&](size_t tile, uint32_t id) { b.ids[fill[tile]++] = id; });
}

/// The pieces of one chunk's triangles that cross the guard band or the near plane: set-up
/// triangles whose vertices index `vertices` (chunk-local, kExtra set), the triangle each
/// came from, and its flat colour.
struct ClippedPieces {
    std::vector<SetupTriangle> triangles;
    std::vector<ClipVertex> vertices;
    std::vector<uint32_t> source;
    std::vector<Color> flat;
};

/// Triangle s (vertices idx) clipped against the near plane and the guard band, its polygon
/// set up as a fan of pieces appended to `out`. A vertex whose clip coordinates overflowed
/// (world coordinates near a float's limit) cannot be clipped or snapped, and a piece through
/// the eye (w = 0: a point at infinity seen edge-on) has no place: neither is drawn.
void clip_and_set_up(FrameState& f, const uint32_t idx[3], uint32_t material, uint32_t s, float gx,
                     float gy, bool flat_mode, ClippedPieces& out) {
    const vec4 &c0 = f.vertices[idx[0]].clip, &c1 = f.vertices[idx[1]].clip,
               &c2 = f.vertices[idx[2]].clip;
    if (!std::isfinite(c0.x + c0.y + c0.z + c0.w + c1.x + c1.y + c1.z + c1.w + c2.x + c2.y + c2.z +
                       c2.w))
        return;
    ClipPolygon poly =
        clip_triangle(f.vertices[idx[0]], f.vertices[idx[1]], f.vertices[idx[2]], gx, gy);
    if (poly.count < 3) return;
    if (!std::all_of(poly.v.begin(), poly.v.begin() + poly.count,
                     [](const ClipVertex& v) { return projectable(v.clip); }))
        return;
    auto first = static_cast<uint32_t>(out.vertices.size());
    std::array<ScreenVertex, std::tuple_size_v<decltype(ClipPolygon::v)>> ps;
    for (int k = 0; k < poly.count; ++k) {
        out.vertices.push_back(poly.v[static_cast<size_t>(k)]);
        ps[k] = project(f, poly.v[static_cast<size_t>(k)]);
    }
    for (int k = 1; k + 1 < poly.count; ++k) {
        const ScreenVertex* fv[3] = {&ps[0], &ps[k], &ps[k + 1]};
        SetupTriangle piece;
        // Chunk-local vertex indices for now: fixed up when the chunks are joined.
        uint32_t local[3] = {kExtra | first, kExtra | (first + static_cast<uint32_t>(k)),
                             kExtra | (first + static_cast<uint32_t>(k) + 1)};
        if (setup_triangle(f, fv, local, material, piece)) {
            out.triangles.push_back(piece);
            out.source.push_back(s);
            if (flat_mode) out.flat.push_back(f.flat[s]);
        }
    }
}

/// The chunks' clipped pieces and their vertices concatenated, chunk after chunk, into the
/// frame's, and the bins' chunk-local ids of pieces made the frame's.
void join_chunks(FrameState& f, const std::vector<ClippedPieces>& chunk_pieces,
                 const std::vector<size_t>& counts, int threads) {
    const size_t chunks = chunk_pieces.size();
    for (size_t c = 0; c < chunks; ++c) {
        const ClippedPieces& p = chunk_pieces[c];
        auto offset = static_cast<uint32_t>(f.extra.size());
        f.extra.insert(f.extra.end(), p.vertices.begin(), p.vertices.end());
        auto begin = static_cast<uint32_t>(f.clipped.size());
        for (SetupTriangle t : p.triangles) {
            for (uint32_t& v : t.v) v = kExtra | (offset + (v & ~kExtra));
            f.clipped.push_back(t);
        }
        f.clipped_flat.insert(f.clipped_flat.end(), p.flat.begin(), p.flat.end());
        f.clipped_source.insert(f.clipped_source.end(), p.source.begin(), p.source.end());
        f.clipped_range.emplace_back(begin, static_cast<uint32_t>(f.clipped.size()));
        f.triangle_count += counts[c] + p.triangles.size();
    }
    auto main_count = static_cast<uint32_t>(f.tris.size());
    parallel_indices(chunks, threads, [&](size_t c) {
        if (chunk_pieces[c].triangles.empty()) return;
        for (uint32_t& id : f.bins[c].ids) {
            if (id & kExtra) id = main_count + f.clipped_range[c].first + (id & ~kExtra);
        }
    });
}

}  // namespace

/// Stage 3: primitive assembly, clipping and setup of every triangle, in chunks of kChunk
/// triangles. An unclipped triangle is set up in its own slot; the pieces of clipped ones go
/// to per-chunk lists appended after the slots, so the order never depends on threads.
void assemble(const TriangleList& list, FrameState& f, int threads) {
#ifdef SVETLO_HAS_AVX2_KERNEL
    f.avx2 = avx2_available();
#endif
    const size_t total = list.triangle_count();
    size_t chunks = (total + kChunk - 1) / kChunk;
    f.tris.reuse(total);
    std::vector<ClippedPieces> chunk_pieces(chunks);
    std::vector<size_t> counts(chunks, 0);
    f.tiles_x = (f.cam.width + kTile - 1) / kTile;
    f.tiles_y = (f.cam.height + kTile - 1) / kTile;
    f.bins.assign(chunks, {});
    f.depth_bins.assign(f.depth_records() ? chunks : 0, {});
    if (f.depth_records()) f.depth_tris.reuse(total);
    float gx = guard_x(f), gy = guard_y(f);
    const bool flat_mode = f.mode == Mode::Flat;
    if (flat_mode) f.flat.reuse(total);
    if (flat_mode && f.per_light) f.face_light.reuse(total * f.sources);
    parallel_indices(chunks, threads, [&](size_t c) {
        const size_t begin = c * kChunk, end = std::min(total, (c + 1) * kChunk);
        std::vector<Binned> to_bin(end - begin);  // binned while the chunk is in cache, below
        size_t binned_count = 0;
        size_t depth_count = 0;
        // The list's arrays held in locals (the stores below could otherwise alias them, and
        // they would be reloaded every time).
        const uint32_t* const indices = list.indices.data();
        const uint32_t* const materials = list.material.data();
        // One triangle (inlined: called apart, the colour pass's setup was 1.5 % slower).
        auto one = [&](size_t s) __attribute__((always_inline)) {
            uint32_t idx[3];
            const ScreenVertex* sv[3];
            for (int i = 0; i < 3; ++i) {
                idx[i] = indices[3 * s + i];
                sv[i] = &f.screen[idx[i]];
            }
            const uint32_t material = materials[s];
            SetupTriangle& slot = f.tris[s];
            if (flat_mode)
                f.flat[s] = flat_colour(f, idx, material,
                                        f.per_light ? &f.face_light[s * f.sources] : nullptr);
            if (sv[0]->inside & sv[1]->inside & sv[2]->inside) {
                if (setup_triangle(f, sv, idx, material, slot))
                    to_bin[binned_count++] = binned(static_cast<uint32_t>(s), slot);
                return;
            }
            slot.make_empty();
            clip_and_set_up(f, idx, material, static_cast<uint32_t>(s), gx, gy, flat_mode,
                            chunk_pieces[c]);
        };
        size_t s = begin;
#if SVETLO_SIMD
        if (f.depth_records()) {
            // Eight at a time where they take the fast road; the rest on the general one.
            std::vector<uint32_t> others(end - begin);
            size_t other_count = 0;
            depth_count = setup_depth_avx2(f, indices + 3 * begin, end - begin,
                                           &f.depth_tris[begin], others.data(), other_count);
            for (size_t k = 0; k < other_count; ++k) one(begin + others[k]);
            s = begin + (end - begin) / 8 * 8;
        }
#endif
        for (; s < end; ++s) one(s);
        // Its slots, then its pieces (ids chunk-local until the pieces are concatenated below).
        to_bin.resize(binned_count);
        counts[c] = binned_count;
        const std::vector<SetupTriangle>& pieces = chunk_pieces[c].triangles;
        for (size_t k = 0; k < pieces.size(); ++k)
            to_bin.push_back(binned(kExtra | static_cast<uint32_t>(k), pieces[k]));
        bin_chunk(f, to_bin, f.bins[c], [&](uint32_t id) -> const SetupTriangle& {
            return (id & kExtra) ? pieces[id & ~kExtra] : f.tris[id];
        });
        if (f.depth_records()) {
            std::vector<Binned> records(depth_count);
            for (size_t k = 0; k < depth_count; ++k) {
                const auto id = static_cast<uint32_t>(begin + k);
                records[k] = binned(id, f.depth_tris[id]);
            }
            bin_chunk(f, records, f.depth_bins[c]);
        }
        counts[c] += depth_count;
    });
    join_chunks(f, chunk_pieces, counts, threads);
}

/// Stage 4 for the painter's algorithm: every triangle sorted back to front by the
/// centroid's depth (ties keep the submission order), then binned again chunk by chunk.
/// (The z-buffer's bins are made by `assemble`, each chunk's right after its setup.)
void bin_back_to_front(PassGeometry& f, int threads) {
    std::vector<uint32_t> order;
    order.reserve(f.triangle_count);
    auto main_count = static_cast<uint32_t>(f.tris.size());
    for (size_t c = 0; c < f.clipped_range.size(); ++c) {  // the submission order
        for (uint32_t id = static_cast<uint32_t>(c * kChunk);
             id < std::min<size_t>(main_count, (c + 1) * kChunk); ++id) {
            if (!f.tris[id].empty()) order.push_back(id);
        }
        for (uint32_t k = f.clipped_range[c].first; k < f.clipped_range[c].second; ++k)
            order.push_back(main_count + k);
    }
    // The centroid's distance along the view axis: mean w (perspective) or mean z (orthographic).
    std::vector<float> key(f.tris.size() + f.clipped.size());
    for (uint32_t id : order) {
        const SetupTriangle& t = f.tri(id);
        float sum = 0.0f;
        for (uint32_t v : t.v) sum += f.cam.orthographic ? f.vertex(v).clip.z : f.vertex(v).clip.w;
        key[id] = sum / 3.0f;
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return key[a] > key[b]; });
    size_t chunks = (order.size() + kChunk - 1) / kChunk;
    f.bins.assign(chunks, {});
    parallel_indices(chunks, threads, [&](size_t c) {
        std::vector<Binned> to_bin;
        for (size_t k = c * kChunk; k < std::min(order.size(), (c + 1) * kChunk); ++k)
            to_bin.push_back(binned(order[k], f.tri(order[k])));
        bin_chunk(f, to_bin, f.bins[c],
                  [&](uint32_t id) -> const SetupTriangle& { return f.tri(id); });
    });
}

}  // namespace svetlo::raster
