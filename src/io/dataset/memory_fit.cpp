#include "io/dataset/memory_fit.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "vknerf/error.h"

namespace vknerf::io {

uint64_t rgba8Bytes(std::span<const ImageSize> sizes, uint32_t downscale) {
  uint64_t total = 0;
  for (const auto& [w, h] : sizes) total += uint64_t(w / downscale) * (h / downscale) * 4;
  return total;
}

uint64_t availableHostBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  while (meminfo >> key >> kib) {
    if (key == "MemAvailable:") return kib * 1024;
    meminfo.ignore(256, '\n');
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : UINT64_MAX;
}

std::string mebibytes(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / double(1 << 20));
  return buf;
}

void requireFit(const std::string& what, std::span<const ImageSize> sizes, uint64_t fixedBytes,
                const std::string& fixedWhat, uint64_t available, const std::string& where, uint32_t downscaleNow) {
  const uint64_t pixels = rgba8Bytes(sizes);
  if (fixedBytes + pixels <= available) return;
  uint32_t smallestSide = UINT32_MAX;
  for (const auto& [w, h] : sizes) smallestSide = std::min({smallestSide, w, h});
  std::string advice = "; no --downscale makes it fit";
  for (uint32_t f = 2; f <= smallestSide; ++f)
    if (fixedBytes + rgba8Bytes(sizes, f) <= available) {
      advice = downscaleNow ? "; --downscale " + std::to_string(f * downscaleNow) + " would fit"
                            : "; " + std::to_string(f) + " times the current --downscale would fit";
      break;
    }
  throw Error(what + " needs " + mebibytes(fixedBytes + pixels) + " (" + std::to_string(sizes.size()) +
              " images: " + mebibytes(pixels) + (fixedBytes ? ", " + fixedWhat + ": " + mebibytes(fixedBytes) : "") +
              ") but " + where + " has " + mebibytes(available) + advice);
}

}  // namespace vknerf::io
