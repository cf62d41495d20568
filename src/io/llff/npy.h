#pragma once
// NumPy's .npy files (format versions 1.0 and 2.0), read strictly: little-endian float64 ('<f8')
// or float32 ('<f4') values, C order (or Fortran order for at most two dimensions), nothing before
// or after the data. Every other file is an error naming the file and the header field at fault.
// Debian 12 packages no small .npy reader (libxtensor-dev's xnpy.hpp comes with all of xtensor), and
// the format is a short header and raw values.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace vknerf::io::detail {

struct NpyArray {
  std::vector<uint64_t> shape;  // as the header states it; () for a scalar
  std::string descr;            // "<f8" or "<f4"
  std::vector<double> values;   // every element as a double, in C (row-major) order
};

// Parses the bytes of a .npy file; `name` (the file's path) begins every message. Throws
// vknerf::Error: "scene/poses_bounds.npy: .npy header field 'descr' is '<i8': ...".
NpyArray parseNpy(std::span<const uint8_t> bytes, const std::string& name);

// Reads and parses `path`; a file too short or too long for its header's shape is refused before
// its values are read.
NpyArray readNpy(const std::filesystem::path& path);

}  // namespace vknerf::io::detail
