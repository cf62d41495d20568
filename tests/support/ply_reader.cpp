#include "support/ply_reader.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace vknerf::test {

Mesh readPly(const std::string& path, bool withFaces) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t end = bytes.find("end_header\n");
  if (end == std::string::npos) throw std::runtime_error(path + ": no end_header");
  std::istringstream header(bytes.substr(0, end));
  std::string line, words;
  size_t vertices = 0, faces = 0;
  while (std::getline(header, line)) {
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
    if (line.rfind("element face ", 0) == 0) faces = std::stoul(line.substr(13));
    if (line.rfind("comment", 0) != 0 && line.rfind("element vertex", 0) != 0 && line.rfind("element face ", 0) != 0)
      words += line + "|";
    if (line.rfind("element face ", 0) == 0) words += "element face|";
  }
  const std::string expected =
      "ply|format binary_little_endian 1.0|property float x|property float y|property float z|"
      "property uchar red|property uchar green|property uchar blue|" +
      std::string(withFaces ? "element face|property list uchar int vertex_indices|" : "");
  if (words != expected) throw std::runtime_error(path + ": header " + words + " is not " + expected);
  const char* p = bytes.data() + end + 11;
  if (size_t(bytes.data() + bytes.size() - p) != vertices * 15 + faces * 13)
    throw std::runtime_error(path + ": the body is not the size the header says");
  Mesh m;
  m.positions.resize(vertices * 3);
  m.colors.resize(vertices * 3);
  m.triangles.resize(faces * 3);
  for (size_t v = 0; v < vertices; ++v, p += 15) {
    std::memcpy(&m.positions[3 * v], p, 12);
    std::memcpy(&m.colors[3 * v], p + 12, 3);
  }
  for (size_t f = 0; f < faces; ++f, p += 13) {
    if (p[0] != 3) throw std::runtime_error(path + ": a face is not a triangle");
    std::memcpy(&m.triangles[3 * f], p + 1, 12);
  }
  return m;
}

}  // namespace vknerf::test
