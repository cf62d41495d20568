#include "models/field_pipeline.h"

#include "models/fast/fast_pipeline.h"
#include "models/vanilla/vanilla_pipeline.h"
#include "vknerf/error.h"

namespace vknerf::models {

std::vector<Camera> FieldPipeline::trainedCameras(std::span<const Camera> given) {
  std::vector<Camera> out(given.begin(), given.end());
  for (StepExtension* e : extensions_) e->adjustTrainedCameras(out);
  return out;
}

uint32_t renderRaysOf(const TrainConfig& config) { return config.isFast() ? 16384u : 4096u; }

std::unique_ptr<FieldPipeline> makeFieldPipeline(Context& ctx, const TrainConfig& config, const Aabb& box,
                                                 uint32_t rayCapacity, bool training, const RenderSettings& overrides,
                                                 const TrainingPhotos& photos) {
  // Every buffer the pipeline's members allocate while it is built is charged to its account.
  gpu::MemoryAccount::Scope charge(std::make_shared<gpu::MemoryAccount>());
  if (overrides.appearancePhoto && !(config.isFast() && config.fastModel().appearanceDims))
    throw Error("render settings: an appearance photo was chosen, but the model has no appearance embedding "
                "(model.appearance_dims is 0)");
  if (overrides.proposalSamples && !(config.isFast() && config.fastModel().usesProposal()))
    throw Error("render settings: proposal samples were chosen (" + std::to_string(overrides.proposalSamples) +
                "), but no proposal places the model's samples (its sampler is not the proposal)");
  // 2^20 rays already take gigabytes; beyond, sizes a batch's buffers multiply up would overflow.
  if (overrides.raysPerBatch > (1u << 20))
    throw Error("render settings: raysPerBatch must be at most 1048576, got " + std::to_string(overrides.raysPerBatch));
  if (config.isFast()) return std::make_unique<FastPipeline>(ctx, config, box, rayCapacity, training, overrides, photos);
  return std::make_unique<VanillaPipeline>(ctx, config, box, rayCapacity, training, overrides);
}

}  // namespace vknerf::models
