// The COLMAP binary model reader, reached through Dataset::load. The input is cameras.bin,
// images.bin and points3D.bin separated by the marker "%%%%" (binary files may hold any byte, so no
// single byte can separate them; a marker that happens to sit inside a file only moves the cut);
// a file the input does not reach is left out of the model. images/ holds tiny images a.png, b.png
// and c.png, the names the seeds use.
#include <array>
#include <string_view>

#include "scratch_folder.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"

using namespace vknerf::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fs::path scene = [] {
    const fs::path s = scratchFolder() / "colmap_binary";
    for (const char* name : {"a.png", "b.png", "c.png"}) writeTinyPng(s / "images" / name, 8, 6);
    return s;
  }();
  static constexpr std::string_view kMarker = "%%%%";
  const fs::path model = scene / "sparse" / "0";
  const std::array<const char*, 3> files = {"cameras.bin", "images.bin", "points3D.bin"};
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  bool reached = true;
  for (const char* name : files) {
    if (!reached) {
      std::error_code ec;
      fs::remove(model / name, ec);
      continue;
    }
    const size_t cut = rest.find(kMarker);
    const std::string_view file = rest.substr(0, cut);
    writeBytes(model / name, reinterpret_cast<const uint8_t*>(file.data()), file.size());
    reached = cut != std::string_view::npos;
    if (reached) rest.remove_prefix(cut + kMarker.size());
  }
  try {
    vknerf::Dataset::load(scene.string());
  } catch (const vknerf::Error&) {
    // A rejected model is the expected outcome of most inputs; anything else escapes and is reported.
  }
  return 0;
}
