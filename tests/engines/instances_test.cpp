// Instances (docs/scene-format.md, "Instances"): a prototype's objects placed by each
// instance's transform render as the same objects written out, in every engine, bit for bit;
// nested prototypes compose their transforms; a material given to an instance replaces its
// objects'; an unknown prototype and a cycle of prototypes are refused naming the key.
#include <gtest/gtest.h>

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

template <class Engine>
void expect_same_as_written_out(const char* engine) {
    const RenderResult a = render_json<Engine>(forest(engine, true));
    const RenderResult b = render_json<Engine>(forest(engine, false));
    ASSERT_EQ(a.color.pixels.size(), b.color.pixels.size());
    size_t differ = 0;
    for (size_t k = 0; k < a.color.pixels.size(); ++k)
        differ += a.color.pixels[k] != b.color.pixels[k];
    EXPECT_EQ(differ, 0u) << engine;
    double sum = 0.0;
    for (const Color& c : a.color.pixels) sum += c.r;
    EXPECT_GT(sum, 0.0) << engine;  // the trees are there
}

TEST(Instances, RenderAsTheirObjectsWrittenOutInEveryEngine) {
    expect_same_as_written_out<RasterRenderer>("raster");
    expect_same_as_written_out<WhittedRenderer>("whitted");
    expect_same_as_written_out<PathRenderer>("path");
    expect_same_as_written_out<RadiosityRenderer>("radiosity");
}

TEST(Instances, TheSceneCountsThemAndTheObjectsTheyMake) {
    const Scene s = scene_from_json(forest("path", true), "s.json");
    // Three placed in objects, one in the grove prototype (parsed once): the grove's two
    // objects made once, then each instance's copies, 2 + 2 + 2 + 2.
    EXPECT_EQ(s.instances, 4u);
    EXPECT_EQ(s.instanced_objects, 8u);
    EXPECT_EQ(s.objects.size(), 6u);
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
