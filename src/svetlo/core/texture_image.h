// A texture's texels as they are kept in memory, the way a GPU keeps them: an 8-bit file
// (PNG, JPEG, TGA, BMP) keeps its 8-bit codes, three bytes a texel, decoded to linear RGB at
// each fetch through a 256-entry table (the sRGB transfer function, or code / 255 for linear
// data); a floating-point file (PFM, EXR, HDR) keeps linear float RGB, twelve bytes a texel.
// A 16384² PNG takes 768 MiB instead of 3 GiB. Rows from the top, as in Image. Copies share
// their texels (a model's file cache, its scene and each engine hold them once); set_texel
// gives a texture texels of its own first.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "svetlo/core/image.h"

namespace svetlo {

class TextureImage {
public:
    TextureImage() = default;
    /// Float texels, linear RGB.
    explicit TextureImage(Image image);
    /// 8-bit texels: `codes` holds 3 per texel, rows from the top; `srgb` picks the decoding.
    TextureImage(int width, int height, std::vector<unsigned char> codes, bool srgb);
    /// A blank texture stored as `like` is (8-bit sRGB, 8-bit linear or float): a mip level.
    static TextureImage same_storage(const TextureImage& like, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    bool is_8bit() const { return codes_ != nullptr; }
    /// Whether `other` holds the same texels, stored the same way.
    bool same_texels(const TextureImage& other) const;
    /// Bytes its texels take in memory.
    size_t bytes() const {
        return texels_ ? texels_->codes.size() + texels_->floats.pixels.size() * sizeof(Color) : 0;
    }

    /// The linear colour of texel (i, j), j counted from the top row.
    Color texel(int i, int j) const {
        size_t k = static_cast<size_t>(j) * static_cast<size_t>(width_) + static_cast<size_t>(i);
        if (!codes_) return floats_[k];
        const unsigned char* c = codes_ + 3 * k;
        return Color(decode_[c[0]], decode_[c[1]], decode_[c[2]]);
    }
    /// Stores a linear colour at (i, j): 8-bit storage rounds it to the nearest code, clipped
    /// to [0, 1].
    void set_texel(int i, int j, Color linear);

private:
    struct Texels {
        std::vector<unsigned char> codes;  // 8-bit storage
        Image floats;                      // float storage
    };
    /// Points codes_ and floats_ into texels_.
    void point_at_texels();

    int width_ = 0;
    int height_ = 0;
    bool srgb_ = false;
    std::shared_ptr<Texels> texels_;        // shared by the copies
    const unsigned char* codes_ = nullptr;  // texels_->codes, or null for float storage
    const Color* floats_ = nullptr;         // texels_->floats
    std::array<float, 256> decode_{};       // code -> linear value
    std::array<float, 255> round_up_{};     // linear values from which code k + 1 is nearest
};

}  // namespace svetlo
