// LargeArray, the uninitialised buffers that the rasterizer keeps from one frame to the next.
#include "svetlo/core/large_array.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

TEST(LargeArray, ReuseKeepsTheMemoryWhenItIsLargeEnough) {
    LargeArray<int> a(1000);
    const int* memory = a.data();
    a.reuse(10);
    EXPECT_EQ(a.size(), 10u);
    EXPECT_EQ(a.data(), memory);
    a.reuse(1000);
    EXPECT_EQ(a.data(), memory);
    a.reuse(1001);
    EXPECT_EQ(a.size(), 1001u);
    EXPECT_NE(a.data(), nullptr);
}

// A renderer moves its buffers out for a frame and back after it; a frame that throws
// leaves them moved from, and the next frame reuses them: a moved-from array must own
// nothing and claim nothing, or reuse() would hand out a null pointer.
TEST(LargeArray, AMovedFromArrayIsEmptyAndReuseAllocates) {
    LargeArray<int> a(1000);
    LargeArray<int> b = std::move(a);
    EXPECT_EQ(b.size(), 1000u);
    EXPECT_EQ(a.size(), 0u);
    EXPECT_EQ(a.data(), nullptr);
    a.reuse(500);
    ASSERT_NE(a.data(), nullptr);
    a[499] = 7;
    EXPECT_EQ(a[499], 7);

    LargeArray<int> c(100);
    c = std::move(b);
    EXPECT_EQ(c.size(), 1000u);
    EXPECT_EQ(b.size(), 0u);
    b.reuse(1000);
    ASSERT_NE(b.data(), nullptr);
    b[999] = 3;
    EXPECT_EQ(b[999], 3);
}

}  // namespace
}  // namespace svetlo
