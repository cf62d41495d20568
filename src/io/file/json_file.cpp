#include "io/file/json_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "vknerf/error.h"

namespace vknerf::io::detail {

namespace fs = std::filesystem;
using nlohmann::json;

[[noreturn]] void fieldError(const JsonFile& f, const std::string& field, const std::string& what) {
  throw Error(f.name() + ": field '" + field + "' " + what);
}

JsonFile readJson(const fs::path& path, const std::string& kind) {
  // A folder opens as a stream on Linux and fails only as it is read, with the library's words.
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error("'" + path.string() + "' is a folder, not a " + kind + " (a JSON file)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path.string() + "': " + std::strerror(errno));
  std::string text;
  try {
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::exception&) {
    throw Error("cannot read '" + path.string() + "' (" + kind + ")");
  }
  JsonFile f{path, {}};
  try {
    f.root = json::parse(text);
  } catch (const json::exception& e) {
    // Parse errors carry "at line L, column C"; a number overflow (1e999) names only the literal,
    // so its first occurrence in the text gives the position.
    std::string what = e.what();
    if (auto close = what.find("] "); what.rfind("[json.exception", 0) == 0 && close != std::string::npos)
      what = what.substr(close + 2);
    if (what.find(" at line ") == std::string::npos) {
      auto q0 = what.find('\''), q1 = what.rfind('\'');
      if (q0 != std::string::npos && q1 > q0 + 1) {
        if (size_t at = text.find(what.substr(q0 + 1, q1 - q0 - 1)); at != std::string::npos) {
          size_t line = 1 + size_t(std::count(text.begin(), text.begin() + long(at), '\n'));
          size_t column = at - (line > 1 ? text.rfind('\n', at) + 1 : 0) + 1;
          what = "at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + what;
        }
      }
    }
    throw Error(path.string() + ": invalid JSON: " + what);
  }
  if (!f.root.is_object()) throw Error(path.string() + ": invalid " + kind + ": the top level is not a JSON object");
  return f;
}

std::optional<double> optNumber(const JsonFile& f, const json& obj, const char* key, const std::string& prefix) {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return std::nullopt;
  if (!it->is_number()) fieldError(f, prefix + key, "must be a number");
  double v = it->get<double>();
  if (!std::isfinite(v)) fieldError(f, prefix + key, "is not finite");
  return v;
}

std::array<double, 16> readMatrixField(const JsonFile& f, const json& obj, const char* key, const std::string& prefix) {
  const std::string field = prefix + key;
  auto it = obj.find(key);
  if (it == obj.end()) fieldError(f, field, "is missing");
  const json& m = *it;
  auto bad = [&] { fieldError(f, field, "must be a 4x4 (or 3x4) array of numbers, as rows or flattened"); };
  if (!m.is_array()) bad();
  std::array<double, 16> out{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  const bool flat = m.size() == 16 || m.size() == 12;
  if (flat) {
    for (size_t i = 0; i < m.size(); ++i) {
      if (!m[i].is_number()) bad();
      out[i] = m[i].get<double>();
    }
    return out;
  }
  if (m.size() != 4 && m.size() != 3) bad();
  for (size_t r = 0; r < m.size(); ++r) {
    if (!m[r].is_array() || m[r].size() != 4) bad();
    for (size_t c = 0; c < 4; ++c) {
      if (!m[r][c].is_number()) bad();
      out[4 * r + c] = m[r][c].get<double>();
    }
  }
  return out;
}

}  // namespace vknerf::io::detail
