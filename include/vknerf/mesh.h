#pragma once
// A triangle mesh exported from a trained field (Model::extractMesh) and its file format.
//
//   auto mesh = vknerf::Model::load(ctx, "tabletop.vknerf").extractMesh({.resolution = 256});
//   vknerf::writePly("tabletop.ply", mesh);
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vknerf/camera.h"

namespace vknerf {

struct Mesh {
  std::vector<float> positions;     // xyz per vertex, world coordinates
  std::vector<uint8_t> colors;      // rgb per vertex
  std::vector<uint32_t> triangles;  // 3 vertex ids per triangle, counter-clockwise seen from outside
  // What extraction cost: the density samples queried (MeshSettings::occupiedOnly skips some of the
  // grid's), and the grid's samples in all.
  uint64_t densityQueries = 0, gridSamples = 0;
};

struct MeshSettings {
  // Density samples along the longest side of the box; the other sides get as many as keep the
  // cells cubic (at least 2).
  uint32_t resolution = 256;
  // The surface's density: what makes about half of one render march step opaque on the sample
  // scene's fast model (1 - exp(-sigma dt) ~ 0.5 with dt = box diagonal / 1024 ~ 0.0017).
  float threshold = kDefaultThreshold;
  static constexpr float kDefaultThreshold = 50.0f;
  std::optional<Aabb> box;  // the region sampled; none: the model's scene box
  // Sample the density only near the cells the model's occupancy grid marks occupied (the fast
  // model; the vanilla model has none and samples the whole box), the rest of the grid taken as
  // empty: the same surface wherever a render can see one, for a fraction of the field queries.
  // Needs a positive threshold. false: the whole box.
  bool occupiedOnly = true;
};

// The mesh as binary little-endian PLY (vertices: float x y z, uchar red green blue; faces: uchar
// count, int indices), written atomically (vknerf/file_output.h).
void writePly(const std::string& path, const Mesh& mesh);

}  // namespace vknerf
