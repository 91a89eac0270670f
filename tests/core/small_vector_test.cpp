#include "svetlo/core/small_vector.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

// Growing past the inline elements and shrinking back keeps every value in order.
TEST(SmallVector, PushAndPopAcrossTheInlineLimit) {
    SmallVector<int, 4> v;
    for (int k = 0; k < 7; ++k) v.push_back(k);
    ASSERT_EQ(v.size(), 7u);
    for (int k = 6; k >= 0; --k) {
        ASSERT_EQ(v.back(), k);
        for (int i = 0; i <= k; ++i) ASSERT_EQ(v[static_cast<size_t>(i)], i) << k;
        v.pop_back();
    }
    EXPECT_TRUE(v.empty());
    v.push_back(9);
    EXPECT_EQ(v[0], 9);
}

}  // namespace
}  // namespace svetlo
