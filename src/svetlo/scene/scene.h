// The scene model: plain value structs, the same for every engine. Objects refer to
// materials and textures by index. Units: lengths in scene units (metres by convention),
// angles in degrees as in the file, radiance in W/(m^2 sr), intensity in W/sr, irradiance
// in W/m^2, all as linear RGB.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "svetlo/core/file_scope.h"
#include "svetlo/core/image.h"
#include "svetlo/core/math.h"
#include "svetlo/core/texture_image.h"

namespace svetlo {

// ---- colours and textures -----------------------------------------------------------------

enum class TextureFilter { Nearest, Bilinear, Trilinear, Anisotropic };
/// What a texture coordinate outside [0, 1] reads: the texture repeated, its edge texels, or
/// the texture repeated mirrored every other time (GL's and glTF's MIRRORED_REPEAT).
enum class TextureWrap { Repeat, Clamp, Mirror };
/// The wrap along u and along v (glTF's wrapS and wrapT); one mode converts to both.
struct TextureWraps {
    TextureWrap u = TextureWrap::Repeat, v = TextureWrap::Repeat;
    constexpr TextureWraps() = default;
    constexpr TextureWraps(TextureWrap both) : u(both), v(both) {}  // NOLINT: both axes
    constexpr TextureWraps(TextureWrap along_u, TextureWrap along_v) : u(along_u), v(along_v) {}
    bool operator==(const TextureWraps&) const = default;
};

/// What a surface point hands its material's colours besides its position: its two texture
/// coordinate sets (glTF's TEXCOORD_0 and TEXCOORD_1; a surface with one set gives it as
/// both) and its vertex colour (glTF's COLOR_0, linear RGBA; white where there is none),
/// interpolated over the triangle as the rasterizer's varyings are.
struct Varyings {
    vec2 uv[2] = {vec2(0.0f), vec2(0.0f)};
    vec4 color{1.0f};

    Varyings() = default;
    Varyings(vec2 uv0) : uv{uv0, uv0} {}  // NOLINT: one set and no vertex colour
    Varyings(vec2 uv0, vec2 uv1, vec4 c) : uv{uv0, uv1}, color(c) {}
};

/// Whether a colour is multiplied by the point's vertex colour (glTF multiplies the base
/// colour by COLOR_0's rgb, and its alpha by COLOR_0's alpha).
enum class VertexColor : unsigned char { None, Rgb, Alpha };

/// A material colour: a constant, an image texture (by index into Scene::textures) or a
/// checkerboard in texture space; times the vertex colour where `vertex_color` says so.
struct ColorSource {
    enum class Kind { Constant, Image, Checker };
    Kind kind = Kind::Constant;
    Color value{0.0f};   // Constant
    int texture = -1;    // Image
    Color factor{1.0f};  // Image: multiplies the texel (glTF's baseColorFactor, emissiveFactor)
    // Image: the texture coordinates' affine map before the lookup (KHR_texture_transform),
    // columns of a 3x3 matrix acting on (u, v, 1); identity unless `transformed`.
    mat3 uv_transform{1.0f};
    bool transformed = false;
    TextureFilter filter = TextureFilter::Bilinear;
    int max_anisotropy = 16;  // Anisotropic: trilinear probes along the footprint, at most
    TextureWraps wrap;
    Color a{0.0f}, b{1.0f};  // Checker: a where floor(scale*u) + floor(scale*v) is even
    float scale = 1.0f;
    int uv_set = 0;  // Image, Checker: the texture coordinate set read (Varyings::uv)
    VertexColor vertex_color = VertexColor::None;

