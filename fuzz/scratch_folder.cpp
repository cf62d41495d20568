#include "scratch_folder.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <vector>

#include "vknerf/image_io.h"

namespace vknerf::fuzz {

const fs::path& scratchFolder() {
  static const fs::path folder = [] {
    std::string pattern = (fs::temp_directory_path() / "vknerf_fuzz_XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(scratchFolder(), ec);
    });
    return fs::path(pattern);
  }();
  return folder;
}

void writeBytes(const fs::path& path, const uint8_t* data, size_t size) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::abort();
  }
}

void writeTinyPng(const fs::path& path, uint32_t width, uint32_t height) {
  std::vector<uint8_t> rgba(size_t(width) * height * 4);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
      p[0] = uint8_t(x * 40), p[1] = uint8_t(y * 40), p[2] = uint8_t((x + y) * 20);
      p[3] = x < width / 3 ? 0 : 255;
    }
  const auto png = vknerf::encodePng(width, height, 4, rgba.data());
  writeBytes(path, png.data(), png.size());
}

}  // namespace vknerf::fuzz
