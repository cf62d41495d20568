// Images through stb_image (PNG, JPEG and the rest): decodeImage from the input's bytes, then what a
// dataset does with a decoded image (downscale, composite over a background).
#include "vknerf/image_io.h"
#include "vknerf/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vknerf;
  try {
    const vknerf::ImageRGBA8 image = decodeImage(data, size, "input");
    if (image.width >= 2 && image.height >= 2) downscaleImage(image, 2);
    compositeOver(image, {0.5f, 0.5f, 0.5f});
  } catch (const vknerf::Error&) {
    // A rejected image is the expected outcome of most inputs; anything else escapes and is reported.
  }
  return 0;
}
