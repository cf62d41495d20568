// LLFF's poses_bounds.npy reader, reached through Dataset::load: the input is the .npy file, beside
// images/ holding tiny images a.png, b.png and c.png (the seeds have three rows) and images_2/
// holding copies half their size, which the second load (downscale 2) reads.
#include "scratch_folder.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"

using namespace vknerf::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fs::path scene = [] {
    const fs::path s = scratchFolder() / "llff";
    for (const char* name : {"a.png", "b.png", "c.png"}) {
      writeTinyPng(s / "images" / name, 8, 6);
      writeTinyPng(s / "images_2" / name, 4, 3);
    }
    return s;
  }();
  writeBytes(scene / "poses_bounds.npy", data, size);
  vknerf::DatasetOptions half;
  half.split = "all";
  half.downscale = 2;
  for (const vknerf::DatasetOptions& options : {vknerf::DatasetOptions{}, half}) {
    try {
      vknerf::Dataset::load(scene.string(), options);
    } catch (const vknerf::Error&) {
      // A rejected file is the expected outcome of most inputs; anything else escapes and is reported.
    }
  }
  return 0;
}
