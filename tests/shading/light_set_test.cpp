// The light set against closed forms: the irradiance its samples estimate, their pdfs, and
// which objects are lights.
#include "svetlo/shading/light_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/rng.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

json base() {
    return {{"camera", {{"position", {0, 1, 5}}, {"look_at", {0, 1, 0}}}},
            {"materials",
             {{"white", {{"type", "lambert"}, {"albedo", 0.5}}},
              {"glow", {{"type", "emissive"}, {"radiance", 2}}}}},
            {"lights", json::array()},
            {"objects", json::array()}};
}

/// Irradiance at p (normal n) from a uniform emitter of radiance L over the polygon `v`, seen
/// from its front: Lambert's formula, E = L/2 sum_i gamma_i n . unit(v_i x v_i+1).
float polygon_irradiance(vec3 p, vec3 n, const std::vector<vec3>& v, float L) {
    double sum = 0.0;
    for (size_t i = 0; i < v.size(); ++i) {
        vec3 a = glm::normalize(v[i] - p), b = glm::normalize(v[(i + 1) % v.size()] - p);
        double gamma = std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f));
        sum += gamma * glm::dot(n, glm::normalize(glm::cross(a, b)));
    }
    return static_cast<float>(std::abs(0.5 * L * sum));
}

/// The mean of E cos(theta) over n samples of source k: an estimate of the irradiance at p.
double estimate(const LightSet& lights, size_t k, vec3 p, vec3 n, int count) {
    Rng rng(7, 3);
    double sum = 0.0;
    for (int i = 0; i < count; ++i) {
        vec2 u = rng.next_2d();
        LightSample s = lights.sample(lights.sources()[k], p, u, rng.next_float());
        sum += s.irradiance.r * std::max(0.0f, glm::dot(n, s.wi));
    }
    return sum / count;
}

TEST(LightSet, AreaLightSamplesEstimateLambertsPolygonFormula) {
    json j = base();
    j["lights"] = {{{"type", "area"},
                    {"corner", {-0.5, 2, -0.5}},
                    {"edge_u", {1, 0, 0}},
                    {"edge_v", {0, 0, 1}},
                    {"radiance", 3}}};
    Scene scene = scene_from_json(j, "t.json");
    LightSet lights(scene);
    ASSERT_EQ(lights.sources().size(), 1u);
    EXPECT_FALSE(lights.sources()[0].delta);
    EXPECT_EQ(lights.sources()[0].light_index, 0);
    EXPECT_FLOAT_EQ(lights.sources()[0].area, 1.0f);
    // edge_u x edge_v = (0, 0, 1) x ... = -y: it shines down, onto the floor.
    std::vector<vec3> quad = {vec3(-0.5f, 2, -0.5f), vec3(0.5f, 2, -0.5f), vec3(0.5f, 2, 0.5f),
                              vec3(-0.5f, 2, 0.5f)};
    for (vec3 p : {vec3(0.0f), vec3(0.7f, 0.3f, -0.2f)}) {
        float exact = polygon_irradiance(p, vec3(0, 1, 0), quad, 3.0f);
        EXPECT_NEAR(estimate(lights, 0, p, vec3(0, 1, 0), 200000), exact, 0.01 * exact);
    }
    // Seen from above, the light shows its back: nothing.
    EXPECT_EQ(estimate(lights, 0, vec3(0, 3, 0), vec3(0, -1, 0), 100), 0.0);
    // The visible quad carries its own emissive material.
    ASSERT_EQ(lights.area_light_quads().size(), 1u);
    EXPECT_EQ(lights.materials().size(), scene.materials.size() + 1);
}

