#pragma once
// The learned far field: the colour a ray sees at infinity in its direction, for scenes photographed
// without alpha (FarField::Learned). A ray that leaves the scene box partly transparent shows
// sum w_i c_i + T_final bg(d); with a constant background such rays borrow that colour, and a bright
// ground or sky becomes a view-dependent mix of field and background. Learned, bg(d) is the sky and
// whatever lies beyond the box, seen from anywhere in the same direction.
//   direction -> unit sphere -> hash grid (8 levels, 4..512 per axis) -> MLP 16 -> 64 -> rgb (sigmoid)
// CPU reference: tests/reference/render/far_field.h. Built from the field's own parts (HashEncoding,
// DenseMlp, TrainableParameters); its kernels are two small per-ray passes (shaders/render/far_field_*).
#include <array>
#include <optional>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/trainable_parameters.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/network/mlp.h"
#include "core/layouts/far_field_shape.h"

namespace vknerf::models {

class LearnedFarField final : public ParameterGroup {
 public:
  // Without Adam configurations: inference only (the fast model steps this table as its field's
  // table: every entry, also those no ray touched). It starts as the constant
  // `initial` everywhere (each channel clamped to [0.05, 0.95], where the sigmoid still learns).
  LearnedFarField(Context& ctx, uint32_t rayCapacity, uint32_t seed, const std::array<float, 3>& initial,
                  const std::optional<nerf::AdamConfig>& tableAdam, const std::optional<nerf::AdamConfig>& mlpAdam);
  // The MLP's initial parameters: PyTorch's layers, then the output layer's weights zero and its
  // bias logit(initial), so that bg(d) = initial for every d and the first steps move the bias.
  static std::vector<float> initialMlpParameters(const nerf::DenseMlp& net, const std::array<float, 3>& initial);

  static core::FarFieldShape shape();
  size_t parameterCount() const override { return table_.count() + mlp_.count(); }
  gpu::Buffer& tableParams() { return table_.params(); }
  gpu::Buffer& mlpParams() { return mlp_.params(); }
  gpu::Buffer& tableGrads() { return table_.grads(); }
  gpu::Buffer& mlpGrads() { return mlp_.grads(); }

  // background[i] = (bg(d_i), 0) for the first `count` rays (2 x vec4 each, nerf::kRayBytes). `keep`
  // (training) keeps the activations for recordBackward.
  void recordForward(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& rays, const gpu::BufferRange& background,
                     bool keep);
  // The gradient of the batch last run forward with keep: from the composite's colours (r, g, b,
  // opacity) and dL/dcolour, into the grads (accumulated until recordOptimizerStep).
  void recordBackward(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& background,
                      const gpu::BufferRange& color, const gpu::BufferRange& dColor);
  void recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) override;
  // "far_field.table.*", "far_field.mlp.*" (TrainableParameters::appendState).
  void appendState(std::vector<StateArray>& out) override;

 private:
  uint32_t capacity_;
  nerf::HashEncoding hash_;
  nerf::DenseMlp net_;
  TrainableParameters table_, mlp_;
  gpu::Kernel directionsKernel_, gradientKernel_;
  gpu::Buffer directions_, features_;
  // training
  std::optional<nerf::DenseMlp::Workspace> workspace_;
  gpu::Buffer dBackground_, dFeatures_;
};

}  // namespace vknerf::models