    static ColorSource constant(Color c) {
        ColorSource s;
        s.value = c;
        return s;
    }
    bool is_black() const { return kind == Kind::Constant && svetlo::is_black(value); }
    /// Whether the colour changes over a surface (a texture, a checker, the vertex colour).
    bool varies() const { return kind != Kind::Constant || vertex_color != VertexColor::None; }
};

// ---- materials ----------------------------------------------------------------------------

struct LambertMaterial {
    ColorSource albedo = ColorSource::constant(Color(0.8f));
};
/// Normalised Phong (or, with blinn = true, Blinn-Phong) with optional ideal mirror and
/// transmission parts for the Whitted engine.
struct PhongMaterial {
    ColorSource ka, kd = ColorSource::constant(Color(0.8f)), ks;
    float shininess = 32.0f;
    ColorSource shininess_map = ColorSource::constant(Color(1.0f));  // its red scales shininess
    ColorSource reflect, transmit;
    float ior = 1.5f;
    bool blinn = false;
};
struct OrenNayarMaterial {
    ColorSource albedo = ColorSource::constant(Color(0.8f));
    float sigma_deg = 20.0f;  // roughness: standard deviation of the facet slope angle
};
/// A tangent-space normal map (docs/scene-format.md, "Keys of every material"): a linear
/// texture whose texel c gives the normal (2c - 1) * (scale, scale, 1), normalised, in the
/// frame of the surface's tangent, bitangent and shading normal (glTF's and OpenGL's +y).
struct NormalMap {
    ColorSource texture;  // an image, or a constant (no map)
    float scale = 1.0f;
    bool present() const { return texture.kind == ColorSource::Kind::Image; }
};

struct CookTorranceMaterial {
    ColorSource base_color = ColorSource::constant(Color(0.8f));
    float roughness = 0.5f;  // perceptual; GGX alpha = roughness^2
    float metallic = 0.0f;
    // glTF's metallicRoughness texture, linear: green scales `roughness`, blue `metallic`
    // (constant white: the factors alone).
    ColorSource metallic_roughness = ColorSource::constant(Color(1.0f));
    // glTF's occlusion texture, linear, its red channel read: it darkens the ambient and
    // environment light of the rasterizer and Whitted (1 + strength (r - 1)), nothing else.
    ColorSource occlusion = ColorSource::constant(Color(1.0f));
    float occlusion_strength = 1.0f;
    // glTF's KHR_materials_ior: the dielectric's index of refraction, which sets its F0,
    // ((ior - 1) / (ior + 1))^2 (0.04 at 1.5), and the refraction of its transmission.
    float ior = 1.5f;
    // KHR_materials_specular: the dielectric's specular strength (red channel; it scales
    // F0 and sets F90) and its F0's tint (F0 = min(F0(ior) tint, 1) strength).
    ColorSource specular = ColorSource::constant(Color(1.0f));
    ColorSource specular_color = ColorSource::constant(Color(1.0f));
    // KHR_materials_transmission: the share of the dielectric's diffuse part that is
    // transmitted instead, as ideal refraction through a smooth interface (its red channel).
    ColorSource transmission = ColorSource::constant(Color(0.0f));
    // KHR_materials_volume: what the object's inside absorbs, Beer-Lambert: light that
    // travels `attenuation_distance` (scene units; infinite: nothing absorbed) inside keeps
    // `attenuation_color` of itself.
    Color attenuation_color{1.0f};
    float attenuation_distance = kInfinity;
    // KHR_materials_clearcoat: a clear varnish over the material, its strength (red channel)
    // and its perceptual roughness (green channel, GGX alpha = roughness^2), F0 0.04.
    ColorSource clearcoat = ColorSource::constant(Color(0.0f));
    ColorSource clearcoat_roughness = ColorSource::constant(Color(0.0f));
    // The coat's own normal map (clearcoatNormalTexture); without one the coat takes the
    // interpolated normal, not the base's map (shading/normal_map.h, coat_shading_normal).
    NormalMap clearcoat_normal;
    bool has_coat() const { return clearcoat.varies() || clearcoat.value.r > 0.0f; }
};
struct MirrorMaterial {
    ColorSource reflectance = ColorSource::constant(Color(1.0f));
};
struct DielectricMaterial {
    float ior = 1.5f;   // at the sodium d line, 587.6 nm
    float abbe = 0.0f;  // Abbe number V_d for dispersion; 0 = no dispersion
};
struct EmissiveMaterial {
    ColorSource radiance = ColorSource::constant(Color(1.0f));
    ColorSource albedo;  // it also reflects diffusely (Lambert) when non-zero
};

/// How a surface reflects: one of the lecture's models.
using MaterialModel =
    std::variant<LambertMaterial, PhongMaterial, OrenNayarMaterial, CookTorranceMaterial,
                 MirrorMaterial, DielectricMaterial, EmissiveMaterial>;

/// How much of a surface is there (docs/scene-format.md, "Keys of every material"): opaque;
/// a mask, a hole wherever the coverage is below the cutoff, for every ray and every shadow
/// technique but shadow volumes; or a blend, covering that fraction of the light.
enum class AlphaMode { Opaque, Mask, Blend };
struct Alpha {
    ColorSource coverage = ColorSource::constant(Color(1.0f));  // its red channel is read
    AlphaMode mode = AlphaMode::Opaque;
    float cutoff = 0.5f;  // Mask
    bool active() const { return mode != AlphaMode::Opaque; }
};

/// A material: its reflection model, and what any model may add: `emission`, the radiance it
/// emits from its front side (W/(m^2 sr); the object is then a light, as an `emissive` one),
/// a normal map and its alpha.
struct Material {
    MaterialModel model;
    ColorSource emission;
    NormalMap normal_map;
    Alpha alpha;

