#include "vknerf/image_io.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "io/image/jpeg_decode.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

#include <stb/stb_image.h>  // implemented in stb_implementation.cpp
#include <stb/stb_image_write.h>

namespace vknerf {

using io::decodeJpeg;
using io::jpegSize;
using io::JpegSize;

namespace {

// The whole file: decoders are handed bytes, never a path, so that the format is checked first.
bool readFile(const std::string& path, std::vector<uint8_t>& bytes, std::string& why) {
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    why = errno ? std::strerror(errno) : "cannot open the file";
    return false;
  }
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) {
    why = "read error";
    return false;
  }
  if (bytes.size() > size_t(INT32_MAX)) {  // stb takes an int length
    why = "larger than 2 GiB";
    return false;
  }
  return true;
}

// Datasets hold PNG and JPEG photos, told apart by their signatures. stb guesses formats, and TGA
// has no signature: any bytes may decode as a TGA whose header claims a huge image that stb then
// loops over for seconds (found by fuzzing), so only PNG reaches stb; JPEG goes to libjpeg-turbo.
enum class Format { Png, Jpeg, Other };

Format formatOf(const uint8_t* data, size_t size) {
  static const uint8_t kPng[] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  static const uint8_t kJpeg[] = {0xff, 0xd8, 0xff};
  if (size >= sizeof kPng && std::equal(kPng, kPng + sizeof kPng, data)) return Format::Png;
  if (size >= sizeof kJpeg && std::equal(kJpeg, kJpeg + sizeof kJpeg, data)) return Format::Jpeg;
  return Format::Other;
}

// Null when every PNG chunk's claimed length fits in the bytes that follow it, else why not.
// stb_image 2.27 grows its IDAT buffer to a chunk's claimed length before reading the chunk, so a
// 10 KB file claiming a 1 GiB chunk made it allocate 2 GiB (found by fuzz/image_fuzzer.cpp).
const char* pngChunksOverrun(const uint8_t* data, size_t size) {
  size_t at = 8;  // after the signature; each chunk is length (4, big-endian), type (4), data, CRC (4)
  while (at + 8 <= size) {
    const uint64_t length = uint64_t(data[at]) << 24 | uint64_t(data[at + 1]) << 16 | uint64_t(data[at + 2]) << 8 |
                            uint64_t(data[at + 3]);
    if (length + 12 > size - at) return "corrupt PNG (a chunk claims more bytes than the file holds)";
    if (std::equal(data + at + 4, data + at + 8, "IEND")) return nullptr;
    at += 12 + length;
  }
  return nullptr;  // a file cut short between chunks: stb reports it
}

// The image size from the file's header; false when the format or the header is not readable.
bool headerSize(const uint8_t* data, size_t size, uint32_t& width, uint32_t& height) {
  switch (formatOf(data, size)) {
    case Format::Jpeg: {
      JpegSize s;
      if (!jpegSize(data, size, s)) return false;
      width = s.width, height = s.height;
      return true;
    }
    case Format::Png: {
      int w = 0, h = 0, channels = 0;
      if (!stbi_info_from_memory(data, int(size), &w, &h, &channels) || w <= 0 || h <= 0) return false;
      width = uint32_t(w), height = uint32_t(h);
      return true;
    }
    case Format::Other: break;
  }
  return false;
}

// The most pixels an image may claim: 1 GiB as RGBA8 (a 16384 x 16384 photo), so that a corrupt
// header cannot ask for an allocation the machine does not have.
constexpr uint64_t kMaxPixels = 1ull << 28;

}  // namespace

ImageRGBA8 loadImage(const std::string& path) {
  std::vector<uint8_t> bytes;
  std::string why;
  if (!readFile(path, bytes, why)) throw Error("cannot read image '" + path + "': " + why);
  return decodeImage(bytes.data(), bytes.size(), path);
}

