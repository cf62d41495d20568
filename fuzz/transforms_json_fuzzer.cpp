// The transforms.json reader, reached as the command line reaches it (Dataset::load): the input is a
// scene's transforms.json, beside train/ and test/ folders holding tiny images r_0 to r_2, the
// names the seeds use.
#include "scratch_folder.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"

using namespace vknerf::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fs::path scene = [] {
    const fs::path s = scratchFolder() / "transforms";
    for (const char* split : {"train", "test"})
      for (int i = 0; i < 3; ++i) writeTinyPng(s / split / ("r_" + std::to_string(i) + ".png"), 8, 6);
    return s;
  }();
  writeBytes(scene / "transforms.json", data, size);
  try {
    vknerf::Dataset::load(scene.string());
  } catch (const vknerf::Error&) {
    // A rejected file is the expected outcome of most inputs; anything else escapes and is reported.
  }
  return 0;
}