TEST(LightSet, EmissiveMeshTrianglesEstimateLambertsPolygonFormulaFromBothWindings) {
    // A unit square at y = 2 as two triangles, shining down; then the same square wound the
    // other way, which shines up. The triangles' kept normals (sample_area) must be each
    // triangle's front normal.
    std::vector<vec3> square = {vec3(-0.5f, 2, -0.5f), vec3(0.5f, 2, -0.5f), vec3(0.5f, 2, 0.5f),
                                vec3(-0.5f, 2, 0.5f)};
    for (bool down : {true, false}) {
        json j = base();
        json indices = down ? json{0, 1, 2, 0, 2, 3} : json{0, 2, 1, 0, 3, 2};
        j["objects"] = {
            {{"type", "mesh"},
             {"positions", {{-0.5, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5}, {-0.5, 2, 0.5}}},
             {"indices", indices},
             {"material", "glow"}}};
        Scene scene = scene_from_json(j, "t.json");
        LightSet lights(scene);
        ASSERT_EQ(lights.sources().size(), 1u);
        const LightSet::Source& mesh = lights.sources()[0];
        ASSERT_EQ(mesh.normals.size(), 2u);
        EXPECT_FLOAT_EQ(mesh.area, 1.0f);
        // Its two faces lie in one plane: sampled by area over both, as any quad light.
        EXPECT_TRUE(mesh.faces.empty());
        vec3 p = down ? vec3(0.7f, 0.3f, -0.2f) : vec3(0.7f, 3.7f, -0.2f);
        vec3 n(0.0f, down ? 1.0f : -1.0f, 0.0f);
        float exact = polygon_irradiance(p, n, square, 2.0f);
        EXPECT_NEAR(estimate(lights, 0, p, n, 200000), exact, 0.01 * exact) << down;
        // From the other side it shows its back.
        EXPECT_EQ(estimate(lights, 0, vec3(p.x, 4.0f - p.y, p.z), -n, 100), 0.0) << down;
    }
}

TEST(LightSet, EmissiveSphereGivesPiLTimesTheSolidAngleFactor) {
    json j = base();
    j["objects"] = {
        {{"type", "sphere"}, {"center", {0, 3, 0}}, {"radius", 0.5}, {"material", "glow"}},
        {{"type", "sphere"}, {"center", {5, 0, 0}}, {"radius", 1}, {"material", "white"}}};
    Scene scene = scene_from_json(j, "t.json");
    LightSet lights(scene);
    ASSERT_EQ(lights.sources().size(), 1u);  // the white sphere is no light
    EXPECT_EQ(lights.sources()[0].light_index, -1);
    // A surface facing the sphere's centre from distance d: E = pi L (R / d)^2.
    float exact = kPi * 2.0f * 0.25f / 9.0f;
    EXPECT_NEAR(estimate(lights, 0, vec3(0.0f), vec3(0, 1, 0), 400000), exact, 0.01 * exact);
}

TEST(LightSet, SamplePdfMatchesPdfAndIntegratesToOne) {
    json j = base();
    j["objects"] = {{{"type", "box"},
                     {"min", {-0.3, 2, -0.2}},
                     {"max", {0.4, 2.5, 0.3}},
                     {"material", "glow"}}};
    Scene scene = scene_from_json(j, "t.json");
    LightSet lights(scene);
    const LightSet::Source& box = lights.sources().at(0);
    EXPECT_NEAR(box.area, 2.0f * (0.7f * 0.5f + 0.5f * 0.5f + 0.7f * 0.5f), 1e-5f);
    Rng rng(1, 2);
    vec3 p(0.1f, 0.0f, 0.05f);
    double solid_angle = 0.0;  // E[1 / pdf] over directions that reach the light's front
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        LightSample s = lights.sample(box, p, rng.next_2d(), rng.next_float());
        if (s.pdf <= 0.0f || is_black(s.irradiance)) continue;
        EXPECT_NEAR(lights.pdf(box, p, s.p, s.n), s.pdf, 1e-4f * s.pdf);
        solid_angle += 1.0 / s.pdf;
    }
    // The box seen from p covers the solid angle of its bottom face (the only face it sees),
    // here by a fine quadrature of the face: d omega = cos' dA / d^2.
    double omega = 0.0;
    const int g = 400;
    for (int a = 0; a < g; ++a) {
        for (int b = 0; b < g; ++b) {
            vec3 q(-0.3f + 0.7f * (a + 0.5f) / g, 2.0f, -0.2f + 0.5f * (b + 0.5f) / g);
            vec3 d = q - p;
            float d2 = glm::dot(d, d);
            omega += (0.7 * 0.5 / (g * g)) * (d.y / std::sqrt(d2)) / d2;
        }
    }
    EXPECT_NEAR(solid_angle / n, omega, 0.01 * omega);
}

