#include "models/common/far_field.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "nerf/rays/rays.h"
#include "vknerf/error.h"
#include "render/far_field_shared.h"

namespace vknerf::models {

namespace {
using CountPush = glsl::FarFieldPush;
constexpr uint32_t kLocal = 64;  // both kernels' local_size_x
constexpr uint32_t kMlpWidth = 64;

// `r` as given (the descriptor sets are cached by range), once it is known to hold `count` rows.
const gpu::BufferRange& holding(const gpu::BufferRange& r, uint32_t count, VkDeviceSize rowBytes) {
  if (gpu::boundBytes(r) < VkDeviceSize(count) * rowBytes)
    throw Error("far field: a binding holds fewer than " + std::to_string(count) + " rows");
  return r;
}
}  // namespace

core::FarFieldShape LearnedFarField::shape() {
  core::HashGridConfig g;
  // 4 to 512 cells per axis of [-1, 1]^3, doubling per level: 512 puts about 1.6 cells on a pixel
  // of a 480-pixel-wide phone photo with a 70-degree view. 2^14 entries a level keep the table's Adam
  // at a quarter of the field's (the coarse levels are dense; the fine ones hash the sphere's cells).
  g.levels = 8;
  g.featuresPerLevel = 2;
  g.log2TableSize = 14;
  g.baseResolution = 4;
  g.growthFactor = 2.0f;
  return {g, core::DenseMlpShape::make(g.levels * g.featuresPerLevel, kMlpWidth, 1, 3)};
}

std::vector<float> LearnedFarField::initialMlpParameters(const nerf::DenseMlp& net, const std::array<float, 3>& initial) {
  std::vector<float> p = net.initialParameters();
  const core::DenseShape& out = net.shape().layers.back();
  const uint64_t bias = out.biasOffset();
  std::fill(p.begin() + long(out.offset), p.begin() + long(bias), 0.0f);
  for (uint32_t k = 0; k < 3; ++k) {
    const double c = std::clamp(double(initial[k]), 0.05, 0.95);
    p[bias + k] = float(std::log(c / (1.0 - c)));
  }
  return p;
}

LearnedFarField::LearnedFarField(Context& ctx, uint32_t rayCapacity, uint32_t seed, const std::array<float, 3>& initial,
                                 const std::optional<nerf::AdamConfig>& tableAdam, const std::optional<nerf::AdamConfig>& mlpAdam)
    : capacity_(rayCapacity),
      hash_(ctx, shape().grid),
      net_(ctx, nerf::DenseMlpConfig{shape().mlp.inputs, kMlpWidth, 1, 3, seed + 0x9e37u}),
      table_(ctx, "far_field.table", hash_.initialParameters(seed + 0x9e37u), tableAdam, hash_.trainedParts()),
      mlp_(ctx, "far_field.mlp", initialMlpParameters(net_, initial), mlpAdam),
      directionsKernel_(ctx, {gpu::shaders::far_field_directions, {gpu::Binding::Storage, gpu::Binding::Storage},
                              sizeof(CountPush), {}}),
      gradientKernel_(ctx, {gpu::shaders::far_field_gradient,
                            {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(CountPush), {}}),
      directions_(gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity) * 16, "the far field's directions")),
      features_(gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity) * net_.inputStride() * 4, "the far field's features")) {
  if (tableAdam) {
    workspace_.emplace(ctx, net_, rayCapacity);
    dBackground_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity) * 16);
    dFeatures_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity) * net_.inputStride() * 4);
  }
}

void LearnedFarField::recordForward(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& rays,
                                    const gpu::BufferRange& background, bool keep) {
  if (count > capacity_)
    throw Error("far field: " + std::to_string(count) + " rays over capacity " + std::to_string(capacity_));
  if (keep && !workspace_) throw Error("far field: built without training, nothing to keep");
  if (count == 0) return;
  rec.dispatch(directionsKernel_, {holding(rays, count, nerf::kRayBytes), gpu::BufferRange(directions_)}, CountPush{count},
               gpu::groupsFor(count, kLocal), 1, 1, "far_field_directions");
  hash_.recordForward(rec, {count, directions_, features_, net_.inputStride(), 0}, table_.params());
  net_.recordForward(rec, {count, features_, holding(background, count, 16)}, mlp_.params(),
                     keep ? &*workspace_ : nullptr);
}

void LearnedFarField::recordBackward(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& background,
                                     const gpu::BufferRange& color, const gpu::BufferRange& dColor) {
  if (!workspace_) throw Error("far field: built without training");
  if (count == 0) return;
  rec.dispatch(gradientKernel_, {holding(dColor, count, 16), holding(color, count, 16), gpu::BufferRange(dBackground_)},
               CountPush{count}, gpu::groupsFor(count, kLocal), 1, 1, "far_field_gradient");
  net_.recordBackward(rec, {count, features_, holding(background, count, 16)}, mlp_.params(),
                      {dBackground_, mlp_.grads(), gpu::BufferRange(dFeatures_)}, *workspace_);
  hash_.recordBackward(rec, {count, directions_, dFeatures_, net_.inputStride(), 0}, table_.grads());
}

void LearnedFarField::recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) {
  table_.recordOptimizerStep(rec, at);
  mlp_.recordOptimizerStep(rec, at);
}

void LearnedFarField::appendState(std::vector<StateArray>& out) {
  table_.appendState(out);
  mlp_.appendState(out);
}

}  // namespace vknerf::models
