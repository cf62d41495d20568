#pragma once
// Photos of a textured scene with known poses, ray-cast on the CPU at test time, for running
// COLMAP end to end: a ground plane and three boxes carrying a multi-octave solid noise texture
// (the same colour at a point from every view, with detail down to a few pixels for SIFT), seen
// by a ring of pinhole cameras looking at the middle.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace vknerf::test {

struct TrueView {
  std::string name;              // file name in the folder
  std::array<double, 16> c2w;    // OpenGL convention (looks down -Z, +Y up), row-major
};

struct TexturedViewsSpec {
  int views = 24;
  int width = 320, height = 240;
  double focal = 300;            // pixels; principal point at the image centre
  double ringRadius = 5;         // the scene's size for position errors: the ring's diameter
};

// Writes spec.views PNG files into `folder` (created) and returns their true poses.
std::vector<TrueView> renderTexturedViews(const std::filesystem::path& folder, const TexturedViewsSpec& spec = {});

}  // namespace vknerf::test
