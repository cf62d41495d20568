#pragma once
// JPEG decoding through libjpeg-turbo's TurboJPEG API (Debian's libturbojpeg0-dev): a well-kept,
// continuously fuzzed decoder, and several times faster than stb_image on phone-sized photos.
// stb_image 2.27 (Debian 12) reads and writes past its Huffman tables on corrupt JPEGs (found by
// fuzz/image_fuzzer.cpp), so JPEG bytes never reach stb.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vknerf::io {

struct JpegSize {
  uint32_t width = 0, height = 0;
};

// The image size from the JPEG header; false when the header cannot be read.
bool jpegSize(const uint8_t* data, size_t size, JpegSize& out);

// Decodes a whole JPEG into RGBA8 (alpha 255), `rgba` sized width * height * 4. Throws vknerf::Error
// "cannot read image '<name>': <libjpeg's reason>" for a corrupt or truncated file: a warning
// (data missing, a marker out of place) is an error too, so a damaged photo never trains as grey.
void decodeJpeg(const uint8_t* data, size_t size, const std::string& name, uint32_t& width, uint32_t& height,
                std::vector<uint8_t>& rgba);

}  // namespace vknerf::io
