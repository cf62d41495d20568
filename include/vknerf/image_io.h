#pragma once
// Image files in and out (stb_image / stb_image_write), and the box-filter downscale used by datasets.
#include <cstddef>
#include <cstdint>
#include <array>
#include <string>
#include <vector>

#include "vknerf/dataset.h"

namespace vknerf {

// PNG, JPEG (and whatever else stb_image reads) as straight-alpha RGBA8; grey and RGB files get
// alpha 255, 16-bit files are reduced to 8 bits. Throws vknerf::Error naming `path`.
ImageRGBA8 loadImage(const std::string& path);
// The same from a file's bytes already in memory; `name` names them in messages.
ImageRGBA8 decodeImage(const uint8_t* data, size_t size, const std::string& name);

// Width and height from the file header alone; false when the file cannot be read as an image.
bool readImageSize(const std::string& path, uint32_t& width, uint32_t& height);

// PNG file bytes of `channels` (1 to 4) 8-bit values per pixel, rows top to bottom.
std::vector<uint8_t> encodePng(uint32_t width, uint32_t height, int channels, const uint8_t* pixels);

// Writes an RGBA PNG with writeFileAtomically. Throws vknerf::Error naming `path`.
void savePng(const std::string& path, const ImageRGBA8& image);

// Averages each factor x factor block into one pixel, weighting colours by alpha (premultiplied
// averaging) so that transparent pixels do not bleed into the edges of an object; a fully
// transparent block keeps the plain average of its colours. A remainder of fewer than `factor`
// columns or rows at the right or bottom is dropped, which leaves pixel centres where the scaled
// intrinsics (f / factor, c / factor) put them. Throws vknerf::Error for factor 0 or an image
// smaller than the factor.
ImageRGBA8 downscaleImage(const ImageRGBA8& image, uint32_t factor);

// The image as the model is asked to reproduce it: straight alpha composited over `background`,
// 3 floats per pixel in [0, 1].
std::vector<float> compositeOver(const ImageRGBA8& image, const std::array<float, 3>& background);

}  // namespace vknerf
