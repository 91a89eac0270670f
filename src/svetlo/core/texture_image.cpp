#include "svetlo/core/texture_image.h"

#include <algorithm>
#include <utility>

namespace svetlo {

TextureImage::TextureImage(Image image)
    : width_(image.width),
      height_(image.height),
      texels_(std::make_shared<Texels>(Texels{{}, std::move(image)})) {
    point_at_texels();
}

TextureImage::TextureImage(int width, int height, std::vector<unsigned char> codes, bool srgb)
    : width_(width),
      height_(height),
      srgb_(srgb),
      texels_(std::make_shared<Texels>(Texels{std::move(codes), {}})) {
    point_at_texels();
    for (int k = 0; k < 256; ++k) {
        float v = static_cast<float>(k) / 255.0f;
        decode_[static_cast<size_t>(k)] = srgb ? srgb_to_linear(v) : v;
    }
    // Halfway between two codes in the encoded space (the nearest code, as linear_to_srgb8
    // rounds), as a linear value: encoding is then a binary search instead of a pow.
    for (int k = 0; k < 255; ++k) {
        float v = (static_cast<float>(k) + 0.5f) / 255.0f;
        round_up_[static_cast<size_t>(k)] = srgb ? srgb_to_linear(v) : v;
    }
}

TextureImage TextureImage::same_storage(const TextureImage& like, int width, int height) {
    size_t texels = static_cast<size_t>(width) * static_cast<size_t>(height);
    if (!like.is_8bit()) return TextureImage(Image(width, height));
    return TextureImage(width, height, std::vector<unsigned char>(3 * texels), like.srgb_);
}

void TextureImage::point_at_texels() {
    codes_ = texels_->codes.empty() ? nullptr : texels_->codes.data();
    floats_ = texels_->floats.pixels.data();
}

bool TextureImage::same_texels(const TextureImage& other) const {
    if (width_ != other.width_ || height_ != other.height_ || srgb_ != other.srgb_) return false;
    if (texels_ == other.texels_) return true;
    if (!texels_ || !other.texels_) return bytes() == 0 && other.bytes() == 0;
    return texels_->codes == other.texels_->codes &&
           texels_->floats.pixels == other.texels_->floats.pixels;
}

void TextureImage::set_texel(int i, int j, Color linear) {
    if (texels_.use_count() > 1) {  // shared with a copy: this texture's own texels first
        texels_ = std::make_shared<Texels>(*texels_);
        point_at_texels();
    }
    size_t k = static_cast<size_t>(j) * static_cast<size_t>(width_) + static_cast<size_t>(i);
    if (!codes_) {
        texels_->floats.pixels[k] = linear;
        return;
    }
    for (int c = 0; c < 3; ++c) {
        // The number of halfway points at or below v is the nearest code (0 for NaN, which
        // no comparison passes): a binary search over the 255 points in eight fixed steps,
        // without branches (a mip chain's codes are made with it each frame; std::upper_bound's
        // unpredictable branches took most of the chain's time).
        const float v = linear[c];
        unsigned code = 0;
        for (unsigned step = 128; step > 0; step /= 2)
            code += round_up_[code + step - 1] <= v ? step : 0;  // index at most 254
        texels_->codes[3 * k + static_cast<size_t>(c)] = static_cast<unsigned char>(code);
    }
}

}  // namespace svetlo
