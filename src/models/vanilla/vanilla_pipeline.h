#pragma once
// The vanilla NeRF pipeline on the device, for one batch of rays:
//   rays -> stratified samples -> points -> gamma(x), gamma(d) -> coarse MLP -> composite
//        -> inverse-CDF samples (merged) -> points -> encodings -> fine MLP -> composite
// and, when training, photometric loss -> composite backward -> MLP backward (both levels) -> Adam.
// Buffers are allocated once for a ray capacity; recording allocates nothing.
#include <array>
#include <memory>
#include <optional>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/field_batch.h"
#include "models/common/ray_batch.h"
#include "models/common/trainable_parameters.h"
#include "models/field_pipeline.h"
#include "nerf/encoding/frequency_encoding.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/network/mlp.h"
#include "nerf/render/composite.h"
#include "nerf/sampling/points.h"
#include "nerf/sampling/samplers.h"
#include "vknerf/config.h"

namespace vknerf::models {

// One network and its trainable parameters.
struct Network {
  Network(Context& ctx, const VanillaModel& model, uint32_t seed, const std::string& name,
          const std::optional<nerf::AdamConfig>& adam);
  nerf::NerfMlp mlp;
  TrainableParameters parameters;
};

// One level of the hierarchy (coarse: Nc samples per ray, fine: Nc + Nf): its samples, their
// field, and per ray the composited colour and depth (and, training, the loss's gradient).
struct Level {
  Level(Context& ctx, const nerf::NerfMlp& mlp, uint32_t rays, uint32_t samplesPerRay, bool training);
  uint32_t samplesPerRay;
  gpu::Buffer samples, weights, color, depth;
  FieldBatch field;
  gpu::Buffer dColor;  // training
};

class VanillaPipeline final : public FieldPipeline {
 public:
  VanillaPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity, bool training,
                  const RenderSettings& overrides = {});

  RenderOutputs renderOutputs() const override { return {levels_[1].color, levels_[1].depth, rays_.background()}; }
  FieldBatch& queryBatch() override { return levels_[1].field; }
  void recordQuery(gpu::Recorder& rec, uint32_t count) override;

 private:
  void doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) override;
  uint32_t doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) override;
  StepSize doCollectTrainStep(uint32_t slot) override;
  ModelStatistics modelStatistics() override;

  Network& fine() { return fine_ ? *fine_ : coarse_; }
  // Coarse and fine passes for `numRays` rays of rays_.
  void recordForward(gpu::Recorder& rec, uint32_t numRays, uint32_t seed, bool jitter);
  void recordLevel(gpu::Recorder& rec, Level& level, Network& net, uint32_t numRays, bool keep);
  // What the compositor reads of a level's first `numRays` rays, forward and backward.
  nerf::CompositeInputs compositeInputs(const Level& level, uint32_t numRays);
  // Encodings and `net` at the first `count` positions and directions of `f`.
  void recordNetwork(gpu::Recorder& rec, FieldBatch& f, Network& net, uint32_t count, bool keep);
  // Loss against the training pixels and backward through both levels; then Adam.
  void recordBackward(gpu::Recorder& rec, uint32_t numRays, const TrainingData& data, nerf::OptimizerStep at);

  TrainConfig config_;
  VanillaModel model_;
  Aabb box_;
  bool training_;
  RayBatch rays_;
  nerf::StratifiedSampler stratified_;
  nerf::PdfSampler pdf_;
  nerf::SamplePoints points_;
  nerf::FrequencyEncoding posEncoding_, dirEncoding_;
  nerf::Compositor compositor_;
  std::optional<nerf::PhotometricLoss> loss_;
  std::optional<nerf::AdamConfig> adam_;  // training
  Network coarse_;
  std::unique_ptr<Network> fine_;  // separateFineNetwork; null: the coarse network is queried twice
  Level levels_[2];
  gpu::Buffer zeroDepthGrad_;
  gpu::Buffer coarsePartials_;  // training: the coarse level's loss (minimised, not reported)
};

}  // namespace vknerf::models
