// Instances (docs/scene-format.md, "Instances"): a prototype's objects placed by each
// instance's transform render as the same objects written out, in every engine, bit for bit;
// nested prototypes compose their transforms; a material given to an instance replaces its
// objects'; an unknown prototype and a cycle of prototypes are refused naming the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <glm/gtc/type_ptr.hpp>

#include "render_json.h"
#include "svetlo/core/error.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/radiosity/radiosity_engine.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

json base(const char* engine) {
    return {{"camera", {{"position", {0, 2, 8}}, {"look_at", {0, 0, 0}}, {"fov", 40}}},
            {"film", {{"width", 24}, {"height", 16}}},
            {"render",
             {{"engine", engine},
              {"spp", 2},
              {"max_depth", 2},
              {"tessellation", 12},
              {"radiosity", {{"element_size", 0.5}}}}},
            {"materials",
             {{"red", {{"type", "lambert"}, {"albedo", {0.8, 0.2, 0.2}}}},
              {"grey", {{"type", "lambert"}, {"albedo", 0.5}}}}},
            {"lights", {{{"type", "point"}, {"position", {0, 5, 5}}, {"intensity", 40}}}}};
}

json translate(float x, float y) { return {{"translate", {x, y, 0}}}; }

/// A tree of a box on a sphere, as a prototype placed three times (one of them in a nested
/// prototype, one in grey), or written out.
json forest(const char* engine, bool instanced) {
    json j = base(engine);
    const json sphere = {
        {"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.5}, {"material", "red"}};
    const json box = {
        {"type", "box"}, {"min", {-0.2, 0.5, -0.2}}, {"max", {0.2, 1.2, 0.2}}, {"material", "red"}};
    if (instanced) {
        j["prototypes"] = {
            {"tree", {{"objects", {sphere, box}}}},
            {"grove",
             {{"objects",
               {{{"type", "instance"}, {"prototype", "tree"}, {"transform", translate(2, 0)}}}}}}};
        j["objects"] = {
            {{"type", "instance"}, {"prototype", "tree"}, {"transform", translate(-2, 0)}},
            {{"type", "instance"}, {"prototype", "tree"}, {"material", "grey"}},
            {{"type", "instance"}, {"prototype", "grove"}, {"transform", translate(0, -1)}}};
        return j;
    }
    j["objects"] = json::array();
    auto place = [&](json o, float x, float y, const char* material) {
        if (x != 0.0f || y != 0.0f) o["transform"] = translate(x, y);
        o["material"] = material;
        j["objects"].push_back(o);
    };
    for (const json& o : {sphere, box}) place(o, -2, 0, "red");
    for (const json& o : {sphere, box}) place(o, 0, 0, "grey");
    for (const json& o : {sphere, box}) place(o, 2, -1, "red");
    return j;
}

/// The rasterizer and radiosity draw instances as copies: bit for bit the objects written
/// out (in the same order). The ray tracers trace each instance in its prototype's space,
/// where the ray's origin and the hit point round differently by an ulp: pixels differ in
/// their last bits, and a ray that grazes an edge may pass on the other side, so
/// `edge_pixels` pixels in a hundred may differ by more than a thousandth.
template <class Engine>
void expect_same(const json& placed, const json& written, const char* engine, size_t edge_pixels) {
    const RenderResult a = render_json<Engine>(placed);
    const RenderResult b = render_json<Engine>(written);
    ASSERT_EQ(a.color.pixels.size(), b.color.pixels.size());
    size_t differ = 0;
    double sum_a = 0.0, sum_b = 0.0;
    for (size_t k = 0; k < a.color.pixels.size(); ++k) {
        const Color d = glm::abs(a.color.pixels[k] - b.color.pixels[k]);
        const float scale =
            edge_pixels == 0 ? 0.0f : 1e-3f * (1e-3f + max_component(b.color.pixels[k]));
        differ += max_component(d) > scale;
        sum_a += a.color.pixels[k].r;
        sum_b += b.color.pixels[k].r;
    }
    EXPECT_LE(differ * 100, edge_pixels * a.color.pixels.size()) << engine;
    EXPECT_NEAR(sum_a, sum_b, edge_pixels == 0 ? 0.0 : 0.01 * sum_b) << engine;
    EXPECT_GT(sum_a, 0.0) << engine;  // the objects are there
}

template <class Engine>
void expect_same_as_written_out(const char* engine, size_t edge_pixels) {
    expect_same<Engine>(forest(engine, true), forest(engine, false), engine, edge_pixels);
}

TEST(Instances, RenderAsTheirObjectsWrittenOutInEveryEngine) {
    expect_same_as_written_out<RasterRenderer>("raster", 0);
    expect_same_as_written_out<RadiosityRenderer>("radiosity", 0);
    expect_same_as_written_out<WhittedRenderer>("whitted", 1);
    expect_same_as_written_out<PathRenderer>("path", 1);
}

/// The rasterizer draws instances in place (raster/placed_draws.h): a visibility pass of every
/// placement, then the colour pass of the triangles it found. The frame is the objects written
/// out, bit for bit, in every shading mode and shadow technique, over two sample passes
/// (20 spp), with blended alpha, on one thread and two. (The placements here
/// are translations, whose boxes are the triangles' own: shadow maps, fitted to the placements'
/// boxes, are then the same maps.)
TEST(Instances, TheRasterizerDrawsThemAsTheObjectsWrittenOut) {
    for (const char* shading : {"flat", "gouraud", "phong"}) {
        for (const char* shadows : {"none", "raytraced", "map", "volume", "planar"}) {
            for (int spp : {1, 20}) {
                json placed = forest("raster", true), written = forest("raster", false);
                for (json* j : {&placed, &written}) {
                    (*j)["render"]["shading"] = shading;
                    (*j)["render"]["shadows"] = shadows;
                    (*j)["render"]["spp"] = spp;
                }
                const std::string what =
                    std::string(shading) + " " + shadows + " " + std::to_string(spp) + " spp";
                expect_same<RasterRenderer>(placed, written, what.c_str(), 0);
            }
        }
    }
    // Blended alpha: a coin per sample and triangle, the triangle as the scene numbers it, so
    // the colour pass keeps the samples the visibility pass kept. (Shadow rays toss coins of
    // their own at a blended occluder, per primitive of the structure they trace, and a
    // placement's primitives are its prototype's: under ray-traced shadows the frame is the
    // copies' in the mean, its shadows' noise drawn anew.)
    for (const char* shadows : {"raytraced", "map", "volume", "planar"}) {
        json placed = forest("raster", true), written = forest("raster", false);
        for (json* j : {&placed, &written}) {
            (*j)["materials"]["red"]["alpha"] = 0.5;
            (*j)["materials"]["red"]["alpha_mode"] = "blend";
            (*j)["render"]["shadows"] = shadows;
            (*j)["render"]["spp"] = 8;
        }
        expect_same<RasterRenderer>(placed, written, shadows,
                                    std::string(shadows) == "raytraced" ? 5 : 0);
    }
    const RenderResult one = render_json<RasterRenderer>(forest("raster", true), 1);
    const RenderResult two = render_json<RasterRenderer>(forest("raster", true), 2);
    EXPECT_EQ(one.color.pixels, two.color.pixels);
}

/// Shadows cast and received by placements alone: a ground (a quad, placed turned and
/// scaled) under two balls of one prototype, one mirrored. The rasterizer's frame in place is
/// the objects written out, bit for bit, under every shadow technique: a placed quad is a
/// planar receiver, a placed ball casts a volume from its own adjacency.
TEST(Instances, TheRasterizerCastsAndReceivesShadowsOfPlacements) {
    const json ball = {
        {"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}, {"material", "red"}};
    const json ground = {{"type", "quad"},
                         {"corner", {-1, 0, 1}},
                         {"edge_u", {2, 0, 0}},
                         {"edge_v", {0, 0, -2}},
                         {"material", "grey"}};
    const json under = {{"rotate", {30, 0, 1, 0}}, {"scale", 3}, {"translate", {0, -0.6, 0}}};
    const json left = {{"translate", {-1, -0.6, 0}}};
    const json right = {{"scale", {-1, 1, 1}}, {"translate", {1, -0.6, 0.5}}};
    for (const char* shadows : {"raytraced", "map", "volume", "planar"}) {
        json placed = base("raster"), written = base("raster");
        placed["prototypes"] = {{"ground", {{"objects", {ground}}}},
                                {"ball", {{"objects", {ball}}}}};
        placed["objects"] = {{{"type", "instance"}, {"prototype", "ground"}, {"transform", under}},
                             {{"type", "instance"}, {"prototype", "ball"}, {"transform", left}},
                             {{"type", "instance"}, {"prototype", "ball"}, {"transform", right}}};
        written["objects"] = json::array();
        for (const auto& [o, t] : {std::pair{ground, under}, {ball, left}, {ball, right}}) {
            json object = o;
            object["transform"] = t;
            written["objects"].push_back(object);
        }
        for (json* j : {&placed, &written}) (*j)["render"]["shadows"] = shadows;
        expect_same<RasterRenderer>(placed, written, shadows, 0);
    }
}

/// A renderer keeps the last frame's placements for the next frame of the same scene (a drag
/// in `svetlo serve`): a frame after another scene's is that scene's own, and the first scene
/// drawn again is its first frame.
TEST(Instances, TheRasterizerKeepsItsPlacementsForTheSameSceneAlone) {
    const Scene first = scene_from_json(forest("raster", true), "s.json");
    json moved_json = forest("raster", true);
    moved_json["objects"][0]["transform"] = translate(-2.5f, 0.3f);
    const Scene moved = scene_from_json(moved_json, "s.json");
    ASSERT_NE(first.geometry_key, moved.geometry_key);
    RenderOptions options;
    options.threads = 2;
    RasterRenderer renderer;
    const RenderResult a = renderer.render(first, options);
    const RenderResult b = renderer.render(moved, options);
    const RenderResult again = renderer.render(first, options);
    EXPECT_EQ(b.color.pixels, RasterRenderer().render(moved, options).color.pixels);
    EXPECT_NE(a.color.pixels, b.color.pixels);
    EXPECT_EQ(again.color.pixels, a.color.pixels);
}

/// A row of spheres placed far past what the rasterizer's list holds (2^25 triangles; 40 M
/// here), the camera seeing three of them: drawn in place, the frame is the one of those three
/// placed alone, bit for bit (a placement out of view is left out, one across the film's
/// edge is not). Past 2^32 - 1 triangles the item buffer cannot number them: refused naming
/// `objects`. The overdraw view, which draws copies, refuses the 40 M.
TEST(Instances, TheRasterizerDrawsMoreThanItsListHolds) {
    auto row = [](int count, int first) {
        json j = base("raster");
        j["camera"] = {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 40}};
        j["render"]["tessellation"] = 256;  // 2 x 256 x 128 triangles a sphere
        j["render"]["shadows"] = "none";
        j["prototypes"] = {{"ball",
                            {{"objects",
                              {{{"type", "sphere"},
                                {"center", {0, 0, 0}},
                                {"radius", 0.6},
                                {"material", "red"}}}}}}};
        j["objects"] = json::array();
        for (int k = first; k < first + count; ++k)
            j["objects"].push_back({{"type", "instance"},
                                    {"prototype", "ball"},
                                    {"transform", translate(1.5f * static_cast<float>(k), 0)}});
        return j;
    };
    // Spheres at x = -1.5, 0, 1.5 cross the film (its edges at x = +-1.46 in their plane).
    const RenderResult many = render_json<RasterRenderer>(row(610, -1));
    const RenderResult three = render_json<RasterRenderer>(row(3, -1));
    EXPECT_EQ(many.color.pixels, three.color.pixels);
    EXPECT_GT(max_component(many.color.at(12, 8)), 0.0f);
    // The views that draw copies refuse them past the list's bound, saying why.
    json overdraw = row(610, -1);
    overdraw["render"]["shading"] = "overdraw";
    try {
        render_json<RasterRenderer>(overdraw);
        ADD_FAILURE() << "40 M triangles were copied";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "render.tessellation");
        EXPECT_NE(e.message().find("instances are copies in the overdraw"), std::string::npos)
            << e.message();
    }
    try {
        render_json<RasterRenderer>(row(65600, -1));
        ADD_FAILURE() << "4.3 G triangles were drawn";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "objects");
        EXPECT_NE(e.message().find("the rasterizer numbers at most 4294967294"), std::string::npos)
            << e.message();
    }
}

/// Where a glTF's nodes place its one triangle: moved, turned, mirrored. The last node places
/// a second mesh (the same triangle), which one node alone places.
const std::vector<mat4>& triangle_places() {
    static const std::vector<mat4> places = {
        glm::translate(mat4(1.0f), vec3(-1.5f, 0.0f, 0.0f)),
        glm::rotate(glm::translate(mat4(1.0f), vec3(0.5f, 0.2f, 0.0f)), 0.5f, vec3(0, 0, 1)),
        glm::scale(glm::translate(mat4(1.0f), vec3(0.0f, -1.2f, 0.0f)), vec3(-1.0f, 1.0f, 1.0f)),
        glm::translate(mat4(1.0f), vec3(1.0f, 1.0f, 0.0f))};
    return places;
}

/// tests/data/triangle.gltf with its triangle placed by four nodes, three of them sharing
/// mesh 0; written to a temporary folder.
std::string shared_triangle_gltf() {
    std::ifstream in(std::string(SVETLO_TEST_DATA) + "/triangle.gltf");
    json g = json::parse(in);
    g["meshes"].push_back(g["meshes"][0]);
    g["nodes"] = json::array();
    g["scenes"][0]["nodes"] = json::array();
    for (size_t k = 0; k < triangle_places().size(); ++k) {
        std::vector<float> m(16);
        for (int c = 0; c < 16; ++c)
            m[static_cast<size_t>(c)] = glm::value_ptr(triangle_places()[k])[c];
        g["nodes"].push_back({{"mesh", k + 1 < triangle_places().size() ? 0 : 1}, {"matrix", m}});
        g["scenes"][0]["nodes"].push_back(k);
    }
    const auto dir = std::filesystem::temp_directory_path() / "svetlo_instances_test";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "shared.gltf").string();
    std::ofstream(path) << g.dump();
    return path;
}

