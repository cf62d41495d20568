#pragma once
// COLMAP models for the tests and the fuzzers' seeds: poses in COLMAP's terms, and one model
// written as text (cameras.txt, images.txt, points3D.txt) or as binary (cameras.bin, images.bin,
// points3D.bin) the way COLMAP writes them. Free of gtest: fuzz/make_seeds.cpp uses it too.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace vknerf::test {

using Mat3 = std::array<double, 9>;  // row-major
using Vec3 = std::array<double, 3>;

Vec3 mul(const Mat3& R, const Vec3& v);
Mat3 transpose(const Mat3& R);

// Unit quaternion (w, x, y, z) of a rotation matrix.
std::array<double, 4> quaternion(const Mat3& R);

// World-to-camera (R, t) in COLMAP's OpenCV convention of an OpenGL camera-to-world pose.
struct W2c {
  Mat3 R;
  Vec3 t;
};
W2c fromOpenGl(const std::array<double, 16>& m);

struct ColmapCameraRecord {
  uint32_t id = 1;
  std::string model;  // COLMAP's name: "PINHOLE", "OPENCV", ...
  uint64_t width = 0, height = 0;
  std::vector<double> params;
};

struct ColmapPoint2D {
  double x = 0, y = 0;
  int64_t point3D = -1;  // -1: not triangulated
};

struct ColmapImageRecord {
  uint32_t id = 1;
  std::array<double, 4> q{1, 0, 0, 0};
  Vec3 t{0, 0, 0};
  uint32_t camera = 1;
  std::string name;
  std::vector<ColmapPoint2D> points2D;
};
// An image record for an OpenGL camera-to-world pose.
ColmapImageRecord imageRecord(uint32_t id, const std::array<double, 16>& c2w, uint32_t camera, const std::string& name);

struct ColmapPointRecord {
  uint64_t id = 1;
  Vec3 xyz{0, 0, 0};
  std::array<uint8_t, 3> rgb{128, 128, 128};
  double error = 0.5;
  std::vector<std::pair<uint32_t, uint32_t>> track;  // (IMAGE_ID, POINT2D_IDX)
};

struct ColmapModelRecords {
  std::vector<ColmapCameraRecord> cameras;
  std::vector<ColmapImageRecord> images;
  std::vector<ColmapPointRecord> points;  // no points3D file when empty
};

// Writes the model into `dir` (created), numbers printed exactly (%.17g) so that both forms hold
// the same values.
void writeColmapText(const std::filesystem::path& dir, const ColmapModelRecords& model);
void writeColmapBinary(const std::filesystem::path& dir, const ColmapModelRecords& model);

}  // namespace vknerf::test
