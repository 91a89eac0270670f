// The job layer's own rules (src/svetlo/job): here, what a render's memory is estimated at,
// which the web page refuses a render by (docs/web.md).
#include "svetlo/job/render_job.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

RenderJob job_of(const std::string& engine, int width, int height) {
    nlohmann::json scene = {
        {"camera", {{"position", {0, 0, 5}}, {"look_at", {0, 0, 0}}, {"fov", 40}}},
        {"film", {{"width", width}, {"height", height}}},
        {"render", {{"engine", engine}}},
        {"materials", {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}}},
        {"lights", {{{"type", "point"}, {"position", {0, 3, 3}}, {"intensity", 10}}}},
        {"objects",
         {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "white"}}}}};
    return make_job(std::move(scene), "memory.json", {});
}

TEST(RenderJob, TheMemoryEstimateFollowsTheEngineTheFilmAndTheAovs) {
    // Each engine's bytes per pixel, from its capabilities (measured: docs/web.md).
    EXPECT_EQ(estimated_render_bytes(job_of("path", 100, 50)), 5000u * 40u);
    EXPECT_EQ(estimated_render_bytes(job_of("radiosity", 100, 50)), 5000u * 48u);
    EXPECT_EQ(estimated_render_bytes(job_of("raster", 100, 50)), 5000u * 16u);
    EXPECT_EQ(estimated_render_bytes(job_of("whitted", 100, 50)), 5000u * 16u);
    // Each AOV adds its image and sums.
    RenderJob with_aovs = job_of("raster", 100, 50);
    request_aov(with_aovs, "depth", "memory.json", "--aov");
    request_aov(with_aovs, "normal", "memory.json", "--aov");
    EXPECT_EQ(estimated_render_bytes(with_aovs), 5000u * (16u + 2u * kAovBytesPerPixel));
    // A crop renders its window alone.
    RenderJob cropped = job_of("path", 100, 50);
    cropped.options.crop = Crop{10, 30, 5, 15};
    EXPECT_EQ(estimated_render_bytes(cropped), 200u * 40u);
    // The largest film (scene_loader.h) in 64 bits.
    EXPECT_EQ(estimated_render_bytes(job_of("path", 8192, 8192)), 8192ull * 8192ull * 40ull);
}

}  // namespace
}  // namespace svetlo