json triangle_scene(const char* engine) {
    json j = base(engine);
    j["camera"] = {{"position", {0, 0, 5}}, {"look_at", {0, 0, 0}}, {"fov", 50}};
    return j;
}

TEST(Instances, AGltfMeshThatSeveralNodesPlaceIsAPrototype) {
    json j = triangle_scene("whitted");
    j["objects"] = {{{"type", "mesh"}, {"file", shared_triangle_gltf()}, {"material", "red"}}};
    const Scene s = scene_from_json(j, "s.json");
    ASSERT_EQ(s.prototypes.size(), 1u);
    EXPECT_EQ(s.instances.size(), 3u);
    ASSERT_EQ(s.objects.size(), 1u);  // the mesh one node places, baked
    EXPECT_EQ(std::get<Mesh>(s.objects[0].shape).triangle_count(), 1u);
    for (size_t k = 0; k < 3; ++k) EXPECT_EQ(s.instances[k].transform.matrix, triangle_places()[k]);
    // A CSG child must be one mesh: such a file is refused there, naming it.
    json csg = j;
    csg["objects"] = {{{"type", "csg"},
                       {"op", "union"},
                       {"material", "red"},
                       {"children", {{{"type", "mesh"}, {"file", shared_triangle_gltf()}}}}}};
    try {
        scene_from_json(csg, "s.json");
        ADD_FAILURE() << "a CSG child with instances was read";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "objects[0].children[0].file");
        EXPECT_NE(e.message().find("places one mesh at several nodes"), std::string::npos);
    }

    // It renders as the triangles written out, in every engine.
    for (const char* engine : {"raster", "radiosity", "whitted", "path"}) {
        json placed = triangle_scene(engine);
        placed["objects"] = j["objects"];
        json written = triangle_scene(engine);
        written["objects"] = json::array();
        // In the scene's order: the mesh one node places, then the shared one's places.
        const std::vector<mat4>& all = triangle_places();
        std::vector<mat4> order = {all.back()};
        order.insert(order.end(), all.begin(), all.end() - 1);
        for (const mat4& m : order) {
            std::vector<float> rows;
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) rows.push_back(m[c][r]);
            written["objects"].push_back({{"type", "mesh"},
                                          {"positions", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                                          {"indices", {0, 1, 2}},
                                          {"material", "red"},
                                          {"transform", {{"matrix", rows}}}});
        }
        const std::string e = engine;
        if (e == "raster") expect_same<RasterRenderer>(placed, written, engine, 0);
        if (e == "radiosity") expect_same<RadiosityRenderer>(placed, written, engine, 0);
        if (e == "whitted") expect_same<WhittedRenderer>(placed, written, engine, 1);
        if (e == "path") expect_same<PathRenderer>(placed, written, engine, 1);
    }
}

