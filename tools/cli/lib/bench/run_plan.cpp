#include "lib/bench/run_plan.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include "vknerf/error.h"

namespace vknerf::bench {
namespace {

namespace fs = std::filesystem;

std::string fileSafe(const std::string& name) {
  std::string out = name;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
  return out;
}

// The absolute path without a trailing separator, "." or "..".
fs::path cleanAbsolute(const std::string& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (!p.has_filename() && p.has_parent_path()) p = p.parent_path();
  return p;
}

bool isNamed(const std::string& argument) {
  const size_t eq = argument.find('='), slash = argument.find('/');
  return eq != std::string::npos && eq > 0 && (slash == std::string::npos || eq < slash);
}

}  // namespace

std::string sceneName(const std::string& path) {
  fs::path p = cleanAbsolute(path);
  std::error_code ec;
  if (!fs::is_directory(p, ec)) p = p.parent_path();  // transforms.json, a COLMAP file: its folder
  const std::string name = p.filename().string();
  const bool digits = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  if (digits && p.parent_path().filename() == "sparse") p = p.parent_path().parent_path();  // SCENE/sparse/0
  else if (name == "sparse") p = p.parent_path();                                            // SCENE/sparse
  return p.filename().string();
}

std::string buildPath(const std::string& argument) {
  return isNamed(argument) ? argument.substr(argument.find('=') + 1) : argument;
}

std::vector<std::string> buildNames(const std::vector<std::string>& binaries) {
  // components[i][k]: binary i's path k folders up from the file (k = 0: the file itself).
  std::vector<std::vector<std::string>> components;
  size_t depth = 0;
  for (const std::string& b : binaries) {
    std::vector<std::string> c;
    for (fs::path p = cleanAbsolute(buildPath(b)); p.has_filename(); p = p.parent_path()) c.push_back(p.filename().string());
    depth = std::max(depth, c.size());
    components.push_back(std::move(c));
  }
  const auto at = [&](size_t i, size_t k) { return k < components[i].size() ? components[i][k] : std::string(); };
  const auto distinctAt = [&](size_t k) {
    std::set<std::string> seen;
    for (size_t i = 0; i < binaries.size(); ++i)
      if (at(i, k).empty() || !seen.insert(at(i, k)).second) return false;
    return true;
  };
  size_t level = 0;  // the file names, when no folder tells the binaries apart
  if (binaries.size() == 1) {
    level = std::min<size_t>(2, depth - 1);  // PROJECT of PROJECT/build/vknerf
  } else {
    for (size_t k = 1; k < depth; ++k)
      if (distinctAt(k)) {
        level = k;
        break;
      }
  }
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (size_t i = 0; i < binaries.size(); ++i) {
    std::string name = fileSafe(isNamed(binaries[i]) ? binaries[i].substr(0, binaries[i].find('=')) : at(i, level));
    if (name.empty()) name = "build" + std::to_string(i + 1);
    if (!seen.insert(name).second)
      throw Error("--vknerf: two builds would both be named \"" + name + "\"; name them as NAME=PATH");
    names.push_back(name);
  }
  return names;
}

std::vector<size_t> buildOrder(size_t scene, size_t builds) {
  std::vector<size_t> order(builds);
  for (size_t i = 0; i < builds; ++i) order[i] = scene % 2 == 0 ? i : builds - 1 - i;
  return order;
}

}  // namespace vknerf::bench
