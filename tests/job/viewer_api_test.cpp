// The viewer's requests (job/viewer_api.h) as svetlo serve and the web page both answer them:
// the routes, their one-line errors, the folder's bounds, the progressive stream's frames and
// the external cancel flag the web page's worker sets.
#include "svetlo/job/viewer_api.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "svetlo/core/image_io.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;

/// A folder with one small scene (a lit sphere) and a file outside it.
class ViewerApiTest : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = fs::temp_directory_path() /
                ("svetlo_viewer_api_" +
                 std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(root_);
        fs::create_directories(root_ / "scenes");
        const nlohmann::json scene = {
            {"camera", {{"position", {0, 0, 5}}, {"look_at", {0, 0, 0}}, {"fov", 40}}},
            {"film", {{"width", 32}, {"height", 24}}},
            {"render", {{"engine", "raster"}, {"spp", 1}}},
            {"materials", {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}}},
            {"lights", {{{"type", "point"}, {"position", {0, 3, 3}}, {"intensity", 10}}}},
            {"objects",
             {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "white"}}}}};
        std::ofstream(root_ / "scenes" / "ball.json") << scene.dump();
        std::ofstream(root_ / "outside.json") << scene.dump();
    }
    void TearDown() override { fs::remove_all(root_); }

    fs::path root_;
};

/// The frames of a progressive stream: each header's JSON and its image's size in bytes.
std::vector<std::pair<nlohmann::json, size_t>> frames_of(const std::string& stream) {
    std::vector<std::pair<nlohmann::json, size_t>> out;
    size_t at = 0;
    auto length = [&]() {
        const auto* b = reinterpret_cast<const unsigned char*>(stream.data() + at);
        at += 4;
        return (uint32_t(b[0]) << 24) | (uint32_t(b[1]) << 16) | (uint32_t(b[2]) << 8) | b[3];
    };
    while (at + 4 <= stream.size()) {
        const uint32_t h = length();
        nlohmann::json header = nlohmann::json::parse(stream.substr(at, h));
        at += h;
        size_t image = 0;
        if (!header.contains("error")) {
            image = length();
            at += image;
        }
        out.emplace_back(std::move(header), image);
    }
    EXPECT_EQ(at, stream.size());
    return out;
}

TEST_F(ViewerApiTest, ListsTheScenesAndTheEngines) {
    ViewerApi api((root_ / "scenes" / "ball.json").string());
    const ViewerResponse scenes = api.get("/api/scenes");
    ASSERT_EQ(scenes.status, 200);
    const auto list = nlohmann::json::parse(scenes.body);
    EXPECT_EQ(list["scenes"], nlohmann::json::array({"ball.json"}));
    EXPECT_EQ(list["default"], "ball.json");
    // Environment maps in the folder or below, those this build reads: an EXR only with
    // OpenEXR (the browser's build has none).
    EXPECT_EQ(list["environments"], nlohmann::json::array());
    fs::create_directories(root_ / "scenes" / "maps");
    for (const char* name : {"maps/sky.pfm", "maps/studio.exr", "maps/sun.hdr", "maps/photo.png"})
        std::ofstream(root_ / "scenes" / name) << "x";
    nlohmann::json maps = {"maps/sky.pfm"};
    if (reads_exr()) maps.push_back("maps/studio.exr");
    maps.push_back("maps/sun.hdr");
    EXPECT_EQ(nlohmann::json::parse(api.get("/api/scenes").body)["environments"], maps);
    const auto engines = nlohmann::json::parse(api.get("/api/engines").body);
    std::vector<std::string> names;
    for (const auto& e : engines) names.push_back(e["name"]);
    EXPECT_EQ(names, (std::vector<std::string>{"raster", "whitted", "path", "radiosity"}));
}

TEST_F(ViewerApiTest, RendersAPngOfTheFilmAsked) {
    ViewerApi api((root_ / "scenes").string());
    const ViewerResponse r =
        api.get("/api/render?scene=ball.json&engine=whitted&width=40&height=30&spp=1");
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.type, "image/png");
    std::ofstream(root_ / "render.png", std::ios::binary) << r.body;
    const Image image = read_image(root_ / "render.png", "test").image;
    EXPECT_EQ(image.width, 40);
    EXPECT_EQ(image.height, 30);
    // The sphere is lit in the middle of the image, the background black at its corner.
    EXPECT_GT(image.at(20, 15).x, 0.01f);
    EXPECT_EQ(image.at(0, 0).x, 0.0f);
}

