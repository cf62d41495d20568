#pragma once
// The per-photo appearance embedding of a model (nerfacto's, instant-ngp's): a learned vector a per
// training photo, fed to the colour network, so that exposure and white balance that differ from
// photo to photo are explained there and not by density (floaters). The vector acts as the input
// columns of the colour layer it would be beside the direction encoding, through its own weights
// W_a; since a is the same for every sample of a photo, it enters as that photo's bias a W_a on the
// layer's pre-activation (nerf/encoding/appearance_embedding.h), which costs the layer nothing.
// The vectors start at zero: the untrained model is exactly the one without the embedding, every
// photo starts alike, and a novel view's vector (the mean) is the untrained one too; the vectors
// move first through dL/da = W_a dz (W_a starts random, as the layer's weights do), then W_a.
// Both are trained with their own Adam state (the network's rate and schedule). Training adds each
// sample its ray's photo's bias; a render adds the bias of the mean of the photos' vectors
// (nerfstudio's choice for a camera that took no training photo) or a chosen photo's. A step
// extension (models/common/step_extension.h): the bias through recordColourBias, the gradient from
// the colour layer's pre-activation gradient the field's backward writes for it.
#include <cstdint>
#include <optional>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/step_extension.h"
#include "models/common/trainable_parameters.h"
#include "nerf/encoding/appearance_embedding.h"
#include "nerf/network/dense_layer.h"

namespace vknerf::models {

// What the weights W_a are drawn from: uniform in +-bound (the colour layer's own initialisation,
// its fan-in counting the vector), deterministic in seed.
struct AppearanceInit {
  uint32_t seed = 0;
  float bound = 0.0f;
};

class Appearance final : public StepExtension {
 public:
  // Without `adam`: the parameters alone (a render loads them from the checkpoint). width: the colour
  // layer's. renderPhoto: the photo whose vectors renders use, or none for the mean. rows: the most
  // rows a training step's backward runs over (the colour-layer gradient's; 0 without `adam`).
  Appearance(Context& ctx, uint32_t numPhotos, uint32_t dims, uint32_t width, const AppearanceInit& init,
             const std::optional<nerf::AdamConfig>& adam, std::optional<uint32_t> renderPhoto, uint32_t rows = 0);

  uint32_t numPhotos() const { return numPhotos_; }
  uint32_t dims() const { return kernels_.dims(); }
  // Checks that the training set has the photos the vectors were made for.
  const gpu::Buffer& recordCameras(gpu::Recorder& rec, const TrainingData& data) override;
  // Training (a batch): every photo's bias from the parameters now, each sample adding its ray's
  // photo's. A render (none): every sample adds the bias of the mean vector (recomputed now) or of
  // the chosen photo's.
  std::optional<nerf::RowBias> recordColourBias(gpu::Recorder& rec, const StepBatch* batch) override;
  void requestGradients(FieldGradientTargets& targets) override { colourGradient_ = sharedTarget(targets.dColour, dColour_); }
  // The gradients of the vectors and of W_a from a trained batch (before the optimizer step).
  void recordGradient(gpu::Recorder& rec, const StepBatch& batch) override;
  void recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) override;
  size_t parameterCount() const override { return vectors_.count() + weights_.count(); }
  // "appearance.params" (dims floats per photo), "appearance_weights.params" (W_a: dims rows of the
  // colour layer's width) and, when training, Adam's moments.
  void appendState(std::vector<StateArray>& out) override;
  // The vectors now, read back (dims floats per photo).
  std::vector<float> vectors() { return vectors_.params().download<float>(vectors_.count()); }

 private:
  nerf::AppearanceParameters parameters() { return {vectors_.params(), weights_.params()}; }

  uint32_t numPhotos_;
  std::optional<uint32_t> renderPhoto_;
  TrainableParameters vectors_, weights_;
  gpu::Buffer mean_, bias_, photoSums_;
  gpu::Buffer dColour_;  // training: dL/d(colour pre-activation) per backward row
  gpu::BufferRange colourGradient_;  // what the backward writes it into: dColour_, or another asker's
  nerf::AppearanceEmbedding kernels_;
};

}  // namespace vknerf::models
