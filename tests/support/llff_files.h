#pragma once
// LLFF scenes for the tests and the fuzzers' seeds: .npy files as numpy's np.save writes them, and
// poses_bounds.npy rows from OpenGL camera-to-world poses. Free of gtest: fuzz/make_seeds.cpp uses it too.
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace vknerf::test {

struct NpyOptions {
  bool float32 = false;  // '<f4' instead of '<f8'
  int version = 1;       // 1: a 2-byte header length, 2: a 4-byte one
  bool fortran = false;  // the values stored column by column (fortran_order True); 2-D shapes only
};

// A .npy file of `values` (given in C order) with `shape`: the magic, the version, the header
// dict padded with spaces to a multiple of 64 bytes and ended by a newline, then the values.
inline std::string npyBytes(const std::vector<double>& values, const std::vector<uint64_t>& shape, const NpyOptions& o = {}) {
  std::string dims;
  for (size_t k = 0; k < shape.size(); ++k) dims += (k ? ", " : "") + std::to_string(shape[k]);
  if (shape.size() == 1) dims += ",";  // numpy writes (n,)
  std::string header = std::string("{'descr': '") + (o.float32 ? "<f4" : "<f8") +
                       "', 'fortran_order': " + (o.fortran ? "True" : "False") + ", 'shape': (" + dims + "), }";
  const size_t lengthBytes = o.version == 1 ? 2 : 4, prefix = 8 + lengthBytes;
  while ((prefix + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out = "\x93NUMPY";
  out += char(o.version);
  out += char(0);
  for (size_t k = 0; k < lengthBytes; ++k) out += char((header.size() >> (8 * k)) & 0xff);
  out += header;
  std::vector<double> stored = values;
  if (o.fortran && shape.size() == 2)
    for (uint64_t r = 0; r < shape[0]; ++r)
      for (uint64_t c = 0; c < shape[1]; ++c) stored[c * shape[0] + r] = values[r * shape[1] + c];
  for (double v : stored) {
    char bytes[8];
    if (o.float32) {
      const float f = float(v);
      std::memcpy(bytes, &f, 4);  // the tests run on little-endian hosts, as the format's '<' says
      out.append(bytes, 4);
    } else {
      std::memcpy(bytes, &v, 8);
      out.append(bytes, 8);
    }
  }
  return out;
}

// A poses_bounds.npy row of an OpenGL camera-to-world pose (right, up, back, position): the 3x5
// matrix [down, right, back, position, hwf] row by row, with down = -up, then near and far.
inline std::array<double, 17> llffRow(const std::array<double, 16>& c2w, double height, double width, double focal,
                                      double nearBound, double farBound) {
  std::array<double, 17> row{};
  const double hwf[3] = {height, width, focal};
  for (int k = 0; k < 3; ++k) {
    row[5 * k + 0] = -c2w[4 * k + 1];
    row[5 * k + 1] = c2w[4 * k + 0];
    row[5 * k + 2] = c2w[4 * k + 2];
    row[5 * k + 3] = c2w[4 * k + 3];
    row[5 * k + 4] = hwf[k];
  }
  row[15] = nearBound;
  row[16] = farBound;
  return row;
}

// The bytes of a poses_bounds.npy holding `rows`.
inline std::string poseBoundsBytes(const std::vector<std::array<double, 17>>& rows, const NpyOptions& o = {}) {
  std::vector<double> values;
  for (const auto& r : rows) values.insert(values.end(), r.begin(), r.end());
  return npyBytes(values, {rows.size(), 17}, o);
}

}  // namespace vknerf::test
