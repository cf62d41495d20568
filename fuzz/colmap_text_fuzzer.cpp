// The COLMAP text model reader, reached through Dataset::load. The input is cameras.txt, images.txt
// and points3D.txt separated by NUL bytes (which text files never hold); a file the input does not
// reach is left out of the model. images/ holds tiny images a.png, b.png and c.png, the names the
// seeds use.
#include <algorithm>
#include <array>

#include "scratch_folder.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"

using namespace vknerf::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fs::path scene = [] {
    const fs::path s = scratchFolder() / "colmap";
    for (const char* name : {"a.png", "b.png", "c.png"}) writeTinyPng(s / "images" / name, 8, 6);
    return s;
  }();
  const fs::path model = scene / "sparse" / "0";
  const std::array<const char*, 3> files = {"cameras.txt", "images.txt", "points3D.txt"};
  const uint8_t* begin = data;
  const uint8_t* end = data + size;
  for (const char* name : files) {
    if (begin > end) {
      std::error_code ec;
      fs::remove(model / name, ec);
      continue;
    }
    const uint8_t* stop = std::find(begin, end, uint8_t(0));
    writeBytes(model / name, begin, size_t(stop - begin));
    begin = stop + 1;
  }
  try {
    vknerf::Dataset::load(scene.string());
  } catch (const vknerf::Error&) {
    // A rejected model is the expected outcome of most inputs; anything else escapes and is reported.
  }
  return 0;
}