TEST(LightSet, BoxLightsAreSampledOverTheFacesAPointSeesFront) {
    // A box lamp, upright and turned 30 degrees about y; seen from a point below and to the
    // side, it shows its bottom and two sides. Every sample must land on a face whose
    // front the point sees, each face taking its share A h / sum(A h) of them (area times the
    // point's height over it), with the pdf pdf() gives, and the samples' mean must be the
    // sum of those faces' polygon irradiances (Lambert's formula).
    for (float degrees : {0.0f, 30.0f}) {
        json j = base();
        j["objects"] = {{{"type", "box"},
                         {"min", {-0.2, -0.1, -0.15}},
                         {"max", {0.2, 0.1, 0.15}},
                         {"transform", {{"rotate", {degrees, 0, 1, 0}}, {"translate", {0, 2, 0}}}},
                         {"material", "glow"}}};
        Scene scene = scene_from_json(j, "t.json");
        LightSet lights(scene);
        const LightSet::Source& box = lights.sources().at(0);
        ASSERT_EQ(box.faces.size(), 6u) << degrees;
        // The box's corners in world space, and its six faces as polygons seen from outside.
        const mat4 to_world = scene.objects[0].transform.matrix;
        auto corner = [&](int i) {
            vec3 c(i & 1 ? 0.2f : -0.2f, i & 2 ? 0.1f : -0.1f, i & 4 ? 0.15f : -0.15f);
            return vec3(to_world * vec4(c, 1.0f));
        };
        const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                 {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
        const vec3 p(0.9f, 0.6f, 0.4f), n = glm::normalize(vec3(-0.9f, 1.4f, -0.4f));
        double exact = 0.0, weight = 0.0;
        std::vector<vec3> front;       // the outward normals of the faces p sees
        std::vector<double> expected;  // and their share of samples, A h / sum(A h)
        for (const auto& f : faces) {
            std::vector<vec3> v = {corner(f[0]), corner(f[1]), corner(f[2]), corner(f[3])};
            const vec3 edge_u = v[1] - v[0], edge_v = v[3] - v[0];
            vec3 outward = glm::normalize(glm::cross(edge_u, edge_v));
            const float height = glm::dot(outward, p - v[0]);
            if (height <= 0.0f) continue;
            front.push_back(outward);
            expected.push_back(glm::length(glm::cross(edge_u, edge_v)) * height);
            weight += expected.back();
            exact += polygon_irradiance(p, n, v, 2.0f);
        }
        ASSERT_EQ(front.size(), 3u);
        Rng rng(5, 9);
        const int count = 20000;
        std::vector<int> landed(front.size(), 0);
        for (int i = 0; i < count; ++i) {
            LightSample s = lights.sample(box, p, rng.next_2d(), rng.next_float());
            ASSERT_FALSE(is_black(s.irradiance));
            auto on = std::find_if(front.begin(), front.end(),
                                   [&](vec3 f) { return glm::dot(f, s.n) > 0.9999f; });
            ASSERT_NE(on, front.end()) << "a sample on a face p does not see";
            ++landed[static_cast<size_t>(on - front.begin())];
            EXPECT_NEAR(lights.pdf(box, p, s.p, s.n), s.pdf, 1e-4f * s.pdf);
        }
        for (size_t f = 0; f < front.size(); ++f) {  // each face's share, within 4 sigma
            const double share = expected[f] / weight;
            EXPECT_NEAR(landed[f], count * share, 4.0 * std::sqrt(count * share * (1 - share)))
                << degrees << " " << f;
        }
        EXPECT_NEAR(estimate(lights, 0, p, n, 200000), exact, 0.01 * exact) << degrees;
        // Right under it, only the bottom shows: its points have the density of the bottom's
        // area alone, 0.4 x 0.3 m^2, per solid angle d^2 / (cos' A).
        const vec3 below(0.0f, 1.0f, 0.0f), centre(0.0f, 1.9f, 0.0f);
        EXPECT_NEAR(lights.pdf(box, below, centre, vec3(0, -1, 0)), 0.81f / 0.12f, 1e-4f)
            << degrees;
    }
}

TEST(LightSet, MeshLightsAreSampledOverTheTrianglesAPointSeesFromBothWindings) {
    // A roof of two slopes, each two triangles, ridge along z at y = 2.2. Wound outward, a
    // point off to the right and just above the eaves sees the right slope's front alone;
    // wound inward, a point under the roof sees both slopes' fronts. The samples must land on
    // those slopes only, and their mean be the slopes' polygon irradiance.
    const std::vector<vec3> left = {vec3(-0.5f, 2, -0.5f), vec3(-0.5f, 2, 0.5f),
                                    vec3(0, 2.2f, 0.5f), vec3(0, 2.2f, -0.5f)};
    const std::vector<vec3> right = {vec3(0, 2.2f, -0.5f), vec3(0, 2.2f, 0.5f), vec3(0.5f, 2, 0.5f),
                                     vec3(0.5f, 2, -0.5f)};
    for (bool outward : {true, false}) {
        json j = base();
        // Vertices 0-3 the left slope, 4-7 the right one, in the order above.
        json positions = json::array();
        for (const auto* slope : {&left, &right}) {
            for (vec3 v : *slope) positions.push_back({v.x, v.y, v.z});
        }
        json indices = json::array();
        for (int base_vertex : {0, 4}) {
            const int a = base_vertex, b = a + 1, c = a + 2, d = a + 3;
            // Counter-clockwise seen from above the roof: a, b, c then a, c, d.
            for (int v :
                 outward ? std::vector<int>{a, b, c, a, c, d} : std::vector<int>{a, c, b, a, d, c})
                indices.push_back(v);
        }
        j["objects"] = {{{"type", "mesh"},
                         {"positions", positions},
                         {"indices", indices},
                         {"material", "glow"}}};
        Scene scene = scene_from_json(j, "t.json");
        LightSet lights(scene);
        const LightSet::Source& roof = lights.sources().at(0);
        ASSERT_EQ(roof.faces.size(), 4u) << outward;
        const vec3 p = outward ? vec3(1.5f, 2.3f, 0.1f) : vec3(0.3f, 1.0f, 0.1f);
        const vec3 n = glm::normalize((outward ? vec3(0.25f, 2.1f, 0) : vec3(0, 2.1f, 0)) - p);
        const float exact =
            outward ? polygon_irradiance(p, n, right, 2.0f)
                    : polygon_irradiance(p, n, left, 2.0f) + polygon_irradiance(p, n, right, 2.0f);
        Rng rng(3, 4);
        for (int i = 0; i < 2000; ++i) {
            LightSample s = lights.sample(roof, p, rng.next_2d(), rng.next_float());
            ASSERT_FALSE(is_black(s.irradiance)) << outward;
            ASSERT_GT(glm::dot(s.n, p - s.p), 0.0f) << "a sample on a face p does not see";
            if (outward) {
                EXPECT_GT(s.p.x, 0.0f) << "a sample on the left slope";
            }
            EXPECT_NEAR(lights.pdf(roof, p, s.p, s.n), s.pdf, 1e-4f * s.pdf);
        }
        EXPECT_NEAR(estimate(lights, 0, p, n, 200000), exact, 0.01 * exact) << outward;
    }
}

TEST(LightSet, EmitterWithManyFacesIsSampledByAreaOverAll) {
    // Past LightSet::kMaxFacingFaces triangles, a light keeps the one area CDF: no faces.
    json j = base();
    json positions = json::array(), indices = json::array();
    for (int k = 0; k <= 9; ++k) {
        positions.push_back({0.1 * k, 2, 0});
        positions.push_back({0.1 * k, 2, 1});
    }
    for (int k = 0; k < 9; ++k) {
        for (int v : {2 * k, 2 * k + 2, 2 * k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3})
            indices.push_back(v);
    }
    j["objects"] = {
        {{"type", "mesh"}, {"positions", positions}, {"indices", indices}, {"material", "glow"}}};
    Scene scene = scene_from_json(j, "t.json");
    LightSet lights(scene);
    EXPECT_EQ(lights.sources().at(0).normals.size(), 18u);
    EXPECT_TRUE(lights.sources().at(0).faces.empty());
}

TEST(LightSet, CsgAndImplicitEmittersGlowButAreNoLights) {
    json j = base();
    json sphere = {{"type", "sphere"}, {"center", {0, 2, 0}}, {"radius", 0.5}};
    j["objects"] = {
        {{"type", "csg"}, {"op", "union"}, {"children", {sphere}}, {"material", "glow"}},
        {{"type", "implicit"},
         {"sdf", {{"op", "sphere"}, {"center", {0, 2, 0}}, {"radius", 0.5}}},
         {"material", "glow"}}};
    EXPECT_TRUE(LightSet(scene_from_json(j, "t.json")).sources().empty());
}

TEST(LightSet, EmittersItCannotSampleAreRefusedWithTheirPlace) {
    json j = base();
    j["objects"] = {
        {{"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 1, 0}}, {"material", "glow"}}};
    try {
        LightSet lights(scene_from_json(j, "t.json"));
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "objects[0]");
    }
    j["objects"] = {{{"type", "sphere"},
                     {"center", {0, 0, 0}},
                     {"radius", 1},
                     {"material", "glow"},
                     {"transform", {{"scale", {1, 2, 1}}}}}};
    EXPECT_THROW(LightSet(scene_from_json(j, "t.json")), Error);
    // A quad is baked into world space: any transform will do.
    j["objects"] = {{{"type", "quad"},
                     {"corner", {0, 0, 0}},
                     {"edge_u", {1, 0, 0}},
                     {"edge_v", {0, 0, 1}},
                     {"material", "glow"},
                     {"transform", {{"scale", {1, 2, 3}}}}}};
    EXPECT_EQ(LightSet(scene_from_json(j, "t.json")).sources().size(), 1u);
}

}  // namespace
}  // namespace svetlo

namespace svetlo {
namespace {

// A textured emitter is sampled by the power each triangle emits (LightSet::weigh_by_power):
// a square of two triangles whose emission texture is bright under one and dark under the
// other, seen from below. Each triangle's share of the samples is its power's, each sample's
// pdf is pdf()'s for its triangle, and the mean estimates Lambert's polygon formula.
TEST(LightSet, ATexturedEmitterIsSampledByThePowerEachTriangleEmits) {
    const std::filesystem::path texture =
        std::filesystem::temp_directory_path() / "svetlo_light_set_emission.png";
    Image im(2, 1);
    im.at(0, 0) = Color(1.0f);
    im.at(1, 0) = Color(0.02f);  // code 5: 0.0196
    write_image(texture, im, PixelMeaning::Data, 1.0f, "test");
    json j = base();
    j["materials"]["tex"] = {{"type", "lambert"},
                             {"albedo", 0},
                             {"emission",
                              {{"texture", texture.string()},
                               {"filter", "nearest"},
                               {"wrap", "clamp"},
                               {"srgb", false}}}};
    // Triangle A (x + z < 0) reads the left texel, B the right; both face down (-y).
    j["objects"] = {{{"type", "mesh"},
                     {"positions",
                      {-0.5, 2, -0.5, 0.5, 2, -0.5, -0.5, 2, 0.5,  // A
                       0.5, 2, -0.5, 0.5, 2, 0.5, -0.5, 2, 0.5}},  // B
                     {"uvs", {0.1, 0.1, 0.4, 0.1, 0.1, 0.4, 0.9, 0.9, 0.6, 0.9, 0.9, 0.6}},
                     {"indices", {0, 1, 2, 3, 4, 5}},
                     {"material", "tex"}}};
    Scene scene = scene_from_json(j, "t.json");
    LightSet lights(scene);
    ASSERT_EQ(lights.sources().size(), 1u);
    const LightSet::Source& src = lights.sources()[0];
    ASSERT_EQ(src.pdf_area.size(), 2u);
    const float bright = 1.0f, dark = 5.0f / 255.0f;
    // Equal areas: the shares are the luminances' (plus the floor of 1e-3 of the mean).
    const double floor = 1e-3 * (bright + dark) / 2,
                 share_a = (bright + floor) / (bright + dark + 2 * floor);
    const vec3 p(0.3f, 0.0f, 0.2f), n(0.0f, 1.0f, 0.0f);
    Rng rng(11, 0);
    const int count = 40000;
    int on_a = 0;
    double sum = 0.0;
    for (int k = 0; k < count; ++k) {
        const LightSample s = lights.sample(src, p, rng.next_2d(), rng.next_float());
        const bool a = s.p.x + s.p.z < 0.0f;
        on_a += a;
        EXPECT_NEAR(lights.pdf(src, p, s.p, s.n, src.prims[a ? 0 : 1]), s.pdf, 1e-4f * s.pdf);
        sum += s.irradiance.r * std::max(0.0f, glm::dot(n, s.wi));
    }
    const double sigma = std::sqrt(share_a * (1 - share_a) / count);
    EXPECT_NEAR(on_a / static_cast<double>(count), share_a, 4 * sigma);
    const float exact =
        polygon_irradiance(p, n, {{-0.5f, 2, -0.5f}, {0.5f, 2, -0.5f}, {-0.5f, 2, 0.5f}}, bright) +
        polygon_irradiance(p, n, {{0.5f, 2, -0.5f}, {0.5f, 2, 0.5f}, {-0.5f, 2, 0.5f}}, dark);
    EXPECT_NEAR(sum / count, exact, 0.01 * exact);
    // By area, half the samples would fall on the dark triangle.
    EXPECT_GT(on_a, 0.95 * count);
    std::filesystem::remove(texture);
}

}  // namespace
}  // namespace svetlo
