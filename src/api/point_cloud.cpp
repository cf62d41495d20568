// appendVisiblePoints: a rendered view's opaque pixels back-projected along the rays the render
// marched (the CPU twin of the ray generator, so lenses agree with the device).
#include "vknerf/point_cloud.h"

#include <string>

#include "api/unit_byte.h"
#include "core/camera/camera_ray.h"
#include "vknerf/error.h"

namespace vknerf {

void appendVisiblePoints(PointCloud& cloud, const Camera& camera, const RenderedImage& image, float minOpacity,
                         const std::array<float, 3>& background) {
  const size_t pixels = size_t(image.width) * image.height;
  if (image.width != camera.width || image.height != camera.height || image.opacity.size() != pixels ||
      image.depth.size() != pixels || image.rgb.size() != 3 * pixels)
    throw Error("points: a rendered image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " does not match its camera's " + std::to_string(camera.width) + "x" + std::to_string(camera.height));
  if (!image.background.empty() && image.background.size() != 3 * pixels)
    throw Error("points: a rendered image's background holds " + std::to_string(image.background.size()) +
                " values for " + std::to_string(pixels) + " pixels");
  const bool perPixel = !image.background.empty();
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      const size_t i = size_t(y) * image.width + x;
      if (!(image.opacity[i] > minOpacity)) continue;
      // depth is the expected distance along the unit direction from the camera's centre.
      const core::Ray<float> ray = core::cameraRay<float>(camera, x, y);
      const float a = image.opacity[i];  // > minOpacity >= 0
      const float* behind = perPixel ? &image.background[3 * i] : background.data();
      for (int k = 0; k < 3; ++k) {
        cloud.positions.push_back(ray.o[k] + image.depth[i] * ray.d[k]);
        cloud.colors.push_back(detail::unitToByte((image.rgb[3 * i + k] - (1 - a) * behind[k]) / a));
      }
    }
}

}  // namespace vknerf
