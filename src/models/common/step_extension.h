#pragma once
// State a model trains beside its field, per training photo (camera refinement's pose corrections,
// the appearance vectors): a StepExtension. It is a parameter group (its optimizer step and its
// checkpoint arrays go through the model's registry) that the training step calls at fixed points,
// so the step, the model's interface and the Trainer need no line of their own for it:
//   recordCameras        before the rays: the cameras the batch is drawn through
//   recordColourBias     before the field's colour layer: a bias per sample (training or a render)
//   requestGradients     before the field's backward: the per-sample gradients it reads
//   recordGradient       after the field's backward: its own gradient
//   adjustTrainedCameras when the checkpoint records the training cameras (read back)
// Each hook does nothing unless the extension overrides it.
#include <optional>
#include <span>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/parameter_groups.h"
#include "nerf/network/dense_layer.h"
#include "nerf/rays/rays.h"
#include "vknerf/camera.h"

namespace vknerf::models {

// The training set on the device: the pixel bindings (nerf::TrainingPixels) and the cameras packed
// with each image's place in them (nerf::packCameras).
struct TrainingData {
  std::span<const gpu::BufferRange> pixels;
  const gpu::Buffer* cameras;
  uint32_t numCameras;
  // Some pixel has alpha < 255. Only then does a random background teach something (that the
  // transparent space is empty); behind opaque photos it is noise, and the constant one is used.
  bool transparentPixels = true;
};

// The training photos a model is built for: how many, and (when training) their cameras as the
// dataset gives them. A loaded model knows the count alone (from its checkpoint's record).
struct TrainingPhotos {
  uint32_t count = 0;
  std::span<const Camera> cameras;
};

// A training batch as the hooks see it, after the field's backward: its rays and their photos, the
// marched samples and the rows the backward ran over (ray r's rows [rowOffsets[r], rowOffsets[r + 1])),
// and the rays the device kept (a uint).
struct StepBatch {
  nerf::RaySpan rays;
  gpu::BufferRange pixelIds;     // uvec2 (photo, pixel) per ray
  gpu::BufferRange sampleRay;    // uint per marched sample: its ray
  gpu::BufferRange marchedOffsets, marchedSamples, rowOffsets;
  gpu::BufferRange rayCount;
  Aabb box;  // the box the field maps onto [-1, 1]^3
};

// The per-row gradients the field's backward writes for the extensions that read them: dL/d(the
// colour layer's pre-activation) and dL/d(position), each a buffer of the asker's (the backward's
// rows, as StepBatch::rowOffsets numbers them).
struct FieldGradientTargets {
  std::optional<gpu::BufferRange> dColour, dPosition;
};

// A target several extensions read (camera and focal refinement both read dPosition): the backward
// writes it once, so the first asker's buffer (`own`) is the target and every asker reads the one
// returned, whoever's it is. An extension's requestGradients keeps what this returns for its
// recordGradient.
inline gpu::BufferRange sharedTarget(std::optional<gpu::BufferRange>& target, const gpu::Buffer& own) {
  if (!target) target = gpu::BufferRange(own);
  return *target;
}

class StepExtension : public ParameterGroup {
 public:
  // The cameras the step's rays are made from: `data.cameras`, or a buffer of the extension's.
  virtual const gpu::Buffer& recordCameras(gpu::Recorder& rec, const TrainingData& data) {
    (void)rec;
    return *data.cameras;
  }
  // The bias on the colour layer's rows: `batch` is the training step's (each sample its photo's),
  // none for a render.
  virtual std::optional<nerf::RowBias> recordColourBias(gpu::Recorder& rec, const StepBatch* batch) {
    (void)rec, (void)batch;
    return std::nullopt;
  }
  virtual void requestGradients(FieldGradientTargets& targets) { (void)targets; }
  virtual void recordGradient(gpu::Recorder& rec, const StepBatch& batch) { (void)rec, (void)batch; }
  // `cameras`: the training cameras as given (one per photo), changed to what the model was
  // fitted through.
  virtual void adjustTrainedCameras(std::vector<Camera>& cameras) { (void)cameras; }
};

}  // namespace vknerf::models
