// Form factors between radiosity's nodes (element_tree.h), by three methods
// (render.radiosity.form_factors, docs/radiosity.md):
//
//   analytic  Lambert's contour integral from the receiver's centroid to the source triangle,
//             clipped to the receiver's hemisphere: exact for a differential receiver and an
//             unoccluded source (Baum, Rushmeier and Winget 1989); times the fraction of
//             `samples` shadow rays from the centroid to stratified points of the source.
//   raycast   `samples` stratified points on the source, each the disc of area A_s / N that
//             it stands for, seen from the receiver's centroid with visibility:
//             dF = V cos_r cos_s (A_s/N) / (pi d^2 + A_s/N) (Wallace, Elmquist and Haines 1989).
//   hemicube  hemicube.h: a row of form factors at once, from an item buffer.
//
// F_rs is the fraction of the light leaving r toward s's side that reaches s, so the
// irradiance r receives from s is E_r = F_rs B_s (W/m^2) and A_r F_rs = A_s F_sr.
#pragma once

#include <cstdint>

#include "svetlo/geometry/accel.h"
#include "svetlo/radiosity/element_tree.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// The unoccluded form factor from a differential area at x (unit normal n, its side) to the
/// triangle v (any winding): (1 / 2 pi) sum over the edges of the clipped polygon of
/// gamma_k n . (R_k x R_k+1) / |R_k x R_k+1|.
float point_triangle_form_factor(vec3 x, vec3 n, const vec3 v[3]);

/// Whether the segment between two surface points is free (each offset off its surface).
bool segment_visible(const Accel& accel, vec3 x, vec3 nx, vec3 y, vec3 ny);

struct FormFactorContext {
    const ElementTree& tree;
    const Accel& accel;
    FormFactorMethod method = FormFactorMethod::Analytic;
    int samples = 4;
};

/// A form factor from a receiver's two sides, with the visibility estimate it used.
struct FormFactor {
    float F[2] = {0.0f, 0.0f};  // from the receiver's front side and from its back side
    float visibility = 1.0f;    // the fraction of the rays that were free
    float sum() const { return F[0] + F[1]; }
};

/// F from node r to node s, estimated at r's centroid x, by the context's analytic or
/// raycast method: the light comes from s's side that faces x, and reaches r's front side
/// from the part of s in front of r's plane and its back side from the part behind (a
/// source that straddles the receiver's plane lights both). `seed` picks the rays' stream
/// (so that the result does not depend on which thread asks). Adds its rays to `rays`.
FormFactor form_factor(const FormFactorContext& ctx, uint32_t r, uint32_t s, uint64_t seed,
                       uint64_t& rays);

/// The unit normal of node id's side facing q (element_tree.h's sides).
inline vec3 facing_normal(const ElementTree& tree, uint32_t id, vec3 q) {
    return tree.side_facing(id, q) == 0 ? tree.normal(id) : -tree.normal(id);
}

}  // namespace svetlo
