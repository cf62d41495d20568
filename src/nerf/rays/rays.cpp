#include "nerf/rays/rays.h"

#include <string>

#include "vknerf/error.h"
#include "rays/rays_shared.h"

namespace vknerf::nerf {
namespace {
using Push = glsl::RaysPush;
constexpr uint32_t kLocal = 64;
}  // namespace

std::vector<CameraGpu> packCameras(std::span<const Camera> cameras, std::span<const PixelPlacement> placement) {
  if (!placement.empty() && placement.size() != cameras.size())
    throw Error("packCameras: " + std::to_string(placement.size()) + " pixel placements for " +
                std::to_string(cameras.size()) + " cameras");
  std::vector<CameraGpu> out;
  uint32_t first = 0;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i];
    checkLens(c, "camera " + std::to_string(i));
    const Lens& l = c.lens;
    const PixelPlacement at = placement.empty() ? PixelPlacement{0, first} : placement[i];
    CameraGpu g{{c.fx, c.fy, c.cx, c.cy}, {}, {c.width, c.height, at.firstPixel, at.binding}, {l.k1, l.k2, l.k3, l.k4},
                {l.k5, l.k6, l.p1, l.p2}, {uint32_t(l.model), 0, 0, 0}};
    for (int k = 0; k < 12; ++k) g.c2w[k] = c.c2w[k];
    first += c.width * c.height;
    out.push_back(g);
  }
  return out;
}

RayGeneration::RayGeneration(Context& ctx)
    : kernel_(ctx, {gpu::shaders::rays, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(Push), {}}) {}

void RayGeneration::record(gpu::Recorder& rec, const gpu::BufferRange& cameras, const Pixels& pixels,
                           const RayClip& clip, const RayOutputs& out) {
  const Aabb& box = clip.box;
  const float nearPlane = clip.nearPlane;
  const uint32_t mode = pixels.mode, camera = pixels.a, first = pixels.b, count = pixels.count;
  Push p{{box.min[0], box.min[1], box.min[2], nearPlane}, {box.max[0], box.max[1], box.max[2], 0}, mode, camera, first, count};
  rec.dispatch(kernel_, {cameras, out.rays, out.pixelIds}, p, gpu::groupsFor(count, kLocal), 1, 1, "rays");
}

void RayGeneration::recordImage(gpu::Recorder& rec, const gpu::BufferRange& cameras, const ImagePixels& pixels,
                                const RayClip& clip, const RayOutputs& out) {
  record(rec, cameras, {0, pixels.camera, pixels.firstPixel, pixels.count}, clip, out);
}

void RayGeneration::recordRandom(gpu::Recorder& rec, const gpu::BufferRange& cameras, const RandomPixels& pixels,
                                 const RayClip& clip, const RayOutputs& out) {
  record(rec, cameras, {pixels.inCameraRuns ? 2u : 1u, pixels.numCameras, pixels.seed, pixels.count}, clip, out);
}

}  // namespace vknerf::nerf