    /// Whether a normal map bends one of its normals: its own, or its clear coat's (the
    /// surface then needs tangents).
    bool has_normal_map() const {
        const auto* ct = std::get_if<CookTorranceMaterial>(&model);
        return normal_map.present() || (ct && ct->clearcoat_normal.present());
    }

    Material() = default;
    template <class M>
    requires std::is_constructible_v<MaterialModel, M&&> &&
        (!std::is_same_v<std::decay_t<M>, Material>)Material(M&& m)
        : model(std::forward<M>(m)) {}  // NOLINT: a model is a material
};

// ---- lights -------------------------------------------------------------------------------

struct PointLight {
    vec3 position{0.0f};
    Color intensity{1.0f};  // W/sr
};
struct DirectionalLight {
    vec3 direction{0.0f, -1.0f, 0.0f};  // unit, the way the light travels
    Color irradiance{1.0f};             // W/m^2 on a surface facing the light
};
struct SpotLight {
    vec3 position{0.0f};
    vec3 direction{0.0f, -1.0f, 0.0f};           // unit, the cone's axis
    Color intensity{1.0f};                       // W/sr on the axis
    float inner_deg = 20.0f, outer_deg = 30.0f;  // half-angles
};
/// A one-sided emitting parallelogram; it emits toward edge_u x edge_v.
struct AreaLight {
    vec3 corner{0.0f}, edge_u{1.0f, 0.0f, 0.0f}, edge_v{0.0f, 0.0f, 1.0f};
    Color radiance{1.0f};  // W/(m^2 sr)
};

using Light = std::variant<PointLight, DirectionalLight, SpotLight, AreaLight>;

// ---- shapes -------------------------------------------------------------------------------

struct Sphere {
    vec3 center{0.0f};
    float radius = 1.0f;
};
struct Quad {
    vec3 corner{0.0f}, edge_u{1.0f, 0.0f, 0.0f}, edge_v{0.0f, 0.0f, 1.0f};
};
struct Plane {
    vec3 point{0.0f}, normal{0.0f, 1.0f, 0.0f};
};
struct Box {
    vec3 min{-0.5f}, max{0.5f};
};
/// A cylinder closed by two caps; `axis` is the height vector from the base centre.
struct Cylinder {
    vec3 base{0.0f}, axis{0.0f, 1.0f, 0.0f};
    float radius = 1.0f;
};
/// A cone closed by its base cap, radius `radius` at `base`, apex at base + axis.
struct Cone {
    vec3 base{0.0f}, axis{0.0f, 1.0f, 0.0f};
    float radius = 1.0f;
};
/// An indexed triangle mesh in object space. Triangles wind counter-clockwise seen from
/// their front. `face_material` (per triangle, an index into Scene::materials) is set when
/// the file brought its own materials.
struct Mesh {
    std::vector<vec3> positions;
    std::vector<vec3> normals;  // empty, or one per position
    std::vector<vec2> uvs;      // empty, or one per position
    std::vector<vec2> uvs1;     // a second set (glTF's TEXCOORD_1): empty, or one per position
    std::vector<vec4> colors;   // vertex colours, linear RGBA: empty, or one per position
    // Empty, or one per position: a unit tangent along increasing u in xyz, and w = +1 or -1,
    // the bitangent's side: bitangent = w * cross(normal, tangent) (glTF's TANGENT).
    std::vector<vec4> tangents;
    std::vector<uint32_t> indices;
    std::vector<int> face_material;
    bool smooth = false;

