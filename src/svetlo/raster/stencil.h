// The stencil buffer's test and operations, with OpenGL's semantics (OpenGL 4.6 core
// specification, section 17.3.3 "Stencil Test"): eight bits per sample, a reference value
// and masks, and separate operations for front and back faces, which is what one-pass
// shadow volumes need (z-pass: front faces increment and back faces decrement where the
// depth test passes; z-fail, Carmack's reverse: back faces increment and front faces
// decrement where it fails; Heidmann 1991, Everitt and Kilgard 2002).
//
// The rasterizer applies them per sample in this order: stencil test (failing: `fail`,
// and the sample is discarded), then depth test (failing: `depth_fail`), else `pass`.
#pragma once

#include <cstdint>

namespace svetlo {

enum class StencilFunc { Never, Less, LessEqual, Greater, GreaterEqual, Equal, NotEqual, Always };

enum class StencilOp {
    Keep,      // leave the value
    Zero,      // 0
    Replace,   // the reference value
    Incr,      // + 1, clamped at 255
    IncrWrap,  // + 1, 255 wraps to 0
    Decr,      // - 1, clamped at 0
    DecrWrap,  // - 1, 0 wraps to 255
    Invert,    // bitwise not
};

struct StencilFace {
    StencilFunc func = StencilFunc::Always;
    StencilOp fail = StencilOp::Keep;        // the stencil test failed
    StencilOp depth_fail = StencilOp::Keep;  // the stencil test passed, the depth test failed
    StencilOp pass = StencilOp::Keep;        // both passed
};

struct StencilState {
    bool enabled = false;
    uint8_t ref = 0;
    uint8_t read_mask = 0xff;   // ANDed with both sides of the comparison
    uint8_t write_mask = 0xff;  // the bits an operation may change
    StencilFace front, back;    // by the side of the triangle the camera sees
};

/// The stencil test: `(ref & mask) FUNC (value & mask)`, the reference on the left as in
/// OpenGL (Less passes when the reference is less than the stored value).
inline bool stencil_test(StencilFunc func, uint8_t ref, uint8_t value, uint8_t mask) {
    unsigned r = ref & mask, v = value & mask;
    switch (func) {
        case StencilFunc::Never:
            return false;
        case StencilFunc::Less:
            return r < v;
        case StencilFunc::LessEqual:
            return r <= v;
        case StencilFunc::Greater:
            return r > v;
        case StencilFunc::GreaterEqual:
            return r >= v;
        case StencilFunc::Equal:
            return r == v;
        case StencilFunc::NotEqual:
            return r != v;
        case StencilFunc::Always:
            return true;
    }
    return true;
}

/// The value after operation `op`; only the bits of `write_mask` change.
inline uint8_t stencil_apply(StencilOp op, uint8_t value, uint8_t ref, uint8_t write_mask) {
    unsigned next = value;
    switch (op) {
        case StencilOp::Keep:
            return value;
        case StencilOp::Zero:
            next = 0;
            break;
        case StencilOp::Replace:
            next = ref;
            break;
        case StencilOp::Incr:
            next = value == 0xff ? 0xff : value + 1u;
            break;
        case StencilOp::IncrWrap:
            next = (value + 1u) & 0xffu;
            break;
        case StencilOp::Decr:
            next = value == 0 ? 0 : value - 1u;
            break;
        case StencilOp::DecrWrap:
            next = (value + 0xffu) & 0xffu;
            break;
        case StencilOp::Invert:
            next = ~static_cast<unsigned>(value) & 0xffu;
            break;
    }
    return static_cast<uint8_t>((next & write_mask) | (value & ~write_mask & 0xffu));
}

}  // namespace svetlo
