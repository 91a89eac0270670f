#include "svetlo/core/image_io.h"

#ifdef SVETLO_HAS_OPENEXR
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#endif
#include <stb_image.h>
#include <stb_image_write.h>
#ifdef SVETLO_HAS_LIBJPEG
#include <jpeglib.h>

#include <csetjmp>
#include <cstdlib>
#endif

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "svetlo/core/atomic_file.h"
#include "svetlo/core/crc32.h"
#include "svetlo/core/error.h"
#include "svetlo/core/input_file.h"
#include "svetlo/core/parallel.h"

namespace svetlo {
namespace fs = std::filesystem;

std::string lower_extension(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

namespace {

/// A PNG chunk: length, type, data and the CRC-32 of type and data (PNG spec, 5.3).
void append_png_chunk(std::vector<unsigned char>& png, const char type[4],
                      const std::string& data) {
    auto put32 = [&](uint32_t v) {
        for (int s = 24; s >= 0; s -= 8) png.push_back(static_cast<unsigned char>(v >> s));
    };
    put32(static_cast<uint32_t>(data.size()));
    size_t start = png.size();
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data.begin(), data.end());
    put32(crc32_of(png.data() + start, png.size() - start));
}

void write_png(const fs::path& path, const Image& image, PixelMeaning meaning, float exposure,
               const std::string& metadata) {
    std::vector<unsigned char> png = encode_png(image, meaning, exposure, metadata);
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
    if (!out.flush()) throw std::runtime_error("write failed");
}

/// The text of the PNG's iTXt or tEXt chunk named `key`, empty when there is none.
std::string read_png_text(const fs::path& path, const std::string& key) {
    std::ifstream in(path, std::ios::binary);
    char signature[8];
    if (!in.read(signature, 8) || std::memcmp(signature, "\x89PNG\r\n\x1a\n", 8) != 0)
        throw std::runtime_error("not a PNG file");
    const uintmax_t file_bytes = fs::file_size(path);
    while (true) {
        unsigned char head[8];
        if (!in.read(reinterpret_cast<char*>(head), 8)) return {};
        uint32_t length = (uint32_t{head[0]} << 24) | (uint32_t{head[1]} << 16) |
                          (uint32_t{head[2]} << 8) | uint32_t{head[3]};
        std::string type(reinterpret_cast<char*>(head + 4), 4);
        if (type == "IEND" || length > file_bytes) return {};
        if (type != "iTXt" && type != "tEXt") {
            in.seekg(static_cast<std::streamoff>(length) + 4, std::ios::cur);
            continue;
        }
        std::string data(length, '\0');
        if (!in.read(data.data(), length)) return {};
        in.seekg(4, std::ios::cur);  // the CRC
        size_t nul = data.find('\0');
        if (nul == std::string::npos || data.substr(0, nul) != key) continue;
        if (type == "tEXt") return data.substr(nul + 1);
        // iTXt: compression flag and method, language tag, translated keyword, then the text.
        if (nul + 2 >= data.size() || data[nul + 1] != 0) continue;  // compressed: not ours
        size_t lang = data.find('\0', nul + 3);
        if (lang == std::string::npos) continue;
        size_t translated = data.find('\0', lang + 1);
        if (translated == std::string::npos) continue;
        return data.substr(translated + 1);
    }
}

void write_pfm(const fs::path& path, const Image& image) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(std::strerror(errno));
    out << "PF\n" << image.width << " " << image.height << "\n-1.0\n";
    std::vector<float> row(static_cast<size_t>(image.width) * 3);
    for (int j = image.height - 1; j >= 0; --j) {  // PFM rows go bottom to top
        for (int i = 0; i < image.width; ++i) {
            for (int c = 0; c < 3; ++c) row[3 * i + c] = image.at(i, j)[c];
        }
        // x86-64 and aarch64 are little-endian, which the negative scale announces.
        out.write(reinterpret_cast<const char*>(row.data()),
                  static_cast<std::streamsize>(row.size() * sizeof(float)));
    }
    if (!out.flush()) throw std::runtime_error("write failed");
}

/// The message of a build without OpenEXR (the browser's).
constexpr const char* kNoOpenExr = "OpenEXR is not in this build: use .pfm or .png";

void write_exr(const fs::path& path, const Image& image, const std::string& metadata) {
#ifndef SVETLO_HAS_OPENEXR
    (void)path, (void)image, (void)metadata;
    throw std::runtime_error(kNoOpenExr);
#else
    Imf::Header header(image.width, image.height);
    if (!metadata.empty()) header.insert(kMetadataKey, Imf::StringAttribute(metadata));
    const char* names[3] = {"R", "G", "B"};
    for (const char* name : names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer frame;
    char* base = reinterpret_cast<char*>(const_cast<Color*>(image.pixels.data()));
    for (int c = 0; c < 3; ++c) {
        frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), sizeof(Color),
                                          sizeof(Color) * static_cast<size_t>(image.width)));
    }
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
#endif
}

}  // namespace