    size_t triangle_count() const { return indices.size() / 3; }
};

struct Object;

/// Constructive solid geometry: a boolean of closed children (spheres, boxes, cylinders,
/// cones, closed meshes, other CSG nodes). Difference is the first child minus the rest.
enum class CsgOp { Union, Intersection, Difference };
struct Csg {
    CsgOp op = CsgOp::Union;
    std::vector<Object> children;  // each with its own transform (relative to this node)
};

/// A node of a signed-distance (F-rep) tree: negative inside, positive outside, and
/// 1-Lipschitz (its value never exceeds the distance to the surface). Leaves are primitives;
/// union, intersection and difference take the min / max of their children, blended over
/// `smooth` (scene units) when it is positive.
enum class SdfOp {
    Sphere,
    Box,
    RoundedBox,
    Torus,
    Cylinder,
    Plane,
    Union,
    Intersection,
    Difference
};
struct SdfNode {
    SdfOp op = SdfOp::Sphere;
    // sphere: a = centre, r1 = radius; box: a = min, b = max; rounded_box: also r1 = edge
    // radius; torus: a = centre, r1 = major radius (ring in the xz plane), r2 = minor radius;
    // cylinder: a = base, b = axis (height vector), r1 = radius; plane: a = point, b = unit
    // normal pointing outside.
    vec3 a{0.0f}, b{0.0f};
    float r1 = 0.0f, r2 = 0.0f;
    float smooth = 0.0f;
    mat4 transform{1.0f};  // this node's space to its parent's
    std::vector<SdfNode> children;
};
struct Implicit {
    SdfNode root;
};

using Shape = std::variant<Sphere, Quad, Plane, Box, Cylinder, Cone, Mesh, Csg, Implicit>;

/// An affine object-to-world transform (identity when `is_identity`).
struct Transform {
    mat4 matrix{1.0f};
    bool is_identity = true;

