// noteOnce (load_note.h).
#include "io/dataset/load_note.h"

#include <cstdio>
#include <mutex>
#include <set>

namespace vknerf::io::detail {

void noteOnce(const std::string& line) {
  static std::mutex lock;
  static std::set<std::string> said;
  std::lock_guard<std::mutex> hold(lock);
  if (!said.insert(line).second) return;
  std::fprintf(stderr, "vknerf: %s\n", line.c_str());
}

}  // namespace vknerf::io::detail
