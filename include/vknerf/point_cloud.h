#pragma once
// A coloured point cloud of what a trained model's renders see (vknerf export points): one point
// per pixel that the field makes opaque enough, at the pixel's expected depth along its ray.
//
//   vknerf::PointCloud cloud;
//   for (const auto& cam : data.cameras)
//     vknerf::appendVisiblePoints(cloud, cam, model.render(cam), 0.5f, model.config().background);
//   vknerf::writePly("points.ply", cloud);
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vknerf/camera.h"
#include "vknerf/rendered_image.h"

namespace vknerf {

struct PointCloud {
  std::vector<float> positions;  // xyz per point, world coordinates
  std::vector<uint8_t> colors;   // rgb per point
};

// Appends, for every pixel of `image` (rendered from `camera`) whose opacity exceeds `minOpacity`,
// the point at the pixel's expected depth along the ray through the pixel's centre (the ray the
// render marched, lens included), coloured by the field's own colour there: the rendered RGB with
// the background it was composited over taken back out, (rgb - (1 - opacity) background) / opacity,
// so that a half-transparent edge is not tinted by the background: the image's own per-pixel
// background when it has one (a render's: a learned far field differs per pixel), else `background`. Row-major pixel order. Throws
// vknerf::Error when the image's size is not the camera's.
void appendVisiblePoints(PointCloud& cloud, const Camera& camera, const RenderedImage& image, float minOpacity,
                         const std::array<float, 3>& background);

// The points as binary little-endian PLY (float x y z, uchar red green blue; no faces), written
// atomically (vknerf/file_output.h).
void writePly(const std::string& path, const PointCloud& cloud);

}  // namespace vknerf
