#pragma once
// The binary little-endian PLY that vknerf writes, read back strictly by the tests: the header must
// be exactly vknerf's (vertices: float xyz, uchar rgb; faces, when there are any: uchar count, int
// ids), the body exactly its size. A point cloud is a Mesh without triangles.
#include <string>

#include "vknerf/mesh.h"

namespace vknerf::test {

// Throws std::runtime_error for a file that is not exactly that; `withFaces` says whether the
// header must declare the face element (a mesh) or must not (a point cloud).
Mesh readPly(const std::string& path, bool withFaces = true);

}  // namespace vknerf::test
