#include "nerf/optim/adam.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vknerf/error.h"
#include "optim/adam_shared.h"
#include "optim/adam_sparse_shared.h"
#include "optim/adam_touched_shared.h"

namespace vknerf::nerf {
namespace {
using Push = glsl::AdamPush;
constexpr uint32_t kLocal = 64;

const AdamConfig& checked(const AdamConfig& c) {
  auto bad = [](const std::string& what) { throw Error("AdamConfig: " + what); };
  if (!(c.beta1 >= 0 && c.beta1 < 1)) bad("beta1 must be in [0, 1), got " + std::to_string(c.beta1));
  if (!(c.beta2 >= 0 && c.beta2 < 1)) bad("beta2 must be in [0, 1), got " + std::to_string(c.beta2));
  if (!(c.epsilon > 0)) bad("epsilon must be > 0 (0 divides 0 by 0 for a zero gradient)");
  if (!(c.initialLearningRate >= 0)) bad("the learning rate must be >= 0");
  if (!(c.decayRate > 0) || !(c.decaySteps > 0)) bad("decayRate and decaySteps must be > 0");
  if (c.skipZeroGradientsFrom != AdamConfig::kNever && c.skipZeroGradientsFrom % 4)
    bad("the first parameter whose zero gradients are skipped must be a multiple of 4, got " +
        std::to_string(c.skipZeroGradientsFrom));
  return c;
}

}  // namespace

float AdamConfig::learningRate(uint32_t step) const {
  const uint32_t decayed = std::min(step, decayEndStep);
  return float(double(initialLearningRate) * std::pow(double(decayRate), double(decayed) / double(decaySteps)));
}

Adam::Adam(Context& ctx, AdamConfig config)
    : ctx_(ctx),
      config_(checked(config)),
      kernel_(ctx, {gpu::shaders::adam,
                    {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f,
                     gpu::Binding::TexelRgba32f, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage},
                    sizeof(Push),
                    {}}),
      dummy_(ctx, 16) {}

void Adam::record(gpu::Recorder& rec, const AdamState& state, uint32_t step, float lr) {
  const uint32_t count = state.count;
  const gpu::BufferRange &params = state.params, &grads = state.grads, &m = state.m, &v = state.v;
  if (step == 0) throw Error("Adam: the step number is 1-based, got 0");
  if (count == 0) return;
  const auto& limits = ctx_.properties().limits;
  const VkDeviceSize align = std::max<VkDeviceSize>({16, limits.minStorageBufferOffsetAlignment,
                                                     limits.minTexelBufferOffsetAlignment});
  for (const gpu::BufferRange* r : {&params, &grads, &m, &v}) {
    if (r->offset % align)
      throw Error("Adam: buffer offsets must be multiples of " + std::to_string(align) + " bytes");
    if (gpu::boundBytes(*r) < VkDeviceSize(count) * 4)
      throw Error("Adam: a bound range holds fewer than " + std::to_string(count) + " floats");
    if (r->buffer->size() - r->offset < 16) throw Error("Adam: buffers must extend at least 16 bytes past their offset");
  }
  // The count % 4 leftovers go through SSBO views ending at the last parameter and starting at an
  // aligned offset at least 16 bytes before that (descriptors bind at least 16 bytes). The offsets
  // are all multiples of `align`, so the leftovers sit at the same index in each view.
  const VkDeviceSize full = count / 4, tailStart = 16 * full, tailEnd = 4 * VkDeviceSize(count);
  const VkDeviceSize tailBase = tailEnd >= 16 ? (tailEnd - 16) / align * align : 0;
  auto tail = [&](const gpu::BufferRange& r) {
    return count % 4 ? gpu::BufferRange(*r.buffer, r.offset + tailBase, tailEnd - tailBase)
                     : gpu::BufferRange(*r.buffer, r.offset, 16);
  };
  // In double: 1 - beta2^t at t = 1 is 1e-3 and loses digits in float.
  double c1 = 1.0 / (1.0 - std::pow(double(config_.beta1), double(step)));
  double c2 = 1.0 / (1.0 - std::pow(double(config_.beta2), double(step)));
  // The vec4s from skipZeroGradientsFrom on go through the list of the touched ones; the kernel
  // below steps the rest and the leftovers (whose zero gradients it skips past that index too).
  const uint32_t sparseFrom4 = uint32_t(std::min<uint64_t>(full, config_.skipZeroGradientsFrom / 4));
  Push p{lr, config_.beta1, config_.beta2, config_.epsilon, float(c1), float(c2), count,
         config_.skipZeroGradientsFrom, uint32_t((tailStart - tailBase) / 4), sparseFrom4};
  // The vec4 part, exactly; with fewer than 4 parameters a dummy keeps the unused views valid.
  auto body = [&](const gpu::BufferRange& r) {
    return full ? gpu::BufferRange(*r.buffer, r.offset, 16 * full) : gpu::BufferRange(dummy_);
  };
  // One invocation per 4 parameters, plus one for the leftovers.
  const uint32_t invocations = sparseFrom4 + (count % 4 ? 1 : 0);
  if (invocations)
    rec.dispatch(kernel_, {body(params), body(grads), body(m), body(v), tail(params), tail(grads), tail(m), tail(v)}, p,
                 gpu::groupsFor(invocations, kLocal), 1, 1, "adam");
  if (sparseFrom4 < full) {
    const AdamState bodies{count, body(params), body(grads), body(m), body(v)};
    const glsl::AdamSparsePush sp{p.lr, p.beta1, p.beta2, p.epsilon, p.correction1, p.correction2, 0, 0};
    recordSparse(rec, bodies, sparseFrom4, uint32_t(full), sp);
  }
}

void Adam::recordSparse(gpu::Recorder& rec, const AdamState& state, uint32_t first4, uint32_t full4,
                        glsl::AdamSparsePush push) {
  const uint32_t capacity = full4 - first4;
  constexpr uint32_t kTouchedPerGroup = 64 * 16;  // adam_touched.comp's invocations x vec4s each
  const uint32_t groups = gpu::groupsFor(capacity, kTouchedPerGroup);
  if (groups > ctx_.properties().limits.maxComputeWorkGroupCount[0])
    throw Error("Adam: " + std::to_string(4ull * capacity) + " parameters with sparse gradients exceed one dispatch of the device");
  if (!touched_) {
    using gpu::Binding;
    touched_ = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::adam_touched, {Binding::TexelRgba32f, Binding::Storage, Binding::Storage},
                              sizeof(glsl::AdamTouchedPush), {}});
    sparse_ = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::adam_sparse,
                              {Binding::TexelRgba32f, Binding::TexelRgba32f, Binding::TexelRgba32f, Binding::TexelRgba32f,
                               Binding::Storage, Binding::Storage},
                              sizeof(glsl::AdamSparsePush), {}});
    listCount_ = std::make_unique<gpu::Buffer>(gpu::Buffer::zeros(ctx_, 16));
    limited_ = std::make_unique<gpu::LimitedDispatch>(ctx_);
  }
  if (!list_ || list_->size() < VkDeviceSize(capacity) * 4)
    list_ = std::make_unique<gpu::Buffer>(gpu::Buffer::zeros(ctx_, VkDeviceSize(capacity) * 4, "Adam's touched parameters"));
  rec.fill(*listCount_, 0);
  rec.dispatch(*touched_, {state.grads, *list_, *listCount_}, glsl::AdamTouchedPush{first4, capacity}, groups, 1, 1,
               "adam touched");
  glsl::AdamSparsePush sp = push;
  sp.count = capacity;
  const gpu::BufferRange count(*listCount_, 0, 4);
  limited_->begin(rec, &count, capacity, capacity, {kLocal});
  gpu::dispatchLimited(rec, *sparse_, {state.params, state.grads, state.m, state.v, *list_}, sp, limited_->rows(0, 0),
                       gpu::groupsFor(capacity, kLocal), "adam sparse");
}

}  // namespace vknerf::nerf
