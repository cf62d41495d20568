#include "nerf/optimizer.h"

#include <cmath>
#include <string>

#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
struct Push {
  float lr, beta1, beta2, epsilon, correction1, correction2;
  uint32_t count, skipZero;
};
constexpr uint32_t kLocal = 64;

const AdamConfig& checked(const AdamConfig& c) {
  auto bad = [](const std::string& what) { throw Error("AdamConfig: " + what); };
  if (!(c.beta1 >= 0 && c.beta1 < 1)) bad("beta1 must be in [0, 1), got " + std::to_string(c.beta1));
  if (!(c.beta2 >= 0 && c.beta2 < 1)) bad("beta2 must be in [0, 1), got " + std::to_string(c.beta2));
  if (!(c.epsilon > 0)) bad("epsilon must be > 0 (0 divides 0 by 0 for a zero gradient)");
  if (!(c.initialLearningRate >= 0)) bad("the learning rate must be >= 0");
  if (!(c.decayRate > 0) || !(c.decaySteps > 0)) bad("decayRate and decaySteps must be > 0");
  return c;
}

VkDeviceSize boundBytes(const gpu::BufferRange& r) {
  return r.range == VK_WHOLE_SIZE ? r.buffer->size() - r.offset : r.range;
}
}  // namespace

float AdamConfig::learningRate(uint32_t step) const {
  return float(double(initialLearningRate) * std::pow(double(decayRate), double(step) / double(decaySteps)));
}

Adam::Adam(Context& ctx, AdamConfig config)
    : config_(checked(config)),
      kernel_(ctx, {"adam",
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(Push),
                    {}}) {}

void Adam::record(gpu::Recorder& rec, const gpu::BufferRange& params, const gpu::BufferRange& grads,
                  const gpu::BufferRange& m, const gpu::BufferRange& v, uint32_t count, uint32_t step, float lr) {
  if (step == 0) throw Error("Adam: the step number is 1-based, got 0");
  if (count == 0) return;
  for (const gpu::BufferRange* r : {&params, &grads, &m, &v}) {
    if (r->offset % 16) throw Error("Adam: buffer offsets must be multiples of 16 bytes (vec4 access)");
    if (boundBytes(*r) < VkDeviceSize(count) * 4)
      throw Error("Adam: a bound range holds fewer than " + std::to_string(count) + " floats");
  }
  // In double: 1 - beta2^t at t = 1 is 1e-3 and loses digits in float.
  double c1 = 1.0 / (1.0 - std::pow(double(config_.beta1), double(step)));
  double c2 = 1.0 / (1.0 - std::pow(double(config_.beta2), double(step)));
  Push p{lr, config_.beta1, config_.beta2, config_.epsilon, float(c1), float(c2), count,
         config_.skipZeroGradients ? 1u : 0u};
  // One invocation per 4 parameters, plus one for the count % 4 leftovers.
  rec.dispatch(kernel_, {params, grads, m, v}, p, gpu::groupsFor(count / 4 + (count % 4 ? 1 : 0), kLocal), 1, 1,
               "adam");
}

}  // namespace vknerf::nerf
