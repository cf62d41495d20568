// writePly: binary little-endian PLY, the layout meshlab, Blender and Open3D read.
#include <bit>
#include <cstring>
#include <string>

#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/mesh.h"

namespace vknerf {

void writePly(const std::string& path, const Mesh& mesh) {
  static_assert(std::endian::native == std::endian::little, "PLY is written little-endian from memory");
  const size_t vertices = mesh.positions.size() / 3, faces = mesh.triangles.size() / 3;
  if (mesh.positions.size() % 3 || mesh.triangles.size() % 3 || mesh.colors.size() != mesh.positions.size())
    throw Error("PLY " + path + ": the mesh needs xyz and rgb per vertex and 3 indices per triangle");
  for (uint32_t i : mesh.triangles)
    if (i >= vertices) throw Error("PLY " + path + ": a triangle names vertex " + std::to_string(i) + " of " + std::to_string(vertices));
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by vknerf\nelement vertex " +
                    std::to_string(vertices) +
                    "\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face " +
                    std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
  const size_t header = out.size();
  out.resize(header + vertices * 15 + faces * 13);
  char* p = out.data() + header;
  for (size_t v = 0; v < vertices; ++v, p += 15) {
    std::memcpy(p, &mesh.positions[3 * v], 12);
    std::memcpy(p + 12, &mesh.colors[3 * v], 3);
  }
  for (size_t f = 0; f < faces; ++f, p += 13) {
    p[0] = 3;
    std::memcpy(p + 1, &mesh.triangles[3 * f], 12);  // ids < vertices <= INT_MAX: the same bits as int
  }
  writeFileAtomically(path, out.data(), out.size());
}

}  // namespace vknerf
