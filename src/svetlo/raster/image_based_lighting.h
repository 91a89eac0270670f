// The environment in the rasterizer, as real-time renderers light with it (docs/raster.md,
// "Image-based lighting"): no rays, no shadows from it.
//   - diffuse: the irradiance E(n) from the map's projection on the nine spherical harmonics
//     of orders 0 to 2, E(n) = sum over l, m of A_l L_lm Y_lm(n), with A_0 = pi, A_1 = 2pi/3,
//     A_2 = pi/4 (Ramamoorthi and Hanrahan 2001, "An efficient representation for irradiance
//     environment maps"); exact for a uniform map and for a sky bright above the horizon;
//   - glossy (Cook-Torrance): the split-sum approximation, a prefiltered map times the
//     BRDF's directional albedo from a table (split_sum.h; Karis 2013);
//   - mirrors: the map along the mirrored direction; glass: the map straight through;
//   - the background: the map along each sample's camera ray.
#pragma once

#include <array>
#include <memory>

#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/edge_function.h"
#include "svetlo/raster/split_sum.h"
#include "svetlo/scene/scene.h"
#include "svetlo/shading/environment.h"

namespace svetlo {

/// What image-based lighting makes of a map (its SH coefficients, its prefiltered levels, the
/// split-sum table), kept from one frame to the next as a GL context keeps a texture: the
/// viewer loads the scene again each frame, and making them is most of a frame's setup
/// (docs/performance.md, "Costs the code's choices rest on"); keeping them costs a compare
/// of the texels. Made again when the map's texels, its rotation or its scale change; a map
/// over kKeptBytes is not kept (a copy would double it).
class IblCache {
public:
    static constexpr size_t kKeptBytes = size_t{64} << 20;

    struct Made {
        std::array<Color, 9> coefficients{};  // A_l L_lm, in the order of sh_basis
        std::shared_ptr<const PrefilteredEnvironment> prefiltered;
        std::shared_ptr<const SplitSumTable> table;
    };
    /// The parts for `scene`'s map, made on `threads` threads when they must be.
    Made of(const Scene& scene, int threads);

private:
    Scene kept_;  // the map the parts were made from (a copy), with its settings
    Made made_;
};

/// The directions of a camera's rays through its film, for the map behind the scene: a
/// perspective camera's ray through the pixel point (px, py) points along c + px a + py b
/// (world space; the film is a plane in front of the eye), found once a frame from the inverse
/// view-projection, so that each background sample costs a multiply-add and a normalisation;
/// an orthographic camera's rays all point along its forward direction.
class FilmRays {
public:
    explicit FilmRays(const CameraMatrices& cam);
    /// The unit direction through the sample at (sx, sy) (pixels times kSubpixel).
    vec3 direction(int64_t sx, int64_t sy) const {
        if (orthographic_) return c_;
        const float px = static_cast<float>(sx) / kSubpixel,
                    py = static_cast<float>(sy) / kSubpixel;
        return glm::normalize(c_ + px * a_ + py * b_);
    }

private:
    vec3 c_{0.0f}, a_{0.0f}, b_{0.0f};
    bool orthographic_ = false;
};

class ImageBasedLighting {
public:
    /// The SH projection, and the prefiltered levels and table made on `threads` threads, or
    /// taken from `cache` when it holds them for this map.
    explicit ImageBasedLighting(const Scene& scene, int threads = 0, IblCache* cache = nullptr);

    /// Whether a map is given (else the uniform background, as before).
    bool active() const { return environment_.is_map(); }
    const Environment& environment() const { return environment_; }
    /// The irradiance (W/m^2) on a surface of unit normal n, from the SH coefficients.
    Color irradiance(vec3 n) const;
    /// The glossy radiance a Cook-Torrance lobe of perceptual `roughness` and Fresnel F0
    /// `f0` (F90 `f90`) reflects toward the viewer: the prefiltered map about the mirror
    /// direction r times F0 A + F90 B at n.v (split_sum.h).
    Color glossy(vec3 r, float n_dot_v, float roughness, Color f0, float f90 = 1.0f) const;
    /// The map about the unit direction d prefiltered for a lobe of perceptual `roughness`
    /// (the glossy part's levels, without its Fresnel terms).
    Color blurred(vec3 d, float roughness) const;

    /// The map seen along the camera ray through the sample at (sx, sy) (pixels times
    /// kSubpixel) of the film `rays` describe.
    Color seen(const FilmRays& rays, int64_t sx, int64_t sy) const {
        return environment_.radiance(rays.direction(sx, sy));
    }

private:
    Environment environment_;
    IblCache::Made made_;  // with a map
};

/// The parts of image-based lighting for `scene`'s map, made afresh (IblCache keeps them).
IblCache::Made make_image_based_lighting(const Scene& scene, int threads);

/// The nine real spherical harmonics of orders 0 to 2 at the unit direction d (y up is
/// svetlo's; the basis is rotation-invariant as a whole, any axis order serves).
std::array<float, 9> sh_basis(vec3 d);

}  // namespace svetlo
