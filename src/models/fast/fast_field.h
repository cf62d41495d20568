#pragma once
// The fast model's field F(x, d) -> (rgb, sigma) and its parameters: a position encoding (the hash
// grid; any nerf::Encoding, a constructor argument), spherical harmonics of the direction, and the
// small MLP (trunc-exp density), whose colour layer takes a per-row bias (the appearance
// embedding's, from a step extension). One forward (rows, what to keep), a density-only query (the
// occupancy update's) and one backward (optionally dL/dposition), over the field's own batch of
// samples (FieldBatch): tiny-cuda-nn's NetworkWithInputEncoding.
#include <memory>
#include <optional>
#include <string>

#include "gpu/dispatch/recorder.h"
#include "models/common/field_batch.h"
#include "models/common/parameter_groups.h"
#include "models/common/step_extension.h"
#include "models/common/trainable_parameters.h"
#include "nerf/encoding/encoding.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/encoding/sh_encoding.h"
#include "nerf/network/mlp.h"
#include "vknerf/config.h"

namespace vknerf::models {

nerf::HashGridConfig hashGridConfigFor(const FastModel& model);

// A hash table's Adam (the field's, the far field's): the configuration's rates times
// FastModel::hashLearningRateScale; every entry steps, also one no sample touched.
nerf::AdamConfig tableAdamOf(const TrainConfig& config);

// A position encoding with the optimizer settings of its parameters (none to render).
struct PositionEncoding {
  std::unique_ptr<nerf::Encoding> encoding;
  std::optional<nerf::AdamConfig> adam;
};
// The fast model's: the multiresolution hash grid of config.fastModel().
PositionEncoding hashGridPosition(Context& ctx, const TrainConfig& config, bool training);

// The rows a forward runs over: `count` rows of the batch, cut on the device to `limit` (a uint)
// or gathered through `gather` (uint per row, the rows a training segment computes); colourBias:
// added to the colour layer's pre-activation; densityOnly: only the density of batch().field is
// read and trained (nerf::NerfRows::densityOnly): the colour branch and the direction's encoding
// are skipped, and a backward of these rows says densityOnly too.
struct FieldRows {
  uint32_t count = 0;
  std::optional<gpu::BufferRange> limit, gather;
  std::optional<nerf::RowBias> colourBias;
  bool densityOnly = false;
};

// The rows a backward runs over: `count` rows below `limit`, their positions (vec4 per row) and,
// for a packed batch (the kept samples), row i the forward's row gather[i]; densityOnly: the
// forward's was (only dField's sigma is read).
struct FieldBackwardRows {
  uint32_t count = 0;
  gpu::BufferRange positions, limit;
  std::optional<gpu::BufferRange> gather;
  bool densityOnly = false;
};

class FastField {
 public:
  // capacity: samples the batch holds; densityRows: the most points a density query takes;
  // stateName: what its checkpoint arrays' names begin with ("": the field's "encoding" and "mlp").
  FastField(Context& ctx, const TrainConfig& config, bool training, uint32_t capacity, uint32_t densityRows,
            PositionEncoding position, const std::string& stateName = "");

  FieldBatch& batch() { return batch_; }
  const nerf::NerfMlp& mlp() const { return mlp_; }
  TrainableParameters& encodingParameters() { return encoding_; }
  TrainableParameters& networkParameters() { return network_; }
  size_t parameterCount() const { return encoding_.count() + network_.count(); }

  // batch().field = F(positions, directions) over `rows`; `keep`: the activations for backward.
  void recordForward(gpu::Recorder& rec, const FieldRows& rows, bool keep);
  // density[i] = sigma at positions[i] for i < count (count <= densityRows): the trunk alone.
  void recordDensity(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& positions,
                     const gpu::BufferRange& density);
  // From batch().dField: the parameters' gradients, and what `targets` asks for (the colour
  // layer's pre-activation gradient, dL/dposition from the encoding's parameters before their step).
  void recordBackward(gpu::Recorder& rec, const FieldBackwardRows& rows, const FieldGradientTargets& targets);

 private:
  std::unique_ptr<nerf::Encoding> position_;
  nerf::ShEncoding sh_;
  nerf::NerfMlp mlp_;
  TrainableParameters encoding_, network_;
  FieldBatch batch_;
  gpu::Buffer dEncoded_;         // training: dL/d(encoded position) per backward row
  gpu::Buffer densityFeatures_;  // a density query's encoded positions
};

}  // namespace vknerf::models
