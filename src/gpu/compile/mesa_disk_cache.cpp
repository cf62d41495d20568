#include "gpu/compile/mesa_disk_cache.h"

#include <strings.h>

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace vknerf::gpu {
namespace {

namespace fs = std::filesystem;

std::string firstLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// Asleep on a futex: Mesa's queue threads wait on a condition variable only when their queue is
// empty (writing a file they run, or sleep elsewhere). Without a readable wchan, asleep at all.
bool waitingForWork(const fs::path& task) {
  const std::string stat = firstLine(task / "stat");
  const size_t paren = stat.rfind(')');  // the state follows the name, which may hold anything
  if (paren == std::string::npos || paren + 2 >= stat.size()) return true;  // gone
  if (stat[paren + 2] != 'S') return false;
  const std::string wchan = firstLine(task / "wchan");
  return wchan.empty() || wchan == "0" || wchan.find("futex") != std::string::npos;
}

}  // namespace

bool mesaShaderCacheDisabled() {
  const char* v = std::getenv("MESA_SHADER_CACHE_DISABLE");
  if (!v) v = std::getenv("MESA_GLSL_CACHE_DISABLE");
  return v && (!strcasecmp(v, "1") || !strcasecmp(v, "true") || !strcasecmp(v, "yes"));
}

bool isMesaCacheWriter(const char* name) {
  const char* at = std::strstr(name, ":disk$");
  if (!at) return false;
  const char* digits = at + 6;
  if (!*digits) return false;
  for (const char* c = digits; *c; ++c)
    if (!std::isdigit(static_cast<unsigned char>(*c))) return false;
  return true;
}

void waitForMesaCacheWriters(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::vector<fs::path> writers;
  std::error_code ec;
  for (fs::directory_iterator it("/proc/self/task", ec), end; !ec && it != end; it.increment(ec))
    if (isMesaCacheWriter(firstLine(it->path() / "comm").c_str())) writers.push_back(it->path());
  for (const fs::path& w : writers)
    while (!waitingForWork(w) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

}  // namespace vknerf::gpu
