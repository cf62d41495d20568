#pragma once
// The vanilla NeRF pipeline on the device, for one batch of rays:
//   rays -> stratified samples -> points -> gamma(x), gamma(d) -> coarse MLP -> composite
//        -> inverse-CDF samples (merged) -> points -> encodings -> fine MLP -> composite
// and, when training, photometric loss -> composite backward -> MLP backward (both levels) -> Adam.
// Buffers are allocated once for a ray capacity; recording allocates nothing.
#include <array>
#include <memory>
#include <optional>

#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "nerf/render/composite.h"
#include "models/field_pipeline.h"
#include "nerf/encoding/frequency_encoding.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/network/mlp.h"
#include "nerf/optim/adam.h"
#include "nerf/sampling/points.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/samplers.h"
#include "vknerf/config.h"

namespace vknerf::nerf {

MlpConfig mlpConfigFor(const ModelConfig& model, uint32_t seed);

// One network's parameters and, when training, its gradient and Adam moments.
struct NetworkState {
  std::unique_ptr<NerfMlp> mlp;
  gpu::Buffer params, grads, m, v;
};

// Per-level buffers of a batch (coarse: Nc samples per ray, fine: Nc + Nf).
struct LevelBuffers {
  uint32_t samplesPerRay = 0;
  gpu::Buffer samples, positions, directions, posFeatures, dirFeatures, field, color, depth, weights;
  gpu::Buffer dField, dColor, partials;
  std::unique_ptr<NerfMlp::Workspace> workspace;  // activations kept for backward (training only)
};

class VanillaPipeline final : public FieldPipeline {
 public:
  VanillaPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity, bool training);

  // FieldPipeline
  uint32_t rayCapacity() const override { return capacity_; }
  void recordRender(gpu::Recorder& rec, const gpu::BufferRange& cameras, uint32_t camera, uint32_t first,
                    uint32_t count, const std::array<float, 3>& background, bool mayWait) override;
  const gpu::Buffer& color() const override { return levels_[1].color; }
  const gpu::Buffer& depth() const override { return levels_[1].depth; }
  StepSize trainStep(gpu::Recorder& rec, const TrainingData& data, uint32_t step) override;
  const gpu::Buffer& lossPartials() const override { return levels_[1].partials; }
  std::vector<StateArray> state() override;
  std::vector<std::pair<std::string, double>> statistics() override;

  NetworkState& coarse() { return coarse_; }
  NetworkState& fine() { return config_.model.separateFineNetwork ? fine_ : coarse_; }
  const NetworkState& coarse() const { return coarse_; }
  const NetworkState& fine() const { return config_.model.separateFineNetwork ? fine_ : coarse_; }
  bool separateFine() const { return config_.model.separateFineNetwork; }

  gpu::Buffer& rays() { return rays_; }
  gpu::Buffer& pixelIds() { return pixelIds_; }
  gpu::Buffer& background() { return background_; }
  const LevelBuffers& coarseLevel() const { return levels_[0]; }
  const LevelBuffers& fineLevel() const { return levels_[1]; }

  RayGeneration& rayGeneration() { return rayGen_; }
  BackgroundColors& backgroundColors() { return backgrounds_; }

  // Coarse and fine passes for `numRays` rays in rays(); per-ray backgrounds from background().
  void recordForward(gpu::Recorder& rec, uint32_t numRays, uint32_t seed, bool jitter);
  // Loss against the training pixels, backward through both levels, Adam on both networks.
  void recordTrainStep(gpu::Recorder& rec, uint32_t numRays, const gpu::Buffer& images, const gpu::Buffer& cameras,
                       uint32_t step, float learningRate);

 private:
  void recordLevel(gpu::Recorder& rec, LevelBuffers& level, NetworkState& net, uint32_t numRays, bool keep);

  Context& ctx_;
  TrainConfig config_;
  Aabb box_;
  uint32_t capacity_;
  bool training_;
  RayGeneration rayGen_;
  StratifiedSampler stratified_;
  PdfSampler pdf_;
  SamplePoints points_;
  FrequencyEncoding posEncoding_, dirEncoding_;
  Compositor compositor_;
  BackgroundColors backgrounds_;
  std::optional<PhotometricLoss> loss_;
  std::optional<Adam> adam_;
  NetworkState coarse_, fine_;
  LevelBuffers levels_[2];
  gpu::Buffer rays_, pixelIds_, background_, zeroDepthGrad_, noOffsets_;
};

}  // namespace vknerf::nerf
