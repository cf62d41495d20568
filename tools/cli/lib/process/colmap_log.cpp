#include "lib/process/colmap_log.h"

#include <cstdio>
#include <fstream>

namespace vknerf::process {
namespace {

// "<prefix>[a/b" anywhere in the line.
bool bracketCount(const std::string& line, const char* prefix, uint64_t& a, uint64_t& b) {
  const size_t at = line.find(prefix);
  if (at == std::string::npos) return false;
  unsigned long long x = 0, y = 0;
  if (std::sscanf(line.c_str() + at + std::char_traits<char>::length(prefix), "[%llu/%llu", &x, &y) != 2) return false;
  a = x, b = y;
  return true;
}

}  // namespace

bool readProgressLine(ColmapStage stage, const std::string& line, StageProgress& progress) {
  uint64_t a = 0, b = 0;
  switch (stage) {
    case ColmapStage::features:
      if (!bracketCount(line, "Processed file ", a, b)) return false;
      break;
    case ColmapStage::exhaustiveMatching: {
      // Blocks are visited row by row: block [i/n, j/n] is number (i - 1) * n + j of n * n.
      const size_t at = line.find("Matching block [");
      unsigned long long i = 0, n = 0, j = 0, m = 0;
      if (at == std::string::npos ||
          std::sscanf(line.c_str() + at, "Matching block [%llu/%llu, %llu/%llu]", &i, &n, &j, &m) != 4 || i == 0 ||
          j == 0)
        return false;
      a = (i - 1) * m + j, b = n * m;
      break;
    }
    case ColmapStage::sequentialMatching:
      if (!bracketCount(line, "Matching image ", a, b)) return false;
      break;
    case ColmapStage::mapping: {
      const size_t at = line.find("Registering image #");
      unsigned long long id = 0, count = 0;
      if (at == std::string::npos || std::sscanf(line.c_str() + at, "Registering image #%llu (%llu)", &id, &count) != 2)
        return false;
      a = count, b = progress.total;
      break;
    }
  }
  if (a == progress.done && b == progress.total) return false;
  progress.done = a, progress.total = b;
  return true;
}

const char* stageDescription(ColmapStage stage) {
  switch (stage) {
    case ColmapStage::features: return "feature extraction";
    case ColmapStage::exhaustiveMatching: return "exhaustive matching";
    case ColmapStage::sequentialMatching: return "sequential matching";
    case ColmapStage::mapping: return "mapping";
  }
  return "";
}

std::string failureReason(const std::string& logPath) {
  std::ifstream in(logPath);
  std::string line, error, last;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    const size_t text = line.find_first_not_of(' ');
    if (text == std::string::npos || line.find_first_not_of("=-") == std::string::npos) continue;
    const std::string body = line.substr(text);
    // glog: "F20261127 12:42:32.474221 17150 cache.h:132] Check failed: ..." (E for errors).
    unsigned date = 0, h = 0, m = 0;
    char severity = 0;
    if (std::sscanf(body.c_str(), "%c%u %u:%u:", &severity, &date, &h, &m) == 4 && (severity == 'F' || severity == 'E')) {
      if (const size_t at = body.find("] "); at != std::string::npos) error = body.substr(at + 2);
      continue;
    }
    if (body.rfind("ERROR: ", 0) == 0) {
      error = body;
      continue;
    }
    const bool trace = body.rfind("@ ", 0) == 0 || body.rfind("*** ", 0) == 0;
    if (!trace) last = body;
  }
  return error.empty() ? last : error;
}

const char* progressUnit(ColmapStage stage) {
  switch (stage) {
    case ColmapStage::features: return "images featured";
    case ColmapStage::exhaustiveMatching: return "blocks of pairs matched";
    case ColmapStage::sequentialMatching: return "images matched";
    case ColmapStage::mapping: return "images registered";
  }
  return "";
}

}  // namespace vknerf::process