TEST(Instances, PlaceTheirPrototypesWithoutCopies) {
    const Scene s = scene_from_json(forest("path", true), "s.json");
    // The tree twice, and the grove's tree: three placements of the one prototype that has
    // objects of its own (the grove has none), and no object written out.
    ASSERT_EQ(s.prototypes.size(), 1u);
    EXPECT_EQ(s.prototypes[0].name, "tree");
    EXPECT_EQ(s.prototypes[0].objects.size(), 2u);
    ASSERT_EQ(s.instances.size(), 3u);
    EXPECT_TRUE(s.objects.empty());
    EXPECT_EQ(s.copied_objects, 0u);
    // The grove's tree: the grove's transform after the tree's place in it.
    EXPECT_EQ(s.instances[2].name, "objects[2]");
    EXPECT_EQ(vec3(s.instances[2].transform.matrix[3]), vec3(2.0f, -1.0f, 0.0f));
    ASSERT_GE(s.instances[1].material, 0);
    EXPECT_EQ(s.material_names[static_cast<size_t>(s.instances[1].material)], "grey");
    EXPECT_EQ(s.instances[0].material, -1);
}

TEST(Instances, ThoseThatEmitOrHaveNoBoxAreWrittenOut) {
    // An emitting material given by the instance, a plane, an implicit surface (a plane in an
    // SDF has no box): each written into the objects; the plain tree stays placed.
    json j = forest("path", true);
    j["materials"]["glow"] = {{"type", "emissive"}, {"radiance", 1}};
    j["prototypes"]["floor"] = {{"objects",
                                 {{{"type", "plane"},
                                   {"point", {0, -1, 0}},
                                   {"normal", {0, 1, 0}},
                                   {"material", "grey"}}}}};
    j["prototypes"]["blob"] = {
        {"objects",
         {{{"type", "implicit"},
           {"material", "red"},
           {"sdf", {{"op", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.5}}}}}}};
    j["objects"] = {{{"type", "instance"}, {"prototype", "tree"}, {"material", "glow"}},
                    {{"type", "instance"}, {"prototype", "floor"}},
                    {{"type", "instance"}, {"prototype", "blob"}},
                    {{"type", "instance"}, {"prototype", "tree"}}};
    const Scene s = scene_from_json(j, "s.json");
    EXPECT_EQ(s.copied_objects, 4u);  // the tree's two, the plane, the implicit surface
    ASSERT_EQ(s.objects.size(), 4u);
    EXPECT_TRUE(std::holds_alternative<Plane>(s.objects[2].shape));
    EXPECT_TRUE(std::holds_alternative<Implicit>(s.objects[3].shape));
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.instances[0].name, "objects[3]");
}