namespace {

/// The 8-bit RGB bytes of an image as PNG and JPEG hold them: radiance scaled by `exposure`,
/// clipped and sRGB-encoded; data clipped to [0, 1] and written linearly. Made band by band
/// of rows (convert), into `bytes`, 3 per pixel.
class EightBitRows {
public:
    EightBitRows(const Image& image, PixelMeaning meaning, float exposure)
        : bytes(image.pixels.size() * 3),
          image_(image),
          radiance_(meaning == PixelMeaning::Radiance),
          exposure_(exposure) {}

    std::vector<unsigned char> bytes;  // 3 per pixel, rows from the top

    /// Rows [row0, row1).
    void convert(int row0, int row1) {
        // The pixels' floats and the bytes as plain arrays, read and written through locals:
        // a write through unsigned char may alias anything, so bytes written through the
        // vector made the compiler load the image, the exposure and the table's address again
        // for each byte (bench/image_bench.cpp; docs/performance.md).
        static_assert(sizeof(Color) == 3 * sizeof(float));
        static const Srgb8Encoder srgb8;
        const Srgb8Encoder& encode = srgb8;
        const size_t row_bytes = 3 * static_cast<size_t>(image_.width);
        const auto* values = reinterpret_cast<const float*>(image_.pixels.data());
        unsigned char* out = bytes.data();
        const size_t begin = static_cast<size_t>(row0) * row_bytes,
                     end = static_cast<size_t>(row1) * row_bytes;
        const float scale = exposure_;
        if (radiance_) {
            for (size_t k = begin; k < end; ++k) out[k] = encode(values[k] * scale);
            return;
        }
        for (size_t k = begin; k < end; ++k) {
            const float v = values[k];
            const float clipped = std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f);
            out[k] = static_cast<unsigned char>(std::lround(clipped * 255.0f));
        }
    }

    /// Every row, in parallel: each byte depends on its own value only (the viewer encodes a
    /// frame per request, and this was most of the JPEG encoder's time: docs/performance.md).
    void convert_all() {
        const auto bands = static_cast<size_t>((image_.height + 15) / 16);
        parallel_for_each(bands, [&](size_t b) {
            const int first = static_cast<int>(b) * 16;
            convert(first, std::min(image_.height, first + 16));
        });
    }

private:
    const Image& image_;
    bool radiance_;
    float exposure_;
};

/// stb_image_write's callback: appends to a byte vector.
void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    auto* p = static_cast<unsigned char*>(data);
    out->insert(out->end(), p, p + size);
}

}  // namespace