ImageRGBA8 decodeImage(const uint8_t* data, size_t size, const std::string& name) {
  if (size > size_t(INT32_MAX)) throw Error("cannot read image '" + name + "': larger than 2 GiB");
  const Format format = formatOf(data, size);
  if (format == Format::Other) throw Error("cannot read image '" + name + "': not a PNG or JPEG file");
  if (const char* why = format == Format::Png ? pngChunksOverrun(data, size) : nullptr)
    throw Error("cannot read image '" + name + "': " + why);
  uint32_t w = 0, h = 0;
  if (headerSize(data, size, w, h) && uint64_t(w) * uint64_t(h) > kMaxPixels)
    throw Error("cannot read image '" + name + "': " + std::to_string(w) + "x" + std::to_string(h) +
                " pixels is more than vknerf loads (" + std::to_string(kMaxPixels) + ")");
  ImageRGBA8 img;
  if (format == Format::Jpeg) {
    decodeJpeg(data, size, name, img.width, img.height, img.rgba);
    return img;
  }
  int iw = 0, ih = 0, channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(data, int(size), &iw, &ih, &channels, 4);
  if (!pixels) {
    const char* why = stbi_failure_reason();
    throw Error("cannot read image '" + name + "': " + (why ? why : "unknown error"));
  }
  img.width = uint32_t(iw);
  img.height = uint32_t(ih);
  img.rgba.assign(pixels, pixels + size_t(iw) * size_t(ih) * 4);
  stbi_image_free(pixels);
  return img;
}

bool readImageSize(const std::string& path, uint32_t& width, uint32_t& height) {
  std::vector<uint8_t> bytes;
  std::string why;
  return readFile(path, bytes, why) && headerSize(bytes.data(), bytes.size(), width, height);
}

namespace {
void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
}
}  // namespace

std::vector<uint8_t> encodePng(uint32_t width, uint32_t height, int channels, const uint8_t* pixels) {
  std::vector<uint8_t> png;
  if (!stbi_write_png_to_func(appendBytes, &png, int(width), int(height), channels, pixels, int(width) * channels))
    throw Error("cannot encode a " + std::to_string(width) + "x" + std::to_string(height) + " PNG");
  return png;
}

void savePng(const std::string& path, const ImageRGBA8& image) {
  if (image.width == 0 || image.height == 0 || image.rgba.size() != size_t(image.width) * image.height * 4)
    throw Error("cannot write '" + path + "': image is empty or its pixel count does not match its size");
  const auto png = encodePng(image.width, image.height, 4, image.rgba.data());
  writeFileAtomically(path, png.data(), png.size());
}

// Averages the stored sRGB values, not linear light: the trainer fits and composites these same
// values, so a downscaled pixel is what supersampling the model's output at full resolution gives.
ImageRGBA8 downscaleImage(const ImageRGBA8& image, uint32_t factor) {
  if (factor == 0) throw Error("downscale factor must be at least 1");
  if (factor == 1) return image;
  if (image.width < factor || image.height < factor)
    throw Error("cannot downscale a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " image by " + std::to_string(factor));
  ImageRGBA8 out;
  out.width = image.width / factor;
  out.height = image.height / factor;
  out.rgba.resize(size_t(out.width) * out.height * 4);
  const uint64_t count = uint64_t(factor) * factor;
  for (uint32_t y = 0; y < out.height; ++y) {
    for (uint32_t x = 0; x < out.width; ++x) {
      uint64_t weighted[3] = {0, 0, 0}, plain[3] = {0, 0, 0}, alpha = 0;
      for (uint32_t dy = 0; dy < factor; ++dy) {
        const uint8_t* row = &image.rgba[(size_t(y * factor + dy) * image.width + size_t(x) * factor) * 4];
        for (uint32_t dx = 0; dx < factor; ++dx) {
          const uint8_t* p = row + 4 * dx;
          for (int c = 0; c < 3; ++c) {
            weighted[c] += uint64_t(p[c]) * p[3];
            plain[c] += p[c];
          }
          alpha += p[3];
        }
      }
      uint8_t* o = &out.rgba[(size_t(y) * out.width + x) * 4];
      // Round to nearest: (2n + d) / (2d).
      for (int c = 0; c < 3; ++c)
        o[c] = alpha ? uint8_t((2 * weighted[c] + alpha) / (2 * alpha)) : uint8_t((2 * plain[c] + count) / (2 * count));
      o[3] = uint8_t((2 * alpha + count) / (2 * count));
    }
  }
  return out;
}

std::vector<float> compositeOver(const ImageRGBA8& im, const std::array<float, 3>& bg) {
  std::vector<float> rgb(size_t(im.width) * im.height * 3);
  for (size_t p = 0; p < size_t(im.width) * im.height; ++p) {
    float a = im.rgba[p * 4 + 3] / 255.0f;
    for (int k = 0; k < 3; ++k) rgb[p * 3 + k] = im.rgba[p * 4 + k] / 255.0f * a + bg[k] * (1 - a);
  }
  return rgb;
}

}  // namespace vknerf
