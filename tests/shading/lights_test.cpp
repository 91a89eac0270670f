#include "svetlo/shading/lights.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

TEST(PointLight, InverseSquareLaw) {
    PunctualSample s = sample_punctual(PointLight{vec3(0, 4, 0), Color(10.0f)}, vec3(3, 0, 0));
    EXPECT_NEAR(s.distance, 5.0f, 1e-6f);
    EXPECT_NEAR(s.irradiance.r, 10.0f / 25.0f, 1e-6f);
    EXPECT_NEAR(s.wi.y, 0.8f, 1e-6f);
}

TEST(DirectionalLight, ConstantIrradianceTowardTheSun) {
    PunctualSample s = sample_punctual(DirectionalLight{vec3(0, -1, 0), Color(3.0f)}, vec3(100.0f));
    EXPECT_EQ(s.wi, vec3(0, 1, 0));
    EXPECT_TRUE(std::isinf(s.distance));
    EXPECT_EQ(s.irradiance, Color(3.0f));
}

TEST(SpotLight, FullInsideInnerZeroOutsideOuterSmoothBetween) {
    SpotLight spot;
    spot.position = vec3(0.0f);
    spot.direction = vec3(0, -1, 0);
    spot.intensity = Color(1.0f);
    spot.inner_deg = 20.0f;
    spot.outer_deg = 30.0f;
    auto at = [&](float deg) {
        return spot_cone_factor(spot, vec3(std::sin(radians(deg)), -std::cos(radians(deg)), 0.0f));
    };
    EXPECT_EQ(at(0.0f), 1.0f);
    EXPECT_EQ(at(19.9f), 1.0f);
    EXPECT_EQ(at(30.1f), 0.0f);
    float t = (std::cos(radians(25.0f)) - std::cos(radians(30.0f))) /
              (std::cos(radians(20.0f)) - std::cos(radians(30.0f)));
    EXPECT_NEAR(at(25.0f), t * t * (3.0f - 2.0f * t), 1e-6f);
    EXPECT_GT(at(22.0f), at(28.0f));
    // Irradiance: I * factor / d^2.
    PunctualSample s = sample_punctual(spot, vec3(0, -2, 0));
    EXPECT_NEAR(s.irradiance.r, 0.25f, 1e-6f);
}

}  // namespace
}  // namespace svetlo
