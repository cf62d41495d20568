#include "kernels/selfcheck.h"

#include <algorithm>
#include <cmath>

#include "gpu/dispatch/recorder.h"
#include "vknerf/camera.h"
#include "nerf/render/composite.h"
#include "nerf/sampling/points.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/samplers.h"
#include "reference/render/composite.h"
#include "kernels/field_analytic_reference.h"
#include "reference/rays/rays.h"
#include "reference/sampling/samplers.h"

namespace vknerf::nerf {
namespace {

constexpr float kNear = 0.05f;
constexpr float kPadding = 1e-5f;
const std::array<float, 3> kBackground{1, 1, 1};

Camera selfCheckCamera(uint32_t size) {
  // On the +x/+z diagonal, slightly above, looking at the origin.
  return pinholeFromFocal(size, size, 1.2f * float(size), lookAt({2.4f, 0.9f, 2.1f}, {0, 0, 0}, {0, 1, 0}));
}

struct RefPixel {
  std::array<double, 3> rgb;
  double opacity, depth;
};

RefPixel referencePixel(const Camera& cam, const Aabb& box, uint32_t pixel, uint32_t nc, uint32_t nf) {
  auto ray = ref::cameraRay<double>(cam, pixel % cam.width, pixel / cam.width);
  ref::intersectAabb(ray, box, double(kNear));
  auto shade = [&](const std::vector<ref::Sample<double>>& s) {
    std::vector<double> flat, field;
    for (auto& x : s) {
      flat.insert(flat.end(), {x.t, x.delta});
      std::array<double, 3> p;
      for (int k = 0; k < 3; ++k)
        p[k] = 2 * (ray.o[k] + x.t * ray.d[k] - box.min[k]) / double(box.max[k] - box.min[k]) - 1;
      auto f = ref::analyticField(p);
      field.insert(field.end(), f.begin(), f.end());
    }
    return ref::compositeForward<double>(flat, field, {kBackground[0], kBackground[1], kBackground[2]});
  };
  auto coarse = ref::stratifiedSamples<double>(ray.tNear, ray.tFar, nc, 0, pixel, false);
  auto c = shade(coarse);
  std::vector<double> ts;
  for (auto& s : coarse) ts.push_back(s.t);
  auto fine = ref::importanceSamples<double>(ray.tNear, ray.tFar, ts, c.weights, nf, 1, pixel, false, kPadding);
  auto f = shade(fine);
  return {f.rgb, f.opacity, f.depth};
}

}  // namespace

SelfCheckResult selfCheck(Context& ctx, uint32_t size, uint32_t nc, uint32_t nf) {
  const Camera cam = selfCheckCamera(size);
  const Aabb box;  // [-1, 1]^3
  const uint32_t R = size * size, nAll = nc + nf;
  auto cams = packCameras(std::span<const Camera>(&cam, 1));
  auto camBuf = gpu::Buffer::of(ctx, cams);
  gpu::Buffer rays(ctx, R * kRayBytes), ids(ctx, R * kPixelIdBytes);
  gpu::Buffer coarse(ctx, VkDeviceSize(R) * nc * kSampleBytes), fine(ctx, VkDeviceSize(R) * nAll * kSampleBytes);
  gpu::Buffer pos(ctx, VkDeviceSize(R) * nAll * kPointBytes), dir(ctx, VkDeviceSize(R) * nAll * kPointBytes);
  gpu::Buffer field(ctx, VkDeviceSize(R) * nAll * kFieldBytes), weights(ctx, VkDeviceSize(R) * nAll * 4);
  gpu::Buffer color(ctx, R * 16), depth(ctx, R * 4), noOffsets(ctx, 16);

  RayGeneration rayGen(ctx);
  StratifiedSampler stratified(ctx);
  PdfSampler pdf(ctx);
  SamplePoints points(ctx);
  Compositor compositor(ctx);
  gpu::Kernel analytic(ctx, {gpu::shaders::field_analytic, {gpu::Binding::Storage, gpu::Binding::Storage}, 4, {}});

  gpu::Recorder rec(ctx, true);
  rec.begin();
  rayGen.recordImage(rec, camBuf, {0, 0, R}, {box, kNear}, {rays, ids});
  stratified.record(rec, {rays, R}, nc, {0, false}, coarse);
  auto shade = [&](const gpu::Buffer& samples, uint32_t spr) {
    const uint32_t n = R * spr;
    points.record(rec, {rays, R}, samples, spr, box, {pos, dir});
    rec.dispatch(analytic, {pos, field}, n, gpu::groupsFor(n, 64), 1, 1, "field_analytic");
    compositor.recordForward(rec, {R, spr, noOffsets, samples, field, kBackground}, {color, depth, weights});
  };
  shade(coarse, nc);
  pdf.record(rec, {rays, R}, {coarse, weights, nc}, {nf, {1, false}, kPadding}, fine);
  shade(fine, nAll);
  rec.end();
  rec.submitAndWait();

  SelfCheckResult out;
  out.width = out.height = size;
  out.kernelMilliseconds = rec.timings();
  auto rgba = color.download<float>(size_t(R) * 4);
  auto d = depth.download<float>(R);
  for (uint32_t p = 0; p < R; ++p) {
    RefPixel rp = referencePixel(cam, box, p, nc, nf);
    for (int k = 0; k < 3; ++k) {
      out.rgb.push_back(rgba[4 * p + k]);
      out.referenceRgb.push_back(float(rp.rgb[k]));
      out.maxColorError = std::max(out.maxColorError, std::abs(rgba[4 * p + k] - rp.rgb[k]));
    }
    out.maxOpacityError = std::max(out.maxOpacityError, std::abs(rgba[4 * p + 3] - rp.opacity));
    out.maxDepthError = std::max(out.maxDepthError, std::abs(d[p] - rp.depth));
  }
  return out;
}

}  // namespace vknerf::nerf