#ifdef SVETLO_HAS_LIBJPEG
namespace {

/// libjpeg reports a failure by calling error_exit, which must not return: it jumps back
/// (the library's own way, jpeglib.h's example.c).
struct JpegError {
    jpeg_error_mgr manager;
    std::jmp_buf back;
};
[[noreturn]] void jpeg_fail(j_common_ptr info) {
    std::longjmp(reinterpret_cast<JpegError*>(info->err)->back, 1);
}

/// 8-bit RGB rows into a JPEG of `quality` by libjpeg(-turbo), in memory that *out holds
/// (malloc'ed, even on failure: the caller frees it); row(context, r) gives row r, asked for
/// in order. Plain C data only between setjmp and longjmp.
bool libjpeg_encode(const unsigned char* (*row)(void* context, int r), void* context, int width,
                    int height, int quality, unsigned char** out, unsigned long* size) {
    jpeg_compress_struct c;
    JpegError error;
    c.err = jpeg_std_error(&error.manager);
    error.manager.error_exit = jpeg_fail;
    if (setjmp(error.back)) {
        jpeg_destroy_compress(&c);
        return false;
    }
    jpeg_create_compress(&c);
    jpeg_mem_dest(&c, out, size);
    c.image_width = static_cast<JDIMENSION>(width);
    c.image_height = static_cast<JDIMENSION>(height);
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, quality, TRUE);
    c.dct_method = JDCT_IFAST;  // the fast integer DCT: a preview while the view moves
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) {
        JSAMPROW scanline =
            const_cast<unsigned char*>(row(context, static_cast<int>(c.next_scanline)));
        jpeg_write_scanlines(&c, &scanline, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    return true;
}

/// An image's 8-bit rows for libjpeg, made beside the encoding instead of before it: bands of
/// 16 rows (a 4:2:0 JPEG's row of blocks), each made by whichever of two threads takes it
/// first, the encoding one (while the band it needs is not ready) or one helper, both taking
/// the bands in order. The encoder's serial time (a viewer frame's last step) was the
/// conversion on two cores and then the encoding on one.
class RowsInOrder {
public:
    static constexpr int kBand = 16;

    RowsInOrder(const Image& image, PixelMeaning meaning, float exposure)
        : rows_(image, meaning, exposure),
          width_(image.width),
          height_(image.height),
          bands_((image.height + kBand - 1) / kBand),
          ready_(std::make_unique<std::atomic<bool>[]>(static_cast<size_t>(bands_))) {
        helper_.run([this] {
            while (convert_next()) {
            }
        });
    }
    ~RowsInOrder() { helper_.wait(); }
    RowsInOrder(const RowsInOrder&) = delete;
    RowsInOrder& operator=(const RowsInOrder&) = delete;

    /// Row r, once its band is made.
    const unsigned char* row(int r) {
        const int band = r / kBand;
        while (!ready_[static_cast<size_t>(band)].load(std::memory_order_acquire)) {
            if (!convert_next()) std::this_thread::yield();  // the helper is making it
        }
        return rows_.bytes.data() + static_cast<size_t>(r) * 3 * static_cast<size_t>(width_);
    }
    static const unsigned char* row_of(void* self, int r) {
        return static_cast<RowsInOrder*>(self)->row(r);
    }

private:
    /// Makes the next band nobody has taken; false when none is left.
    bool convert_next() {
        const int band = next_.fetch_add(1);
        if (band >= bands_) return false;
        rows_.convert(band * kBand, std::min(height_, (band + 1) * kBand));
        ready_[static_cast<size_t>(band)].store(true, std::memory_order_release);
        return true;
    }

    EightBitRows rows_;
    int width_, height_, bands_;
    std::unique_ptr<std::atomic<bool>[]> ready_;  // per band
    std::atomic<int> next_{0};                    // the next band to take
    TaskGroup helper_;                            // (last: it stops before the rest goes)
};

}  // namespace
#endif

std::vector<unsigned char> encode_jpeg(const Image& image, PixelMeaning meaning, float exposure,
                                       int quality) {
    std::vector<unsigned char> jpeg;
#ifdef SVETLO_HAS_LIBJPEG
    unsigned char* out = nullptr;
    unsigned long size = 0;
    bool ok = false;
    {
        RowsInOrder rows(image, meaning, exposure);
        ok = libjpeg_encode(&RowsInOrder::row_of, &rows, image.width, image.height, quality, &out,
                            &size);
    }
    if (ok) jpeg.assign(out, out + size);
    std::free(out);
    if (!ok) throw std::runtime_error("cannot write JPEG");
#else
    EightBitRows rows(image, meaning, exposure);
    rows.convert_all();
    if (!stbi_write_jpg_to_func(append_bytes, &jpeg, image.width, image.height, 3,
                                rows.bytes.data(), quality))
        throw std::runtime_error("cannot write JPEG");
#endif
    return jpeg;
}

std::vector<unsigned char> encode_png(const Image& image, PixelMeaning meaning, float exposure,
                                      const std::string& metadata) {
    EightBitRows rows(image, meaning, exposure);
    rows.convert_all();
    const std::vector<unsigned char>& bytes = rows.bytes;
    std::vector<unsigned char> png;
    if (!stbi_write_png_to_func(append_bytes, &png, image.width, image.height, 3, bytes.data(),
                                image.width * 3)) {
        throw std::runtime_error("cannot write PNG");
    }
    if (!metadata.empty()) {
        // An uncompressed iTXt chunk (UTF-8 text) before IEND, the last 12 bytes: keyword,
        // NUL, compression flag and method, empty language tag and translated keyword.
        std::vector<unsigned char> end(png.end() - 12, png.end());
        png.resize(png.size() - 12);
        std::string itxt = std::string(kMetadataKey) + '\0' + '\0' + '\0' + '\0' + '\0' + metadata;
        append_png_chunk(png, "iTXt", itxt);
        png.insert(png.end(), end.begin(), end.end());
    }
    return png;
}

