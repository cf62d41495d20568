#pragma once
// What Model and Trainer drive: one model configuration's whole device pipeline (vanilla:
// nerf::VanillaPipeline, fast: nerf::FastPipeline), rendering a block of pixels and, when built for
// training, one optimisation step. Buffers are allocated once for a ray capacity.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/optim/adam.h"
#include "vknerf/config.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

// Rays start this far in front of the camera (or at the scene box, whichever is further).
constexpr float kNearPlane = 0.05f;

// Adam's rate and moments as a training configuration sets them.
AdamConfig adamConfigOf(const TrainConfig& config);

// A named float array of the model's state, for checkpoints.
struct StateArray {
  std::string name;
  gpu::Buffer* buffer;
  size_t count;
  bool optimizer;  // Adam moments: saved for resuming, not needed to render
};

// The training set on the device: packed RGBA8 images and packed cameras (nerf::packCameras).
struct TrainingData {
  const gpu::Buffer* images;
  const gpu::Buffer* cameras;
  uint32_t numCameras;
};

class FieldPipeline {
 public:
  virtual ~FieldPipeline() = default;

  virtual uint32_t rayCapacity() const = 0;

  // Renders pixels [first, first + count) (row-major) of camera `camera` in `cameras`,
  // count <= rayCapacity(). Afterwards color() holds vec4 (rgb over `background`, opacity) and depth()
  // the float sum w_i t_i, per ray. mayWait: `rec` is the pipeline's own and it may end, submit and
  // re-begin it to size later work from counts on the device; false: everything is recorded into
  // `rec` (a caller's command buffer) and nothing is submitted.
  virtual void recordRender(gpu::Recorder& rec, const gpu::BufferRange& cameras, uint32_t camera, uint32_t first,
                            uint32_t count, const std::array<float, 3>& background, bool mayWait) = 0;
  virtual const gpu::Buffer& color() const = 0;
  virtual const gpu::Buffer& depth() const = 0;

  // One optimisation step (`step` counts from 0), recorded into `rec`, submitted, waited for. Returns
  // the rays whose loss partials lossPartials() holds and the field evaluations the step made.
  struct StepSize {
    uint32_t rays = 0;
    uint64_t samples = 0;
  };
  virtual StepSize trainStep(gpu::Recorder& rec, const TrainingData& data, uint32_t step) = 0;
  virtual const gpu::Buffer& lossPartials() const = 0;
  // Called after resume() loads the state: rebuild anything derived from it.
  virtual void stateLoaded() {}

  // Parameters (and, when training, optimizer state and auxiliary structures) by name.
  virtual std::vector<StateArray> state() = 0;
  // Numbers worth reporting about what the model spends ("occupied 12.5%", "samples/ray 18.2").
  virtual std::vector<std::pair<std::string, double>> statistics() { return {}; }
};

}  // namespace vknerf::nerf
