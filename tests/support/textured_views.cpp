#include "support/textured_views.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "vknerf/image_io.h"

namespace vknerf::test {
namespace {

using V3 = std::array<double, 3>;
V3 add(V3 a, V3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 sub(V3 a, V3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 scale(V3 a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(V3 a, V3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 cross(V3 a, V3 b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
V3 normalize(V3 a) { return scale(a, 1 / std::sqrt(dot(a, a))); }

// Value noise: a hashed value in [0, 1] at each lattice point, smoothly interpolated.
double lattice(int64_t x, int64_t y, int64_t z, uint32_t seed) {
  uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ull ^ uint64_t(y) * 0xC2B2AE3D27D4EB4Full ^
               uint64_t(z) * 0x165667B19E3779F9ull ^ uint64_t(seed) * 0x27D4EB2F165667C5ull;
  h ^= h >> 31, h *= 0xBF58476D1CE4E5B9ull, h ^= h >> 29;
  return double(h >> 11) / double(1ull << 53);
}
double valueNoise(V3 p, uint32_t seed) {
  const double fx = std::floor(p[0]), fy = std::floor(p[1]), fz = std::floor(p[2]);
  auto smooth = [](double t) { return t * t * (3 - 2 * t); };
  const double u = smooth(p[0] - fx), v = smooth(p[1] - fy), w = smooth(p[2] - fz);
  const int64_t x = int64_t(fx), y = int64_t(fy), z = int64_t(fz);
  double r = 0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    r += (dx ? u : 1 - u) * (dy ? v : 1 - v) * (dz ? w : 1 - w) * lattice(x + dx, y + dy, z + dz, seed);
  }
  return r;
}
double octaves(V3 p, uint32_t seed) {
  double r = 0, amplitude = 0.5, frequency = 2;
  for (int o = 0; o < 4; ++o, amplitude *= 0.5, frequency *= 2) r += amplitude * valueNoise(scale(p, frequency), seed + o);
  return r;
}

struct Box {
  V3 lo, hi;
};
const Box kBoxes[] = {{{-0.6, 0, -0.6}, {0.6, 1.2, 0.6}}, {{1.1, 0, -1.4}, {1.9, 0.8, -0.6}}, {{-1.7, 0, 0.9}, {-1.1, 0.6, 1.5}}};
constexpr double kGround = 8;  // the ground is the square |x|, |z| <= kGround at y = 0

// Nearest hit of the ray o + t d: distance and surface normal; false for the sky.
bool trace(V3 o, V3 d, double& tHit, V3& normal) {
  tHit = 1e30;
  if (d[1] < 0) {
    const double t = -o[1] / d[1];
    const V3 p = add(o, scale(d, t));
    if (std::fabs(p[0]) <= kGround && std::fabs(p[2]) <= kGround) tHit = t, normal = {0, 1, 0};
  }
  for (const Box& b : kBoxes) {
    double t0 = 0, t1 = 1e30;
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
      double a = (b.lo[k] - o[k]) / d[k], c = (b.hi[k] - o[k]) / d[k];
      if (a > c) std::swap(a, c);
      if (a > t0) t0 = a, axis = k;
      t1 = std::min(t1, c);
    }
    if (axis >= 0 && t0 <= t1 && t0 < tHit) {
      tHit = t0;
      normal = {0, 0, 0};
      normal[axis] = d[axis] > 0 ? -1 : 1;
    }
  }
  return tHit < 1e30;
}

std::array<double, 3> shade(V3 o, V3 d) {
  double t;
  V3 n;
  if (!trace(o, d, t, n)) return {0.55, 0.65, 0.8};
  const V3 p = add(o, scale(d, t));
  const double light = 0.55 + 0.45 * std::max(0.0, dot(n, normalize({0.4, 0.8, 0.3})));
  // Smooth colour variation plus sharp-edged spots at two scales: corners and blobs for SIFT.
  const bool spot = valueNoise(scale(p, 9), 101) > 0.62, fine = valueNoise(scale(p, 23), 202) > 0.66;
  const double shade = spot ? 0.25 : fine ? 0.55 : 1.0;
  std::array<double, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = light * shade * (0.2 + 0.8 * octaves(p, 17 * uint32_t(k) + 1));
  return c;
}

}  // namespace

std::vector<TrueView> renderTexturedViews(const std::filesystem::path& folder, const TexturedViewsSpec& s) {
  std::filesystem::create_directories(folder);
  std::vector<TrueView> views;
  const V3 target{0, 0.3, 0};
  for (int v = 0; v < s.views; ++v) {
    const double azimuth = 2 * M_PI * v / s.views, height = v % 2 ? 4.0 : 3.0;
    const V3 eye{s.ringRadius * std::cos(azimuth), height, s.ringRadius * std::sin(azimuth)};
    const V3 back = normalize(sub(eye, target)), right = normalize(cross({0, 1, 0}, back)), up = cross(back, right);
    TrueView tv;
    char name[32];
    std::snprintf(name, sizeof name, "view_%02d.png", v);
    tv.name = name;
    tv.c2w = {right[0], up[0], back[0], eye[0], right[1], up[1], back[1], eye[1],
              right[2], up[2], back[2], eye[2], 0,        0,     0,       1};
    ImageRGBA8 img;
    img.width = uint32_t(s.width), img.height = uint32_t(s.height);
    img.rgba.resize(size_t(s.width) * s.height * 4);
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        std::array<double, 3> sum{};
        for (int sub = 0; sub < 4; ++sub) {  // 2x2 samples per pixel against aliasing
          const double px = x + 0.25 + 0.5 * (sub & 1), py = y + 0.25 + 0.5 * (sub >> 1);
          const V3 dc{(px - 0.5 * s.width) / s.focal, -(py - 0.5 * s.height) / s.focal, -1};
          const V3 d = normalize(add(add(scale(right, dc[0]), scale(up, dc[1])), scale(back, dc[2])));
          const auto c = shade(eye, d);
          for (int k = 0; k < 3; ++k) sum[k] += 0.25 * c[k];
        }
        uint8_t* p = &img.rgba[(size_t(y) * s.width + x) * 4];
        for (int k = 0; k < 3; ++k) p[k] = uint8_t(std::clamp(std::lround(255 * sum[k]), 0L, 255L));
        p[3] = 255;
      }
    vknerf::savePng((folder / tv.name).string(), img);
    views.push_back(tv);
  }
  return views;
}

}  // namespace vknerf::test
