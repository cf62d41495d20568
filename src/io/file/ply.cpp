// writePly: binary little-endian PLY, the layout meshlab, Blender, Open3D and CloudCompare read.
#include <bit>
#include <cstring>
#include <string>

#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/mesh.h"
#include "vknerf/point_cloud.h"

namespace vknerf {
namespace {

static_assert(std::endian::native == std::endian::little, "PLY is written little-endian from memory");
constexpr size_t kVertexBytes = 15;  // float x y z, uchar red green blue

// The header, and the body sized for it with the vertices filled in; faces are the caller's.
std::string plyWithVertices(const std::vector<float>& positions, const std::vector<uint8_t>& colors,
                            const std::string& faceElement, size_t faceBytes) {
  const size_t vertices = positions.size() / 3;
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by vknerf\nelement vertex " +
                    std::to_string(vertices) +
                    "\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\n" +
                    faceElement + "end_header\n";
  const size_t header = out.size();
  out.resize(header + vertices * kVertexBytes + faceBytes);
  char* p = out.data() + header;
  for (size_t v = 0; v < vertices; ++v, p += kVertexBytes) {
    std::memcpy(p, &positions[3 * v], 12);
    std::memcpy(p + 12, &colors[3 * v], 3);
  }
  return out;
}

}  // namespace

void writePly(const std::string& path, const Mesh& mesh) {
  const size_t vertices = mesh.positions.size() / 3, faces = mesh.triangles.size() / 3;
  if (mesh.positions.size() % 3 || mesh.triangles.size() % 3 || mesh.colors.size() != mesh.positions.size())
    throw Error("PLY " + path + ": the mesh needs xyz and rgb per vertex and 3 indices per triangle");
  for (uint32_t i : mesh.triangles)
    if (i >= vertices) throw Error("PLY " + path + ": a triangle names vertex " + std::to_string(i) + " of " + std::to_string(vertices));
  std::string out = plyWithVertices(mesh.positions, mesh.colors,
                                    "element face " + std::to_string(faces) + "\nproperty list uchar int vertex_indices\n",
                                    faces * 13);
  char* p = out.data() + out.size() - faces * 13;
  for (size_t f = 0; f < faces; ++f, p += 13) {
    p[0] = 3;
    std::memcpy(p + 1, &mesh.triangles[3 * f], 12);  // ids < vertices <= INT_MAX: the same bits as int
  }
  writeFileAtomically(path, out.data(), out.size());
}

void writePly(const std::string& path, const PointCloud& cloud) {
  if (cloud.positions.size() % 3 || cloud.colors.size() != cloud.positions.size())
    throw Error("PLY " + path + ": the point cloud needs xyz and rgb per point");
  const std::string out = plyWithVertices(cloud.positions, cloud.colors, "", 0);
  writeFileAtomically(path, out.data(), out.size());
}

}  // namespace vknerf
