#pragma once
// Adam over a flat float parameter buffer (shaders/optim/adam.comp). params, grads, m and v hold `count`
// floats each, bound at offsets that are multiples of 16 bytes and of the device's storage and
// texel-buffer offset alignments (whole buffers always qualify); m and v start at zero; the
// gradient buffer is zeroed by every step so the next backward pass accumulates into it.
#include <cstdint>

#include <memory>
#include <vector>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/limited_dispatch.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::glsl {
struct AdamPush;
}

namespace vknerf::nerf {

struct AdamConfig {
  static constexpr uint32_t kNever = UINT32_MAX;
  float initialLearningRate = 5e-4f;
  float beta1 = 0.9f;
  float beta2 = 0.999f;    // 0.99 for hash grids
  float epsilon = 1e-8f;   // 1e-15 for hash grids; must be > 0
  float decayRate = 1.0f;  // lr = initialLearningRate * decayRate^(step / decaySteps); 1: constant
  float decaySteps = 250000.0f;
  // The rate decays until this step and holds its value there after; kNever: it decays on, as in
  // NeRF. A training configuration holds at its final rate (adamConfigOf): a run longer than its
  // decay would otherwise train at a vanishing rate (1e-6 after 4 decays).
  uint32_t decayEndStep = kNever;
  // Parameters at and past this index (a multiple of 4) whose gradient is exactly 0 keep p, m and v
  // (instant-ngp's skip of the table entries a step did not touch); 0: every one, kNever: none.
  // That part's step costs what the step touched: a pass lists its vec4s with a nonzero gradient,
  // and only those are stepped (shaders/optim/adam_touched.comp, adam_sparse.comp).
  uint32_t skipZeroGradientsFrom = kNever;

  // The exponentially decayed learning rate at `step` (continuous in the step, as in NeRF, up to
  // decayEndStep); learningRate(0) is the initial rate.
  float learningRate(uint32_t step) const;
};

// One optimizer step: Adam's step number (from 0; its bias correction counts it) and where the rate
// schedule stands, in steps: the step itself, or the run's progress times decay_steps when the
// decay spans a run's budget (Trainer::setRunProgress).
struct OptimizerStep {
  uint32_t step = 0;
  uint32_t rateStep = 0;
  static OptimizerStep at(uint32_t step) { return {step, step}; }
};

// A part of a parameter set that a step updates: floats [first, first + count), first a multiple of 4.
struct ParameterRange {
  uint32_t first = 0, count = 0;
};

// What one Adam step updates, as one value: `count` parameters and their gradients and first and
// second moments, each a range of `count` floats (offsets multiples of 16 bytes and of the device's
// storage and texel offset alignments; each buffer extends at least 16 bytes past its offset).
// `stepped`: the parts stepped, in order and apart, each start's byte offset a multiple of those
// alignments (empty: all). A parameter outside them keeps p, m, v and its gradient, so it is for
// parameters no backward ever writes: a hash table's dense levels leave the end of their slot
// unused (HashEncoding::usedRanges), and a step over it would cost the dense step as much as a used
// part.
struct AdamState {
  uint32_t count = 0;
  gpu::BufferRange params, grads, m, v;
  std::vector<ParameterRange> stepped;
};

class Adam {
 public:
  Adam(Context& ctx, AdamConfig config);
  const AdamConfig& config() const { return config_; }
  // One step; `step` is 1-based (bias correction 1 / (1 - beta^step)); lr is this step's rate.
  void record(gpu::Recorder& rec, const AdamState& state, uint32_t step, float lr);

 private:
  // The dense step over one part and its leftovers; returns the vec4s [first4, end4) of `whole`
  // past skipZeroGradientsFrom, which the touched list steps.
  struct SparseSpan {
    uint32_t first4 = 0, end4 = 0;
  };
  SparseSpan recordDense(gpu::Recorder& rec, const AdamState& whole, const ParameterRange& part, const glsl::AdamPush& base);
  // The listed vec4s of `spans`, those with a nonzero gradient alone.
  void recordSparse(gpu::Recorder& rec, const AdamState& whole, const std::vector<SparseSpan>& spans,
                    const glsl::AdamPush& base);

  Context& ctx_;
  AdamConfig config_;
  gpu::Kernel kernel_;
  gpu::Buffer dummy_;  // binds the vec4 views when there are fewer than 4 parameters
  // The sparse part's kernels, list of touched vec4s and its length, built on first use.
  std::unique_ptr<gpu::Kernel> touched_, sparse_;
  std::unique_ptr<gpu::Buffer> list_, listCount_;
  std::unique_ptr<gpu::LimitedDispatch> limited_;
};

}  // namespace vknerf::nerf
