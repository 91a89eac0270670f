// The stencil buffer's test and operations against OpenGL's rules (stencil.h), value by value.
#include "svetlo/raster/stencil.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

TEST(Stencil, ComparisonsPutTheReferenceOnTheLeft) {
    // (ref & mask) FUNC (value & mask): Less passes when the reference is below the value.
    EXPECT_TRUE(stencil_test(StencilFunc::Less, 1, 2, 0xff));
    EXPECT_FALSE(stencil_test(StencilFunc::Less, 2, 2, 0xff));
    EXPECT_TRUE(stencil_test(StencilFunc::LessEqual, 2, 2, 0xff));
    EXPECT_FALSE(stencil_test(StencilFunc::Greater, 1, 2, 0xff));
    EXPECT_TRUE(stencil_test(StencilFunc::Greater, 3, 2, 0xff));
    EXPECT_TRUE(stencil_test(StencilFunc::GreaterEqual, 2, 2, 0xff));
    EXPECT_TRUE(stencil_test(StencilFunc::Equal, 0, 0, 0xff));
    EXPECT_FALSE(stencil_test(StencilFunc::NotEqual, 7, 7, 0xff));
    EXPECT_FALSE(stencil_test(StencilFunc::Never, 0, 0, 0xff));
    EXPECT_TRUE(stencil_test(StencilFunc::Always, 9, 0, 0));
    // The read mask applies to both sides: 0x13 and 0x03 agree on the low two bits.
    EXPECT_TRUE(stencil_test(StencilFunc::Equal, 0x13, 0x03, 0x03));
    EXPECT_FALSE(stencil_test(StencilFunc::Equal, 0x13, 0x03, 0xff));
    EXPECT_TRUE(stencil_test(StencilFunc::NotEqual, 0, 0x80, 0xff));  // the shadow test
    EXPECT_FALSE(stencil_test(StencilFunc::NotEqual, 0, 0x80, 0x7f));
}

TEST(Stencil, OperationsClampWrapAndRespectTheWriteMask) {
    EXPECT_EQ(stencil_apply(StencilOp::Keep, 42, 7, 0xff), 42);
    EXPECT_EQ(stencil_apply(StencilOp::Zero, 42, 7, 0xff), 0);
    EXPECT_EQ(stencil_apply(StencilOp::Replace, 42, 7, 0xff), 7);
    EXPECT_EQ(stencil_apply(StencilOp::Incr, 254, 0, 0xff), 255);
    EXPECT_EQ(stencil_apply(StencilOp::Incr, 255, 0, 0xff), 255);  // clamped
    EXPECT_EQ(stencil_apply(StencilOp::IncrWrap, 255, 0, 0xff), 0);
    EXPECT_EQ(stencil_apply(StencilOp::Decr, 0, 0, 0xff), 0);  // clamped
    EXPECT_EQ(stencil_apply(StencilOp::Decr, 1, 0, 0xff), 0);
    EXPECT_EQ(stencil_apply(StencilOp::DecrWrap, 0, 0, 0xff), 255);
    EXPECT_EQ(stencil_apply(StencilOp::Invert, 0x0f, 0, 0xff), 0xf0);
    // Only the write mask's bits change.
    EXPECT_EQ(stencil_apply(StencilOp::Zero, 0xff, 0, 0x0f), 0xf0);
    EXPECT_EQ(stencil_apply(StencilOp::Replace, 0x00, 0xff, 0x3c), 0x3c);
    EXPECT_EQ(stencil_apply(StencilOp::IncrWrap, 0x0f, 0, 0x0f), 0x00);
    EXPECT_EQ(stencil_apply(StencilOp::Invert, 0xaa, 0, 0x00), 0xaa);
}

TEST(Stencil, WrappingCountsOfAShadowVolumeReturnToZero) {
    // z-pass counting with wrapping operations: entering and leaving a volume any number of
    // times leaves 0, whatever the order, even past 255 layers.
    uint8_t s = 0;
    for (int k = 0; k < 300; ++k) s = stencil_apply(StencilOp::IncrWrap, s, 0, 0xff);
    for (int k = 0; k < 299; ++k) s = stencil_apply(StencilOp::DecrWrap, s, 0, 0xff);
    EXPECT_EQ(s, 1);  // still inside one volume
    s = stencil_apply(StencilOp::DecrWrap, s, 0, 0xff);
    EXPECT_EQ(s, 0);
}

}  // namespace
}  // namespace svetlo
