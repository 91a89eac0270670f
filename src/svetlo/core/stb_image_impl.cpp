// The one translation unit that compiles Debian's stb_image and stb_image_write.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_FAILURE_USERMSG
// Only the formats svetlo documents (docs/scene-format.md, *Textures*). The others stb knows
// (PNM, PSD, GIF, PIC) are left out: fuzzing found signed overflow in its PNM header parser.
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_BMP
#define STBI_ONLY_TGA
#define STBI_ONLY_HDR
#include <stb_image.h>
#include <stb_image_write.h>
