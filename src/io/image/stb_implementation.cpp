// The one translation unit that holds the stb implementations (image_io.cpp uses them).
//
// Built without UBSan's nonnull-attribute check (CMakeLists.txt): stb_image 2.27 copies a PNG's
// zero-length IDAT chunk with memcpy(NULL, p, 0) before it has allocated its data buffer, undefined
// by the letter of the C standard and harmless in practice (found by fuzz/image_fuzzer.cpp). Every
// other check stays on here, and vknerf's own code keeps all of them.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_FAILURE_USERMSG
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