std::string error_of(const json& j) {
    try {
        scene_from_json(j, "s.json");
    } catch (const Error& e) {
        return e.where() + ": " + e.message();
    }
    return "no error";
}

TEST(Instances, AnUnknownPrototypeOrACycleIsRefusedNamingTheKey) {
    json j = forest("path", true);
    j["objects"][0]["prototype"] = "oak";
    EXPECT_EQ(error_of(j).rfind("objects[0].prototype: unknown prototype 'oak'", 0), 0u)
        << error_of(j);
    j = forest("path", true);
    j["prototypes"]["tree"]["objects"].push_back({{"type", "instance"}, {"prototype", "grove"}});
    const std::string cycle = error_of(j);
    EXPECT_NE(cycle.find("prototype 'tree' holds an instance of itself (tree -> grove -> tree)"),
              std::string::npos)
        << cycle;
    EXPECT_EQ(cycle.rfind("prototypes.grove.objects[0].prototype", 0), 0u) << cycle;
    j = forest("path", true);
    j["prototypes"]["tree"]["objects"][0] = {{"type", "instance"}, {"prototype", "tree"}};
    EXPECT_NE(error_of(j).find("(tree -> tree)"), std::string::npos) << error_of(j);
}

}  // namespace
}  // namespace svetlo
