#pragma once
// A check stb_image 2.27 (Debian 12's libstb-dev) lacks: a JPEG Huffman table (DHT) of more than
// 256 codes makes stbi__build_huffman and the table read after it write past their 256- and
// 257-entry arrays. stb 2.28 rejects such a table ("bad DHT header"); until then vknerf refuses the
// file before stb sees it. Found by fuzz/image_fuzzer.cpp.
#include <cstddef>
#include <cstdint>

namespace vknerf::nerf {

// False when `data` is a JPEG (starts with the SOI marker) holding a Huffman table whose code
// counts add up to more than 256; true for anything else, valid or not (stb judges the rest).
bool jpegHuffmanTablesFit(const uint8_t* data, size_t size);

}  // namespace vknerf::nerf
