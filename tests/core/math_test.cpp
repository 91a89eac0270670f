#include "svetlo/core/math.h"

#include <gtest/gtest.h>

#include <cmath>

namespace svetlo {
namespace {

// atan2_approx against the exact angle (double precision) all around the circle, at radii from
// 1e-30 to 1e30, the axes and the diagonals among them: within 3e-7 rad, as math.h states.
TEST(Atan2Approx, WithinItsStatedErrorAllAroundTheCircle) {
    double worst = 0.0;
    for (int k = 0; k < 200000; ++k) {
        const double angle = -M_PI + 2.0 * M_PI * (k + 0.5) / 200000.0;
        for (const double radius : {1e-30, 1e-3, 1.0, 7.5, 1e30}) {
            const float x = static_cast<float>(radius * std::cos(angle));
            const float y = static_cast<float>(radius * std::sin(angle));
            const double exact = std::atan2(static_cast<double>(y), static_cast<double>(x));
            worst = std::max(worst, std::abs(atan2_approx(y, x) - exact));
        }
    }
    EXPECT_LT(worst, 3e-7);
    EXPECT_GT(worst, 1e-8);  // a polynomial, not libm: the test sees its error
}

// The quadrants and signs of std::atan2, on the axes and the diagonals, both zeros' signs.
TEST(Atan2Approx, QuadrantsAndSignsAreStdAtan2s) {
    for (const float y : {-2.0f, -1.0f, -0.0f, 0.0f, 1.0f, 3.0f})
        for (const float x : {-3.0f, -1.0f, -0.0f, 0.0f, 1.0f, 2.0f}) {
            if (x == 0.0f && y == 0.0f) continue;
            EXPECT_NEAR(atan2_approx(y, x), std::atan2(y, x), 3e-7f) << y << ", " << x;
            EXPECT_EQ(std::signbit(atan2_approx(y, x)), std::signbit(std::atan2(y, x)))
                << y << ", " << x;
        }
    EXPECT_EQ(atan2_approx(0.0f, 0.0f), 0.0f);
    EXPECT_EQ(atan2_approx(0.0f, -0.0f), 0.0f);  // no NaN from 0 / 0
    EXPECT_NEAR(atan2_approx(1.0f, 0.0f), 0.5f * kPi, 1e-7f);
    EXPECT_NEAR(atan2_approx(-1.0f, -1.0f), -0.75f * kPi, 3e-7f);
}

}  // namespace
}  // namespace svetlo
