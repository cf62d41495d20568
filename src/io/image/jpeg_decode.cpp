#include "io/image/jpeg_decode.h"

#include <turbojpeg.h>

#include <memory>

#include "vknerf/error.h"

namespace vknerf::io {
namespace {

struct HandleDeleter {
  void operator()(void* h) const { tjDestroy(h); }
};
using Handle = std::unique_ptr<void, HandleDeleter>;

Handle decompressor() {
  Handle h(tjInitDecompress());
  if (!h) throw Error(std::string("cannot start the JPEG decoder: ") + tjGetErrorStr2(nullptr));
  return h;
}

}  // namespace

bool jpegSize(const uint8_t* data, size_t size, JpegSize& out) {
  Handle h = decompressor();
  int w = 0, hgt = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(h.get(), data, static_cast<unsigned long>(size), &w, &hgt, &subsampling, &colorspace) != 0 ||
      w <= 0 || hgt <= 0)
    return false;
  out = {uint32_t(w), uint32_t(hgt)};
  return true;
}

void decodeJpeg(const uint8_t* data, size_t size, const std::string& name, uint32_t& width, uint32_t& height,
                std::vector<uint8_t>& rgba) {
  Handle h = decompressor();
  auto fail = [&] { throw Error("cannot read image '" + name + "': " + tjGetErrorStr2(h.get())); };
  int w = 0, hgt = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(h.get(), data, static_cast<unsigned long>(size), &w, &hgt, &subsampling, &colorspace) != 0)
    fail();
  width = uint32_t(w);
  height = uint32_t(hgt);
  rgba.resize(size_t(width) * height * 4);
  // STOPONWARNING: truncated or damaged data is an error, not grey rows. LIMITSCANS: a progressive
  // file of thousands of scans (a decoding-time bomb) is refused.
  const int flags = TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS;
  if (tjDecompress2(h.get(), data, static_cast<unsigned long>(size), rgba.data(), w, 0, hgt, TJPF_RGBA, flags) != 0)
    fail();
}

}  // namespace vknerf::io
