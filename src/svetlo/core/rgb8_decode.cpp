// PNG through libspng, JPEG through libjpeg-turbo (rgb8_decode.h). Each decodes straight
// into the texture's codes: no second copy of the image.
#include "svetlo/core/rgb8_decode.h"

#include <csetjmp>

#ifdef SVETLO_HAS_SPNG
#include <spng.h>
#endif
#ifdef SVETLO_HAS_LIBJPEG
#include <jpeglib.h>

#include <cstdio>  // jpeglib.h uses FILE without including it
#endif

#include "svetlo/core/image_signature.h"
#include "svetlo/core/large_array.h"

namespace svetlo {
namespace {

#ifdef SVETLO_HAS_SPNG
bool decode_png(const unsigned char* bytes, size_t size, int width, int height,
                std::vector<unsigned char>& codes) {
    // The chunks' CRCs and the stream's Adler-32 are not checked, as stb does not check them:
    // a damaged file still fails where its deflate stream or its sizes are wrong.
    struct Context {
        spng_ctx* ctx = spng_ctx_new(SPNG_CTX_IGNORE_ADLER32);
        ~Context() { spng_ctx_free(ctx); }
    } png;
    spng_ihdr header{};
    size_t bytes_out = 0;
    const auto w = static_cast<uint32_t>(width), h = static_cast<uint32_t>(height);
    if (!png.ctx || spng_set_crc_action(png.ctx, SPNG_CRC_USE, SPNG_CRC_USE) != 0 ||
        spng_set_png_buffer(png.ctx, bytes, size) != 0 ||
        spng_set_image_limits(png.ctx, w, h) != 0 || spng_get_ihdr(png.ctx, &header) != 0 ||
        header.width != w || header.height != h ||
        spng_decoded_image_size(png.ctx, SPNG_FMT_RGB8, &bytes_out) != 0 ||
        bytes_out != size_t{3} * w * h)
        return false;
    std::vector<unsigned char> out = large_buffer(bytes_out);
    if (spng_decode_image(png.ctx, out.data(), out.size(), SPNG_FMT_RGB8, 0) != 0) return false;
    codes = std::move(out);
    return true;
}
#endif

#ifdef SVETLO_HAS_LIBJPEG
/// libjpeg reports a failure by calling error_exit, which must not return: it jumps back
/// (the library's own way, jpeglib.h's example.c). Its warnings (a truncated file's missing
/// blocks) are not failures: the decoder fills the rest, as stb does.
struct JpegDecodeError {
    jpeg_error_mgr manager;
    std::jmp_buf back;
};

[[noreturn]] void jpeg_decode_fail(j_common_ptr info) {
    std::longjmp(reinterpret_cast<JpegDecodeError*>(info->err)->back, 1);
}

void jpeg_quiet(j_common_ptr, int) {}

/// Decodes into `rows` (3 x width x height bytes). Plain C data only between setjmp and
/// longjmp.
bool decode_jpeg_into(const unsigned char* bytes, size_t size, int width, int height,
                      unsigned char* rows) {
    jpeg_decompress_struct d;
    JpegDecodeError error;
    d.err = jpeg_std_error(&error.manager);
    error.manager.error_exit = jpeg_decode_fail;
    error.manager.emit_message = jpeg_quiet;
    if (setjmp(error.back)) {
        jpeg_destroy_decompress(&d);
        return false;
    }
    jpeg_create_decompress(&d);
    jpeg_mem_src(&d, bytes, static_cast<unsigned long>(size));
    if (jpeg_read_header(&d, TRUE) != JPEG_HEADER_OK ||
        d.image_width != static_cast<JDIMENSION>(width) ||
        d.image_height != static_cast<JDIMENSION>(height) ||
        (d.jpeg_color_space != JCS_GRAYSCALE && d.jpeg_color_space != JCS_YCbCr &&
         d.jpeg_color_space != JCS_RGB)) {
        jpeg_destroy_decompress(&d);
        return false;
    }
    d.out_color_space = JCS_RGB;
    jpeg_start_decompress(&d);
    const size_t stride = size_t{3} * static_cast<size_t>(width);
    while (d.output_scanline < d.output_height) {
        JSAMPROW row = rows + d.output_scanline * stride;
        jpeg_read_scanlines(&d, &row, 1);
    }
    jpeg_finish_decompress(&d);
    jpeg_destroy_decompress(&d);
    return true;
}

bool decode_jpeg(const unsigned char* bytes, size_t size, int width, int height,
                 std::vector<unsigned char>& codes) {
    std::vector<unsigned char> out =
        large_buffer(size_t{3} * static_cast<size_t>(width) * static_cast<size_t>(height));
    if (!decode_jpeg_into(bytes, size, width, height, out.data())) return false;
    codes = std::move(out);
    return true;
}
#endif

}  // namespace

bool decode_rgb8(const unsigned char* bytes, size_t size, int width, int height,
                 std::vector<unsigned char>& codes) {
    if (width <= 0 || height <= 0) return false;
#ifdef SVETLO_HAS_SPNG
    if (is_png(bytes, size)) return decode_png(bytes, size, width, height, codes);
#endif
#ifdef SVETLO_HAS_LIBJPEG
    if (is_jpeg(bytes, size)) return decode_jpeg(bytes, size, width, height, codes);
#endif
    (void)bytes, (void)size, (void)codes;
    return false;
}

bool png_decoded_by_libspng() {
#ifdef SVETLO_HAS_SPNG
    return true;
#else
    return false;
#endif
}

bool jpeg_decoded_by_libjpeg() {
#ifdef SVETLO_HAS_LIBJPEG
    return true;
#else
    return false;
#endif
}

}  // namespace svetlo
