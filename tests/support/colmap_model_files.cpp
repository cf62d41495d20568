#include "support/colmap_model_files.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <type_traits>

#include "io/colmap/colmap_camera.h"

namespace vknerf::test {

namespace fs = std::filesystem;

Vec3 mul(const Mat3& R, const Vec3& v) {
  return {R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
          R[6] * v[0] + R[7] * v[1] + R[8] * v[2]};
}

Mat3 transpose(const Mat3& R) { return {R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8]}; }

// Shepperd's method: each branch divides by the largest of the four candidates.
std::array<double, 4> quaternion(const Mat3& R) {
  double tr = R[0] + R[4] + R[8];
  if (tr > 0) {
    double s = 2 * std::sqrt(tr + 1);
    return {s / 4, (R[7] - R[5]) / s, (R[2] - R[6]) / s, (R[3] - R[1]) / s};
  }
  if (R[0] > R[4] && R[0] > R[8]) {
    double s = 2 * std::sqrt(1 + R[0] - R[4] - R[8]);
    return {(R[7] - R[5]) / s, s / 4, (R[1] + R[3]) / s, (R[2] + R[6]) / s};
  }
  if (R[4] > R[8]) {
    double s = 2 * std::sqrt(1 + R[4] - R[0] - R[8]);
    return {(R[2] - R[6]) / s, (R[1] + R[3]) / s, s / 4, (R[5] + R[7]) / s};
  }
  double s = 2 * std::sqrt(1 + R[8] - R[0] - R[4]);
  return {(R[3] - R[1]) / s, (R[2] + R[6]) / s, (R[5] + R[7]) / s, s / 4};
}

W2c fromOpenGl(const std::array<double, 16>& m) {
  Mat3 c2wCv = {m[0], -m[1], -m[2], m[4], -m[5], -m[6], m[8], -m[9], -m[10]};  // flip camera y, z
  W2c out{transpose(c2wCv), {}};
  Vec3 c{m[3], m[7], m[11]}, rc = mul(out.R, c);
  out.t = {-rc[0], -rc[1], -rc[2]};
  return out;
}

ColmapImageRecord imageRecord(uint32_t id, const std::array<double, 16>& c2w, uint32_t camera, const std::string& name) {
  W2c p = fromOpenGl(c2w);
  ColmapImageRecord r;
  r.id = id;
  r.q = quaternion(p.R);
  r.t = p.t;
  r.camera = camera;
  r.name = name;
  return r;
}

namespace {

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void writeFile(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary);
  out << bytes;
  if (!out) throw std::runtime_error("cannot write '" + p.string() + "'");
}

// Little-endian fields, as COLMAP writes them on every machine it runs on.
struct Bytes {
  std::string s;
  template <class T>
  void put(T v) {
    uint64_t bits;
    if constexpr (std::is_same_v<T, double>)
      bits = std::bit_cast<uint64_t>(v);
    else
      bits = uint64_t(v);
    for (size_t i = 0; i < sizeof(T); ++i) s.push_back(char((bits >> (8 * i)) & 0xff));
  }
};

int modelId(const std::string& name) {
  const auto* m = io::detail::colmapModelByName(name);
  if (!m) throw std::runtime_error("no COLMAP camera model '" + name + "'");
  return m->id;
}

}  // namespace

void writeColmapText(const fs::path& dir, const ColmapModelRecords& model) {
  std::string cameras = "# Camera list with one line of data per camera:\n";
  for (const auto& c : model.cameras) {
    cameras += std::to_string(c.id) + " " + c.model + " " + std::to_string(c.width) + " " + std::to_string(c.height);
    for (double p : c.params) cameras += " " + number(p);
    cameras += "\n";
  }
  std::string images = "# Image list with two lines of data per image:\n";
  for (const auto& i : model.images) {
    images += std::to_string(i.id);
    for (double v : i.q) images += " " + number(v);
    for (double v : i.t) images += " " + number(v);
    images += " " + std::to_string(i.camera) + " " + i.name + "\n";
    std::string points;
    for (const auto& p : i.points2D)
      points += (points.empty() ? "" : " ") + number(p.x) + " " + number(p.y) + " " + std::to_string(p.point3D);
    images += points + "\n";
  }
  writeFile(dir / "cameras.txt", cameras);
  writeFile(dir / "images.txt", images);
  if (model.points.empty()) return;
  std::string points = "# 3D point list with one line of data per point:\n";
  for (const auto& p : model.points) {
    points += std::to_string(p.id);
    for (double v : p.xyz) points += " " + number(v);
    for (uint8_t c : p.rgb) points += " " + std::to_string(c);
    points += " " + number(p.error);
    for (const auto& [image, index] : p.track) points += " " + std::to_string(image) + " " + std::to_string(index);
    points += "\n";
  }
  writeFile(dir / "points3D.txt", points);
}

void writeColmapBinary(const fs::path& dir, const ColmapModelRecords& model) {
  Bytes cameras;
  cameras.put<uint64_t>(model.cameras.size());
  for (const auto& c : model.cameras) {
    cameras.put<uint32_t>(c.id);
    cameras.put<int32_t>(modelId(c.model));
    cameras.put<uint64_t>(c.width);
    cameras.put<uint64_t>(c.height);
    for (double p : c.params) cameras.put<double>(p);
  }
  Bytes images;
  images.put<uint64_t>(model.images.size());
  for (const auto& i : model.images) {
    images.put<uint32_t>(i.id);
    for (double v : i.q) images.put<double>(v);
    for (double v : i.t) images.put<double>(v);
    images.put<uint32_t>(i.camera);
    images.s += i.name;
    images.s.push_back('\0');
    images.put<uint64_t>(i.points2D.size());
    for (const auto& p : i.points2D) {
      images.put<double>(p.x);
      images.put<double>(p.y);
      images.put<uint64_t>(uint64_t(p.point3D));  // -1 is COLMAP's invalid id, all bits set
    }
  }
  writeFile(dir / "cameras.bin", cameras.s);
  writeFile(dir / "images.bin", images.s);
  if (model.points.empty()) return;
  Bytes points;
  points.put<uint64_t>(model.points.size());
  for (const auto& p : model.points) {
    points.put<uint64_t>(p.id);
    for (double v : p.xyz) points.put<double>(v);
    for (uint8_t c : p.rgb) points.put<uint8_t>(c);
    points.put<double>(p.error);
    points.put<uint64_t>(p.track.size());
    for (const auto& [image, index] : p.track) {
      points.put<uint32_t>(image);
      points.put<uint32_t>(index);
    }
  }
  writeFile(dir / "points3D.bin", points.s);
}

}  // namespace vknerf::test
