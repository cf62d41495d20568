#pragma once
// The fast (instant-ngp style) pipeline: only what the scene needs.
//   rays -> march through the occupancy grid (packed samples, empty cells skipped) -> points
//        -> hash grid(x), SH(d) -> small MLP (trunc-exp density) -> composite (packed)
// and, when training, photometric loss -> composite backward -> MLP backward (dL/dfeatures)
// -> hash-grid backward -> Adam (MLP and table), with the occupancy grid re-measured every K steps.
// The number of samples a batch marches is known only on the device; a step submits the march,
// reads the total (a few bytes, mapped), sizes the rest of the step to it and adapts the next
// step's ray count to hold about TrainConfig::samplesPerBatch samples.
#include <memory>
#include <optional>

#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "nerf/render/composite.h"
#include "models/field_pipeline.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/sampling/marcher.h"
#include "nerf/network/mlp.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "nerf/optim/adam.h"
#include "nerf/rays/rays.h"
#include "nerf/encoding/sh_encoding.h"
#include "vknerf/config.h"

namespace vknerf::nerf {

HashGridConfig hashGridConfigFor(const ModelConfig& model);

class FastPipeline final : public FieldPipeline {
 public:
  FastPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity, bool training);

  uint32_t rayCapacity() const override { return rayCapacity_; }
  void recordRender(gpu::Recorder& rec, const gpu::BufferRange& cameras, uint32_t camera, uint32_t first,
                    uint32_t count, const std::array<float, 3>& background, bool mayWait) override;
  const gpu::Buffer& color() const override { return color_; }
  const gpu::Buffer& depth() const override { return depth_; }
  StepSize trainStep(gpu::Recorder& rec, const TrainingData& data, uint32_t step) override;
  const gpu::Buffer& lossPartials() const override { return partials_; }
  std::vector<StateArray> state() override;
  std::vector<std::pair<std::string, double>> statistics() override;

  float marchStep() const { return dt_; }
  OccupancyGrid& occupancy() { return grid_; }
  size_t parameterCount() const { return hash_.parameterCount() + mlp_.parameterCount(); }

 private:
  // Marches rays [rayOffset, rayOffset + numRays) of rays_ into the sample buffers.
  void recordMarch(gpu::Recorder& rec, uint32_t rayOffset, uint32_t numRays, uint32_t maxSamples, uint32_t seed,
                   bool jitter);
  // How many of the marched rays are whole within the sample capacity (all when nothing was cut),
  // and their sample total. Reads offsets on the host (after the march was submitted and waited).
  std::pair<uint32_t, uint32_t> wholeRays(uint32_t numRays);
  // The packed batch the field and the compositor read: the march's, or its early-terminated copy.
  struct Packed {
    gpu::Buffer *offsets, *samples, *sampleRay, *totals;
  };
  Packed marched() { return {&offsets_, &samples_, &sampleRay_, &totals_}; }
  Packed terminated() { return {&termOffsets_, &termSamples_, &termSampleRay_, &termTotals_}; }
  // Field at `count` packed samples of the rays at rayOffset: points, encodings, MLP. With
  // limitToTotal, only the samples below the batch's device total are evaluated (count: capacity).
  void recordField(gpu::Recorder& rec, const Packed& batch, uint32_t rayOffset, uint32_t count,
                   NerfMlp::Workspace* keep, bool limitToTotal = false);
  void recordComposite(gpu::Recorder& rec, const Packed& batch, uint32_t rayOffset, uint32_t numRays,
                       const std::array<float, 3>& bg);
  void recordOccupancyUpdate(gpu::Recorder& rec, uint32_t step);
  void allocate(uint32_t sampleCapacity);

  Context& ctx_;
  TrainConfig config_;
  Aabb box_;
  uint32_t rayCapacity_, sampleCapacity_ = 0;
  bool training_;
  float dt_, trainedDt_;  // march step now, and in training (the occupancy threshold's)
  HashEncoding hash_;
  ShEncoding sh_;
  NerfMlp mlp_;
  OccupancyGrid grid_;
  RayGeneration rayGen_;
  RayMarcher marcher_;
  PackedSamplePoints points_;
  Compositor compositor_;
  std::optional<EarlyTermination> termination_;
  BackgroundColors backgrounds_;
  std::optional<PhotometricLoss> loss_;
  std::optional<Adam> adamMlp_, adamHash_;
  std::unique_ptr<NerfMlp::Workspace> workspace_;
  std::unique_ptr<gpu::Recorder> marchRec_;

  gpu::Buffer hashParams_, hashGrads_, hashM_, hashV_;
  gpu::Buffer mlpParams_, mlpGrads_, mlpM_, mlpV_;
  // per ray
  gpu::Buffer rays_, pixelIds_, background_, color_, depth_, dColor_, zeroDepthGrad_, partials_, offsets_;
  // per sample
  gpu::Buffer samples_, sampleRay_, totals_, positions_, directions_, posFeatures_, dirFeatures_, field_, weights_,
      dField_, dPos_;
  // early termination (training): the samples in front of T < 1e-4
  gpu::Buffer termOffsets_, termSamples_, termSampleRay_, termTotals_;
  uint64_t marchedSamples_ = 0, keptSamples_ = 0;
  // occupancy update
  uint32_t occPoints_ = 0;
  gpu::Buffer occPositions_, occCells_, occDirections_, occPosFeatures_, occDirFeatures_, occField_;

  uint32_t raysNext_;  // adaptive ray count of the next training step
  double lastSamplesPerRay_ = 0;
  uint32_t lastRays_ = 0, lastSamples_ = 0;
};

}  // namespace vknerf::nerf