    vec3 point(vec3 p) const { return is_identity ? p : vec3(matrix * vec4(p, 1.0f)); }
    vec3 vector(vec3 v) const { return is_identity ? v : vec3(matrix * vec4(v, 0.0f)); }
};

/// A tangent (Mesh::tangents) carried by `transform`: its direction as a vector of the
/// surface, unit again, and its sign turned where the transform mirrors (the normal, carried
/// by the inverse transpose, keeps its side; the bitangent's cross product changes hand).
inline vec4 transform_tangent(const Transform& transform, vec4 t) {
    if (transform.is_identity || t.w == 0.0f) return t;
    const vec3 d = transform.vector(vec3(t));
    const float len = glm::length(d);
    if (!(len > 0.0f)) return vec4(0.0f);
    const float det = glm::determinant(mat3(transform.matrix));
    return vec4(d / len, det < 0.0f ? -t.w : t.w);
}

struct Object {
    std::string name;  // the JSON path, objects[k], for messages
    Shape shape;
    int material = -1;  // index into Scene::materials (-1: the mesh's own per-face materials)
    Transform transform;
};

/// A prototype's objects, in its own space (docs/scene-format.md, "Instances").
struct Prototype {
    std::string name;
    std::vector<Object> objects;
};

/// One placement of a prototype: its objects carried by `transform` into the world, their
/// materials all replaced by `material` when it is >= 0. Nested prototypes are resolved when
/// the scene is read: an instance always names a prototype's own objects.
struct Instance {
    std::string name;        // the JSON path of the instance that placed it, for messages
    uint32_t prototype = 0;  // index into Scene::prototypes
    Transform transform;
    int material = -1;
};

// ---- camera, film, settings ---------------------------------------------------------------

struct Camera {
    enum class Type { Perspective, Orthographic };
    Type type = Type::Perspective;
    vec3 position{0.0f, 0.0f, 5.0f}, look_at{0.0f}, up{0.0f, 1.0f, 0.0f};
    float fov_deg = 40.0f;  // full vertical field of view (perspective)
    float height = 2.0f;    // world-space film height (orthographic)
    // A thin lens (perspective, ray-traced engines): its diameter in scene units (0 = a
    // pinhole) and the distance along the view direction that is in focus (0 = to look_at).
    float aperture = 0.0f;
    float focus_distance = 0.0f;
};

struct Film {
    int width = 512, height = 512;
};

// ---- closed sets of settings: enums, parsed once by the loader from these names ------------

template <class E>
using EnumName = std::pair<std::string_view, E>;

/// The name of `value` in `names` (for messages).
template <class E, size_t N>
std::string_view name_of(const EnumName<E> (&names)[N], E value) {
    for (const auto& [name, v] : names) {
        if (v == value) return name;
    }
    return "?";
}

/// A texture's filter and wrap mode.
inline constexpr EnumName<TextureFilter> kTextureFilters[] = {
    {"nearest", TextureFilter::Nearest},
    {"bilinear", TextureFilter::Bilinear},
    {"trilinear", TextureFilter::Trilinear},
    {"anisotropic", TextureFilter::Anisotropic}};
inline constexpr EnumName<AlphaMode> kAlphaModes[] = {
    {"opaque", AlphaMode::Opaque}, {"mask", AlphaMode::Mask}, {"blend", AlphaMode::Blend}};
inline constexpr EnumName<TextureWrap> kTextureWraps[] = {{"repeat", TextureWrap::Repeat},
                                                          {"clamp", TextureWrap::Clamp},
                                                          {"mirror", TextureWrap::Mirror}};

/// render.shading (raster): how fragments are coloured, or a debug view.
enum class ShadingMode { Flat, Gouraud, Phong, Depth, Normal, Overdraw };
inline constexpr EnumName<ShadingMode> kShadingModes[] = {
    {"flat", ShadingMode::Flat},     {"gouraud", ShadingMode::Gouraud},
    {"phong", ShadingMode::Phong},   {"depth", ShadingMode::Depth},
    {"normal", ShadingMode::Normal}, {"overdraw", ShadingMode::Overdraw}};

/// render.shadows: the rasterizer's shadow technique (the ray tracers always trace).
enum class ShadowTechnique { None, Planar, Volume, Map, Raytraced };
inline constexpr EnumName<ShadowTechnique> kShadowTechniques[] = {
    {"none", ShadowTechnique::None},
    {"planar", ShadowTechnique::Planar},
    {"volume", ShadowTechnique::Volume},
    {"map", ShadowTechnique::Map},
    {"raytraced", ShadowTechnique::Raytraced}};

/// render.shadow_map.filter.
enum class ShadowFilter { None, Pcf, Pcss };
inline constexpr EnumName<ShadowFilter> kShadowFilters[] = {
    {"none", ShadowFilter::None}, {"pcf", ShadowFilter::Pcf}, {"pcss", ShadowFilter::Pcss}};

/// render.visibility (raster): hidden surfaces by z-buffer or by the painter's algorithm.
enum class VisibilityMethod { ZBuffer, Painter };
inline constexpr EnumName<VisibilityMethod> kVisibilityMethods[] = {
    {"zbuffer", VisibilityMethod::ZBuffer}, {"painter", VisibilityMethod::Painter}};

/// render.wireframe (raster): an overlay of triangle edges, and its line algorithm.
enum class WireframeMode { None, Bresenham, Wu };
inline constexpr EnumName<WireframeMode> kWireframeModes[] = {
    {"none", WireframeMode::None},
    {"bresenham", WireframeMode::Bresenham},
    {"wu", WireframeMode::Wu}};

/// render.shadow_map (docs/shadows.md).
struct ShadowMapSettings {
    int resolution = 2048;  // texels per side of each map (a cube map's face)
    float bias = 0.002f;    // m: a receiver counts as lit up to this far behind the stored depth
    float normal_offset = 1.0f;  // texels: the lookup moves this far off the surface, along n
    float slope_bias = 1.0f;     // texels of depth per texel of offset, times tan(theta)
    ShadowFilter filter = ShadowFilter::Pcf;
    int kernel = 5;    // PCF taps per side; PCSS: taps per side of the search and the filter
    int cascades = 1;  // directional lights: maps over slices of the camera's depth range
};

/// render.shadow_volume.count: how a stencil shadow volume is counted (docs/shadows.md):
/// per light, z-fail where the camera's near plane may be inside one of its volumes and z-pass
/// elsewhere (`auto`), or always one of them.
enum class VolumeCount { Auto, ZFail, ZPass };
inline constexpr EnumName<VolumeCount> kVolumeCounts[] = {
    {"auto", VolumeCount::Auto}, {"zfail", VolumeCount::ZFail}, {"zpass", VolumeCount::ZPass}};

/// Switches for the shadow techniques' teaching pictures (docs/shadows.md): the defaults are
/// the robust forms, and the others show what goes wrong without them.
struct ShadowTeachingSettings {
    VolumeCount volume_count = VolumeCount::Auto;  // z-pass fails with the camera in a volume
    bool planar_clip = true;  // clip occluders to the slab between receiver and light
};

/// Settings of the rasterizer (svetlo extensions, docs/raster.md).
struct RasterSettings {
    VisibilityMethod visibility = VisibilityMethod::ZBuffer;
    bool cull_back_faces = false;  // docs/scene-format.md: surfaces are two-sided by default
    bool msaa = false;             // false: supersampling (shade every sample)
    WireframeMode wireframe = WireframeMode::None;
    Color wireframe_color{1.0f};
    int tessellation = 64;  // segments around spheres, cylinders and cones
};

/// render.caustics (path): the caustics found by photons (docs/path.md). `auto` sends photons
/// from point, spot and directional lights only, whose caustics no path tracer can find;
/// `photons` from every light, and the path tracer then leaves those paths to the photons.
enum class CausticMode { Auto, Photons, None };
inline constexpr EnumName<CausticMode> kCausticModes[] = {
    {"auto", CausticMode::Auto}, {"photons", CausticMode::Photons}, {"none", CausticMode::None}};

/// render.mis (path): how direct light is found at each vertex. `power` combines light and BSDF
/// sampling by the power heuristic; `light` and `bsdf` use one strategy alone, to show what
/// MIS gains (docs/path.md). Delta lights are always sampled, and the background, a light too,
/// follows the same choice.
enum class MisMode { Power, LightOnly, BsdfOnly };
inline constexpr EnumName<MisMode> kMisModes[] = {
    {"power", MisMode::Power}, {"light", MisMode::LightOnly}, {"bsdf", MisMode::BsdfOnly}};

/// render.photons (path): probabilistic progressive photon mapping (Knaus and Zwicker 2011),
/// a photon map per pass whose radius shrinks as r_{k+1}^2 = r_k^2 (k + alpha) / (k + 1).
struct PhotonSettings {
    int count = 100000;         // photons emitted per pass
    float radius = 0.0f;        // first pass's gather radius, scene units; 0 = 1/500 of the
                                // scene's diameter
    float alpha = 2.0f / 3.0f;  // in (0, 1): how fast the radius shrinks
};

/// render.radiosity (docs/radiosity.md): the patch mesh, the form factors, the solver and the
/// display of the radiosity engine.
enum class FormFactorMethod { Analytic, Raycast, Hemicube };
inline constexpr EnumName<FormFactorMethod> kFormFactorMethods[] = {
    {"analytic", FormFactorMethod::Analytic},
    {"raycast", FormFactorMethod::Raycast},
    {"hemicube", FormFactorMethod::Hemicube}};
enum class RadiositySolver { Auto, Progressive, Jacobi, GaussSeidel, Hierarchical };
inline constexpr EnumName<RadiositySolver> kRadiositySolvers[] = {
    {"auto", RadiositySolver::Auto},
    {"progressive", RadiositySolver::Progressive},
    {"jacobi", RadiositySolver::Jacobi},
    {"gauss_seidel", RadiositySolver::GaussSeidel},
    {"hierarchical", RadiositySolver::Hierarchical}};
enum class RadiosityDisplay { Gouraud, Gather };
inline constexpr EnumName<RadiosityDisplay> kRadiosityDisplays[] = {
    {"gouraud", RadiosityDisplay::Gouraud}, {"gather", RadiosityDisplay::Gather}};

struct RadiositySettings {
    float patch_size = 0.0f;    // m, the shooters' longest edge; 0 = 1/8 of the scene's
                                // diameter, or element_size where that is larger
    float element_size = 0.0f;  // m, the receivers' longest edge; 0 = half the patch size
    FormFactorMethod form_factors = FormFactorMethod::Analytic;
    int samples = 4;     // visibility rays per form factor (source points for raycast)
    int hemicube = 128;  // a hemicube face's side, in cells
    // auto: hierarchical where the scene has few enough triangles to link them pairwise,
    // else progressive
    RadiositySolver solver = RadiositySolver::Auto;
    float tolerance = 1e-3f;     // stop when the residual power falls below this fraction
    int max_iterations = 0;      // 0 = no limit but the tolerance (sweeps or shots)
    float adaptive = 1.0f;       // split elements whose direct light varies more than this
                                 // fraction of its mean (0 = uniform elements)
    int max_subdivision = 3;     // the adaptive and hierarchical splits below an element
    float link_epsilon = 3e-4f;  // hierarchical: a link's estimated rho F B, relative to the
                                 // brightest emitter's B, above which it is refined
    RadiosityDisplay display = RadiosityDisplay::Gouraud;
    bool ambient_term = true;          // progressive: show the unshot light as an ambient term
    int form_factor_cache_mib = 1024;  // progressive: memory for the shooters' rows, MiB
    int max_links = 1 << 26;           // hierarchical: links at most (16 bytes each: 1 GiB)
};

struct RenderSettings {
    std::string engine = "whitted";  // an open set: engines are made by name (apps/svetlo)
    int spp = 1;
    int max_depth = 5;
    uint64_t seed = 0;
    ShadingMode shading = ShadingMode::Phong;
    ShadowTechnique shadows = ShadowTechnique::Raytraced;
    ShadowMapSettings shadow_map;
    Color ambient{0.0f};
    Color background{0.0f};
    float exposure = 1.0f;
    std::string accel = "bvh";    // none, grid, octree, bvh2, bvh (wide), embree
    int light_samples = 1;        // shadow rays per area light and shading point
    int area_shadow_points = 16;  // raster map and volume: point casters per light with area
    int area_light_points = 64;   // raster: VPLs per light with area (shading, raytraced shadows)
    ShadowTeachingSettings shadow_teaching;
    RasterSettings raster;
    CausticMode caustics = CausticMode::Auto;
    PhotonSettings photons;
    MisMode mis = MisMode::Power;
    bool guiding = false;  // path: path guiding (docs/path.md, "Path guiding")
    RadiositySettings radiosity;
};

/// The top-level `environment` (docs/scene-format.md, "environment"): an equirectangular map
/// of linear radiance, the radiance of every ray that leaves the scene and a light.
struct EnvironmentSettings {
    int texture = -1;         // index into Scene::textures (float texels)
    Color scale{1.0f};        // multiplies every texel
    float rotate_deg = 0.0f;  // the map turned about +y
};

struct Scene {
    std::filesystem::path path;  // the scene file, for messages and relative paths
    FileScope files;             // where the files it names may lie
    Camera camera;
    Film film;
    RenderSettings render;
    std::vector<Material> materials;
    std::vector<std::string> material_names;
    std::vector<TextureImage> textures;  // 8-bit or float texels, rows from the top
    // Per texture, the file and colour space it was read from: each is read once, however
    // many materials use it.
    std::vector<std::string> texture_sources;
    std::vector<Light> lights;
    std::vector<Object> objects;
    std::optional<EnvironmentSettings> environment;  // in place of render.background
    /// What the shapes are made of (the objects, the area lights, the materials' order, the
    /// mesh files' sizes and times): scenes with equal keys make the same geometry, so that
    /// the renders of one command can share one BVH (geometry/accel_cache.h).
    std::string geometry_key;
    /// What a mesh file had that svetlo left out (an optional glTF extension), a line each,
    /// naming the key and the file: the command line prints them as warnings.
    std::vector<std::string> warnings;
    /// The prototypes that instances place, and the placements. The ray tracers trace them
    /// as a two-level structure; the rasterizer and radiosity draw them as copies
    /// (instance_copies, scene/instances.h). An instance whose prototype holds an emitter, an
    /// infinite plane or an implicit surface is written into `objects` as copies instead (the light
    /// set samples emitters in world space): `copied_objects` counts those.
    std::vector<Prototype> prototypes;
    std::vector<Instance> instances;
    size_t copied_objects = 0;
    /// The mesh files' glTF extensions (what `svetlo info` reports).
    std::vector<std::string> extensions;
};

}  // namespace svetlo
