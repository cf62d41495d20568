#pragma once
// The per-photo appearance embedding of a model (nerfacto's, instant-ngp's): a learned vector per
// training photo, fed to the colour network beside the direction encoding, so that exposure and
// white balance that differ from photo to photo are explained there and not by density (floaters).
// The table starts at zero: the untrained model is exactly the one without the embedding, every
// photo starts alike, and a novel view's vector (the mean) is the untrained one too; the vectors
// move first through dL/dvector = W^T dz (the colour layer's weights start random), then the
// weights that read them. Trained with its own Adam state (the network's rate and schedule).
// Training writes each sample the vector of its ray's photo; a render writes the mean of the
// photos' vectors (nerfstudio's choice for a camera that took no training photo) or a chosen photo's.
#include <cstdint>
#include <optional>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "models/common/trainable_parameters.h"
#include "nerf/encoding/appearance_embedding.h"

namespace vknerf::nerf {

class Appearance {
 public:
  // Without `adam`: the table alone (a render loads it from the checkpoint). renderPhoto: the photo
  // whose vector renders use, or none for the mean.
  Appearance(Context& ctx, uint32_t numPhotos, uint32_t dims, const std::optional<AdamConfig>& adam,
             std::optional<uint32_t> renderPhoto);

  uint32_t numPhotos() const { return numPhotos_; }
  uint32_t dims() const { return kernels_.dims(); }
  // Training: each row gets the vector of its ray's photo (rows.pixelIds and rows.sampleRay given).
  void recordTrainingRows(gpu::Recorder& rec, const AppearanceRows& rows);
  // A render: every row gets the mean vector (recomputed from the table now) or the chosen photo's.
  void recordRenderRows(gpu::Recorder& rec, AppearanceRows rows);
  // The table's gradient from a trained batch (before the optimizer step).
  void recordGradient(gpu::Recorder& rec, const AppearanceGradientInputs& in);
  void recordOptimizerStep(gpu::Recorder& rec, uint32_t step) { table_.recordOptimizerStep(rec, step); }
  // "appearance.params" (dims floats per photo) and, when training, Adam's moments.
  void appendState(std::vector<StateArray>& out) { table_.appendState(out); }
  // The table now, read back (dims floats per photo).
  std::vector<float> vectors() { return table_.params().download<float>(table_.count()); }

 private:
  uint32_t numPhotos_;
  std::optional<uint32_t> renderPhoto_;
  TrainableParameters table_;
  gpu::Buffer mean_;
  AppearanceEmbedding kernels_;
};

}  // namespace vknerf::nerf
