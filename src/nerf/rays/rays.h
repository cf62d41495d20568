#pragma once
// Stage 1 of the data flow: camera rays clipped to the scene box (shaders/rays/rays.comp).
// Layouts: rays are 2 x vec4 per ray, (o, t_near) and (d, t_far), with (-1, -1) for a miss;
// pixel ids are (camera, pixel index within that camera's image) per ray.
#include <span>
#include <vector>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

struct CameraGpu {  // mirrors `struct Camera` in shaders/rays/camera.glsl (std430: vec4 / uvec4 members)
  float intrinsics[4];
  float c2w[12];
  uint32_t size[4];  // width, height, first pixel of this image in its pixel binding, that binding's index
  float lensK[4];    // k1, k2, k3, k4
  float lensKP[4];   // k5, k6, p1, p2
  uint32_t lensModel[4];  // LensModel, 0, 0, 0
};
static_assert(sizeof(CameraGpu) == 128);

// Where one camera's training image lies on the device: the binding (of the training pixels'
// several buffers) that holds the whole image, and the index of its first pixel there.
struct PixelPlacement {
  uint32_t binding = 0;
  uint32_t firstPixel = 0;
};

// Cameras as the shaders read them. Throws vknerf::Error (naming "camera <index>") for a lens
// checkLens() rejects, so that no camera reaches the device with a lens the ray generator cannot invert. Without `placement`, the images follow one another in binding 0
// (a render, or a training set small enough for one buffer); otherwise one placement per camera.
std::vector<CameraGpu> packCameras(std::span<const Camera> cameras, std::span<const PixelPlacement> placement = {});

constexpr VkDeviceSize kRayBytes = 32;
constexpr VkDeviceSize kPixelIdBytes = 8;

// `count` rays (kRayBytes each) in `range`: a batch's rays, or a block of them, as one value.
struct RaySpan {
  gpu::BufferRange range;
  uint32_t count = 0;
};

// Where generated rays lie: clipped to `box`, starting nearPlane in front of their camera.
struct RayClip {
  Aabb box;
  float nearPlane = 0;
};

// What a generation writes: the rays (kRayBytes each) and their pixel ids (kPixelIdBytes each).
struct RayOutputs {
  gpu::BufferRange rays, pixelIds;
};

class RayGeneration {
 public:
  explicit RayGeneration(Context& ctx);
  // Pixels [firstPixel, firstPixel + count) of camera `camera`, row-major.
  struct ImagePixels {
    uint32_t camera = 0, firstPixel = 0, count = 0;
  };
  // `count` random pixels of random cameras among the first numCameras (uniform over cameras, then
  // pixels). inCameraRuns: the rays come in runs of one camera each (tests/reference/rays/camera_runs.h;
  // each ray's camera still uniform), which the per-camera sums of camera refinement and the
  // appearance embedding need (shaders/gpu/per_camera_sum.glsl); otherwise each ray's camera is drawn alone.
  struct RandomPixels {
    uint32_t numCameras = 0, seed = 0, count = 0;
    bool inCameraRuns = false;
  };
  // A ray through each of `pixels`.
  void recordImage(gpu::Recorder& rec, const gpu::BufferRange& cameras, const ImagePixels& pixels,
                   const RayClip& clip, const RayOutputs& out);
  void recordRandom(gpu::Recorder& rec, const gpu::BufferRange& cameras, const RandomPixels& pixels,
                    const RayClip& clip, const RayOutputs& out);

 private:
  // The kernel's pixel choice: mode 0 (an image: a = camera, b = first pixel), 1 (random: a =
  // numCameras, b = seed) or 2 (random, in camera runs), `count` rays.
  struct Pixels {
    uint32_t mode, a, b, count;
  };
  void record(gpu::Recorder& rec, const gpu::BufferRange& cameras, const Pixels& pixels, const RayClip& clip,
              const RayOutputs& out);
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf
