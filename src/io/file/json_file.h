#pragma once
// A JSON file read for its fields (transforms.json, a camera path), with messages that name the
// file and the field: "scene/transforms.json: field 'frames[3].transform_matrix' is missing".
#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace vknerf::io::detail {

struct JsonFile {
  std::filesystem::path path;
  nlohmann::json root;
  std::string name() const { return path.string(); }
};

[[noreturn]] void fieldError(const JsonFile& f, const std::string& field, const std::string& what);

// Parses `path`, whose top level must be an object; `kind` names the format in that error
// ("transforms file"). Parse errors give the line and column.
JsonFile readJson(const std::filesystem::path& path, const std::string& kind);

// obj[key] as a finite number, or nullopt when absent or null; `prefix` locates obj ("frames[3].").
std::optional<double> optNumber(const JsonFile& f, const nlohmann::json& obj, const char* key,
                                const std::string& prefix);

// obj[key] as a row-major 4x4 matrix: rows of 4 numbers (4 rows, or 3 with (0, 0, 0, 1) below),
// or the same flattened to 16 (or 12) numbers.
std::array<double, 16> readMatrixField(const JsonFile& f, const nlohmann::json& obj, const char* key,
                                       const std::string& prefix);

}  // namespace vknerf::io::detail
