// The MIS weights (pt/mis.h): the power heuristic's values, its complement, and no overflow.
#include "svetlo/pt/mis.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

TEST(Mis, PowerHeuristicWeightsSumToOne) {
    EXPECT_FLOAT_EQ(power_heuristic(1.0f, 1.0f), 0.5f);
    EXPECT_FLOAT_EQ(power_heuristic(3.0f, 1.0f), 0.9f);
    EXPECT_FLOAT_EQ(power_heuristic(1.0f, 3.0f), 0.1f);
    EXPECT_FLOAT_EQ(power_heuristic(0.0f, 2.0f), 0.0f);
    EXPECT_FLOAT_EQ(power_heuristic(2.0f, 0.0f), 1.0f);
    EXPECT_FLOAT_EQ(power_heuristic(0.0f, 0.0f), 0.0f);
    for (float a : {1e-30f, 0.3f, 7.0f, 2e19f}) {
        for (float b : {1e-30f, 0.5f, 9.0f, 3e19f}) {
            EXPECT_NEAR(power_heuristic(a, b) + power_heuristic(b, a), 1.0f, 1e-6f)
                << a << " " << b;
        }
    }
}

TEST(Mis, PowerHeuristicDoesNotOverflow) {
    // A point at the horizon of an infinite plane sees a light edge-on: pdfs past 1e19 sr^-1,
    // whose squares overflow a float. This gave NaN in a pixel before.
    EXPECT_FLOAT_EQ(power_heuristic(6.6e19f, 6.6e19f), 0.5f);
    EXPECT_FLOAT_EQ(power_heuristic(2e20f, 1.0f), 1.0f);
    EXPECT_NEAR(power_heuristic(1.0f, 2e20f), 0.0f, 1e-30f);
    EXPECT_FLOAT_EQ(power_heuristic(kInfinity, kInfinity), 0.5f);
    EXPECT_FLOAT_EQ(power_heuristic(kInfinity, 1.0f), 1.0f);
}

TEST(Mis, OneStrategyAloneTakesItsSamplesInFull) {
    EXPECT_FLOAT_EQ(light_weight(MisMode::LightOnly, 1.0f, 5.0f), 1.0f);
    EXPECT_FLOAT_EQ(bsdf_weight(MisMode::LightOnly, 5.0f, 1.0f), 0.0f);
    EXPECT_FLOAT_EQ(light_weight(MisMode::BsdfOnly, 5.0f, 1.0f), 0.0f);
    EXPECT_FLOAT_EQ(bsdf_weight(MisMode::BsdfOnly, 1.0f, 5.0f), 1.0f);
    EXPECT_FLOAT_EQ(light_weight(MisMode::Power, 3.0f, 1.0f), 0.9f);
}

}  // namespace
}  // namespace svetlo