bool is_image_path(const fs::path& path) {
    std::string ext = lower_extension(path);
    return ext == ".png" || ext == ".pfm" || ext == ".exr";
}

ImageFormat image_format_for(const fs::path& path, const std::string& where) {
    std::string ext = lower_extension(path);
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".pfm") return ImageFormat::Pfm;
    if (ext == ".exr") return ImageFormat::Exr;
    throw Error(path.string(), where,
                "unknown image format '" + ext + "' (use .png, .pfm or .exr)");
}

void check_writable(const fs::path& path, const std::string& where) {
    image_format_for(path, where);
    check_creatable(path, where);
}

void check_creatable(const fs::path& path, const std::string& where) {
    if (fs::is_directory(path)) throw Error(path.string(), where, "is a directory");
    fs::path tmp = temporary_path(path);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) {
        throw Error(path.string(), where, std::string("cannot write: ") + std::strerror(errno));
    }
    std::fclose(f);
    std::error_code ec;
    fs::remove(tmp, ec);
}

void write_image(const fs::path& path, const Image& image, PixelMeaning meaning, float exposure,
                 const std::string& where, const std::string& metadata) {
    ImageFormat format = image_format_for(path, where);
    fs::path tmp = temporary_path(path);
    fs::path sidecar = path, sidecar_tmp;
    sidecar += ".json";
    try {
        switch (format) {
            case ImageFormat::Png:
                write_png(tmp, image, meaning, exposure, metadata);
                break;
            case ImageFormat::Pfm:
                write_pfm(tmp, image);
                if (!metadata.empty()) {  // PFM has no room for text: a file beside it
                    sidecar_tmp = temporary_path(sidecar);
                    std::ofstream out(sidecar_tmp, std::ios::binary);
                    out << metadata << "\n";
                    if (!out.flush()) throw std::runtime_error("write failed");
                }
                break;
            case ImageFormat::Exr:
                write_exr(tmp, image, metadata);
                break;
        }
        if (!sidecar_tmp.empty()) fs::rename(sidecar_tmp, sidecar);
        fs::rename(tmp, path);
        // A PFM without metadata replaces one that had it: the old sidecar would describe it.
        if (format == ImageFormat::Pfm && metadata.empty()) fs::remove(sidecar);
    } catch (const std::exception& e) {
        std::error_code ec;
        fs::remove(tmp, ec);
        if (!sidecar_tmp.empty()) fs::remove(sidecar_tmp, ec);
        throw Error(path.string(), where, std::string("cannot write: ") + e.what());
    }
}

std::string read_image_metadata(const fs::path& path, const std::string& where) {
    std::string problem = input_file_problem(path);
    if (!problem.empty()) throw Error(path.string(), where, problem);
    try {
        switch (image_format_for(path, where)) {
            case ImageFormat::Png:
                return read_png_text(path, kMetadataKey);
            case ImageFormat::Exr: {
#ifdef SVETLO_HAS_OPENEXR
                Imf::InputFile file(path.c_str());
                const auto* text =
                    file.header().findTypedAttribute<Imf::StringAttribute>(kMetadataKey);
                return text ? text->value() : std::string();
#else
                throw std::runtime_error(kNoOpenExr);
#endif
            }
            case ImageFormat::Pfm: {
                fs::path sidecar = path;
                sidecar += ".json";
                if (!fs::exists(sidecar)) return {};
                std::ifstream in(sidecar, std::ios::binary);
                std::ostringstream text;
                text << in.rdbuf();
                std::string json = text.str();
                while (!json.empty() && std::isspace(static_cast<unsigned char>(json.back())))
                    json.pop_back();  // the sidecar ends its line
                return json;
            }
        }
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path.string(), where, std::string("cannot read image: ") + e.what());
    }
    return {};
}

LoadedImage read_image(const fs::path& path, const std::string& where) {
    ImageFormat format = image_format_for(path, where);
    TextureImage texture = read_texture(path, true, kMaxFilmImageBytes, where);
    LoadedImage loaded;
    loaded.ldr = format == ImageFormat::Png;
    loaded.image = Image(texture.width(), texture.height());
    for (int j = 0; j < texture.height(); ++j) {
        for (int i = 0; i < texture.width(); ++i) loaded.image.at(i, j) = texture.texel(i, j);
    }
    return loaded;
}

}  // namespace svetlo
