#include "models/fast/fast_pipeline.h"
#include "api/model_impl.h"
#include "models/vanilla/vanilla_pipeline.h"
#include "vknerf/error.h"

namespace vknerf::nerf {

AdamConfig adamConfigOf(const TrainConfig& config) {
  AdamConfig ac;
  ac.initialLearningRate = config.learningRate;
  ac.beta1 = config.beta1;
  ac.beta2 = config.beta2;
  ac.epsilon = config.epsilon;
  return ac;
}

std::unique_ptr<FieldPipeline> makeFieldPipeline(Context& ctx, const TrainConfig& config, const Aabb& box,
                                                 uint32_t rayCapacity, bool training) {
  if (config.model.name == "vanilla") return std::make_unique<VanillaPipeline>(ctx, config, box, rayCapacity, training);
  if (config.model.name == "fast") return std::make_unique<FastPipeline>(ctx, config, box, rayCapacity, training);
  throw Error("unknown model configuration \"" + config.model.name + "\" (expected vanilla or fast)");
}

}  // namespace vknerf::nerf