TEST_F(ViewerApiTest, BadRequestsGetOneLineNamingTheirPlace) {
    ViewerApi api((root_ / "scenes").string());
    for (const char* target :
         {"/api/render?scene=../outside.json&engine=raster", "/api/render?scene=missing.json",
          "/api/render?scene=ball.json&engine=nonesuch", "/api/render?scene=ball.json&spp=0",
          "/api/render?scene=ball.json&set=render.shading", "/api/scene?scene=.hidden.json",
          "/api/trace?scene=ball.json&x=-1&y=0"}) {
        const ViewerResponse r = api.get(target);
        EXPECT_EQ(r.status, 400) << target;
        ASSERT_FALSE(r.body.empty()) << target;
        EXPECT_EQ(r.body.find('\n'), r.body.size() - 1) << target << ": " << r.body;
        EXPECT_EQ(r.body.find(root_.string()), std::string::npos) << "names files relative to "
                                                                     "the folder: "
                                                                  << r.body;
    }
    EXPECT_EQ(api.get("/api/nonesuch").status, 404);
    const ProgressiveRender bad = api.start_progressive("/api/progressive?scene=ball.json&spp=x");
    EXPECT_EQ(bad.job, nullptr);
    EXPECT_EQ(bad.failed.status, 400);
}

TEST_F(ViewerApiTest, ReadsALinkAsARequestIs) {
    ViewerApi api((root_ / "scenes").string());
    const auto link = nlohmann::json::parse(
        api.get("/api/link?scene=ball.json&engine=path&spp=8&set=render.shading=phong"
                "&set=lights.0.position=%5B1,2,3%5D")
            .body);
    EXPECT_EQ(link["scene"], "ball.json");
    EXPECT_EQ(link["engine"], "path");
    EXPECT_EQ(link["spp"], 8);
    ASSERT_EQ(link["sets"].size(), 2u);
    EXPECT_EQ(link["sets"][0]["key"], "render.shading");
    EXPECT_EQ(link["sets"][0]["value"], "phong");  // a bare word, as --set reads it
    EXPECT_EQ(link["sets"][1]["value"], nlohmann::json::array({1, 2, 3}));
    EXPECT_FALSE(link.contains("error"));
    const auto bad =
        nlohmann::json::parse(api.get("/api/link?scene=ball.json&engine=nonesuch").body);
    EXPECT_EQ(bad["scene"], "ball.json");  // what could be read, and the problem
    EXPECT_NE(bad["error"].get<std::string>().find("nonesuch"), std::string::npos);
}

TEST_F(ViewerApiTest, StreamsEachPassThenTheFinalPng) {
    ViewerApi api((root_ / "scenes").string());
    ProgressiveRender render =
        api.start_progressive("/api/progressive?scene=ball.json&engine=path&spp=3");
    ASSERT_NE(render.job, nullptr) << render.failed.body;
    std::string stream;
    api.run_progressive(render, [&](std::string_view bytes) {
        stream.append(bytes);
        return true;
    });
    const auto frames = frames_of(stream);
    ASSERT_FALSE(frames.empty());
    const auto& [last, bytes] = frames.back();
    EXPECT_EQ(last["final"], true);
    EXPECT_EQ(last["spp"], 3);
    EXPECT_EQ(last["type"], "image/png");
    EXPECT_GT(bytes, 0u);
    for (size_t k = 0; k + 1 < frames.size(); ++k) EXPECT_EQ(frames[k].first["final"], false);
}

TEST_F(ViewerApiTest, AReaderGoneEndsTheStreamAfterItsPass) {
    ViewerApi api((root_ / "scenes").string());
    ProgressiveRender render =
        api.start_progressive("/api/progressive?scene=ball.json&engine=path&spp=4096");
    ASSERT_NE(render.job, nullptr);
    int writes = 0;
    api.run_progressive(render, [&](std::string_view) { return ++writes < 2; });
    EXPECT_TRUE(render.cancel->load());
    EXPECT_LE(writes, 4);  // the first frame's two lengths: nothing after the refusal
}

TEST_F(ViewerApiTest, AnOuterFlagEndsARenderAsANewerRequestDoes) {
    ViewerApi api((root_ / "scenes").string());
    // The web page's worker holds one flag the page sets; set before, the path tracer's
    // million samples end after the first pass.
    std::atomic<bool> cancel{true};
    const ViewerResponse r =
        api.get("/api/render?scene=ball.json&engine=path&width=16&height=12&spp=4096", &cancel);
    ASSERT_EQ(r.status, 200) << r.body;
    const auto spp = std::find_if(r.headers.begin(), r.headers.end(),
                                  [](const auto& h) { return h.first == "X-Svetlo-Spp"; });
    ASSERT_NE(spp, r.headers.end());
    EXPECT_EQ(spp->second, "1");
}

TEST_F(ViewerApiTest, ANewerRequestOfTheSameClientSupersedesTheOneInProgress) {
    ViewerApi api((root_ / "scenes").string());
    ViewerResponse first;
    std::thread older([&] {
        first = api.get(
            "/api/render?scene=ball.json&engine=path&width=64&height=48&spp=4096"
            "&client=a");
    });
    // Once it renders, the same client's next request ends it after its pass: 409.
    while (nlohmann::json::parse(api.get("/api/status").body)["renders"] == 0)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const ViewerResponse second = api.get("/api/render?scene=ball.json&client=a");
    older.join();
    EXPECT_EQ(first.status, 409);
    EXPECT_EQ(second.status, 200);
    // Another client's request supersedes nothing.
    EXPECT_EQ(api.get("/api/render?scene=ball.json&client=b").status, 200);
}

}  // namespace
}  // namespace svetlo
