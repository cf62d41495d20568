// A frame's camera: the intrinsics a file states completed from its image's size, and scaled to the
// downscaled copy of that image that is trained on.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

float asDeviceFloat(double v, const FrameSpec& f, const char* field) {
  if (!(std::fabs(v) <= kDeviceLimit)) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", v);
    throw Error(f.where + ": " + field + " value " + value + " is beyond the range the device computes with (|x| <= 1e15)");
  }
  return float(v);
}

}  // namespace

Camera completeCamera(const FrameSpec& f, uint32_t width, uint32_t height) {
  const Intrinsics& in = f.intrinsics;
  if ((in.width && in.width != width) || (in.height && in.height != height))
    throw Error(f.where + ": image '" + f.image.string() + "' is " + std::to_string(width) + "x" +
                std::to_string(height) + " but the camera says " + std::to_string(in.width) + "x" +
                std::to_string(in.height));
  // A resized copy of the image the intrinsics are stated for scales them axis by axis; both axes
  // must have shrunk alike, to within the rounding of one pixel.
  double sx = 1, sy = 1;
  if (in.statedWidth && in.statedHeight) {
    const double sw = in.statedWidth, sh = in.statedHeight;
    if (std::fabs(double(height) * sw - double(width) * sh) > std::max(sw, sh))
      throw Error(f.where + ": image '" + f.image.string() + "' is " + std::to_string(width) + "x" + std::to_string(height) +
                  ", not a copy of the " + std::to_string(in.statedWidth) + "x" + std::to_string(in.statedHeight) +
                  " the camera states scaled alike in width and height");
    // A folder of copies N times smaller holds them at the stated size over N, however rounded: a
    // size further off is a copy of other photos than those the intrinsics are stated for.
    if (const double n = in.statedFactor) {
      for (const auto& [got, stated, field] : {std::tuple{double(width), sw, &in.statedWidthField},
                                               std::tuple{double(height), sh, &in.statedHeightField}})
        if (!(std::fabs(got * n - stated) < n)) {
          char want[32];
          std::snprintf(want, sizeof want, "%g", stated / n);
          throw Error(f.where + ": image '" + f.image.string() + "' is " + std::to_string(width) + "x" +
                      std::to_string(height) + " but " + *field + " " + std::to_string(uint32_t(stated)) + " / " +
                      std::to_string(in.statedFactor) + " is " + want + ": its folder should hold the photos " +
                      std::to_string(in.statedFactor) + " times smaller than the " + std::to_string(in.statedWidth) +
                      "x" + std::to_string(in.statedHeight) + " the camera states");
        }
    }
    sx = double(width) / sw;
    sy = double(height) / sh;
  }
  double fx = in.fx * sx, fy = in.fy * sy;
  if (!std::isfinite(fx) && std::isfinite(in.angleX)) fx = 0.5 * width / std::tan(0.5 * in.angleX);
  if (!std::isfinite(fy) && std::isfinite(in.angleY)) fy = 0.5 * height / std::tan(0.5 * in.angleY);
  if (!std::isfinite(fx)) fx = fy;  // square pixels when only one focal length is stated
  if (!std::isfinite(fy)) fy = fx;
  if (!std::isfinite(fx)) throw Error(f.where + ": no focal length (" + in.focalFieldX + ")");
  if (!(fx > 0) || !(fy > 0)) throw Error(f.where + ": focal length must be positive");
  Camera c;
  // The focal length the file states is named first: the other may be derived from it.
  const bool xStated = std::isfinite(in.fx) || std::isfinite(in.angleX);
  const std::string fieldX = "focal length x (" + in.focalFieldX + ")", fieldY = "focal length y (" + in.focalFieldY + ")";
  if (!xStated) c.fy = asDeviceFloat(fy, f, fieldY.c_str());
  c.fx = asDeviceFloat(fx, f, fieldX.c_str());
  c.fy = asDeviceFloat(fy, f, fieldY.c_str());
  if (!(c.fx > 0) || !(c.fy > 0)) throw Error(f.where + ": focal length is too small for 32-bit floats");
  c.cx = asDeviceFloat(std::isfinite(in.cx) ? in.cx * sx : 0.5 * width, f, "principal point cx");
  c.cy = asDeviceFloat(std::isfinite(in.cy) ? in.cy * sy : 0.5 * height, f, "principal point cy");
  c.width = width;
  c.height = height;
  for (int i = 0; i < 16; ++i) c.c2w[i] = asDeviceFloat(f.c2w[i], f, f.poseField.c_str());
  // The coefficients are dimensionless, so the check at full resolution holds for every downscale:
  // the grid runs from edge to edge of the image, which bounds every pixel centre at any scale.
  c.lens = in.lens;
  checkLens(c, f.where);
  return c;
}

Camera downscaledCamera(const Camera& fullRes, uint32_t downscale, uint32_t width, uint32_t height) {
  Camera c = fullRes;
  // A downscaled pixel covers `downscale` full-resolution pixels, so its centre is at
  // downscale * (x + 0.5) in full-resolution pixels: every intrinsic divides by the factor.
  const float s = 1.0f / float(downscale);
  c.fx *= s;
  c.fy *= s;
  c.cx *= s;
  c.cy *= s;
  c.width = width;
  c.height = height;
  return c;
}

}  // namespace vknerf::io::detail
