#pragma once
// Held-out quality of a model and the baseline it must beat: the best constant colour for the same
// views (their mean), which is what a model that learned nothing about geometry approaches.
#include <vector>

#include "vknerf/image_io.h"
#include "lib/metrics.h"
#include "vknerf/trainer.h"

namespace vknerf::test {

struct HeldOutScore {
  double psnr = 0, ssim = 0, constantPsnr = 0;
};

inline HeldOutScore scoreHeldOut(const Model& model, const Dataset& views, size_t count) {
  const auto& bg = model.config().background;
  std::vector<double> mean(3, 0.0);
  size_t pixels = 0;
  for (size_t i = 0; i < count; ++i) {
    auto gt = vknerf::compositeOver(views.images[i], bg);
    for (size_t p = 0; p < gt.size(); ++p) mean[p % 3] += gt[p];
    pixels += gt.size() / 3;
  }
  for (double& m : mean) m /= double(pixels);
  HeldOutScore s;
  for (size_t i = 0; i < count; ++i) {
    auto gt = vknerf::compositeOver(views.images[i], bg);
    RenderedImage img = model.render(views.cameras[i]);
    std::vector<float> constant(gt.size());
    for (size_t p = 0; p < gt.size(); ++p) constant[p] = float(mean[p % 3]);
    s.psnr += nerf::psnr(img.rgb, gt) / double(count);
    s.constantPsnr += nerf::psnr(constant, gt) / double(count);
    s.ssim += nerf::ssim(img.rgb, gt, img.width, img.height) / double(count);
  }
  return s;
}

}  // namespace vknerf::test
