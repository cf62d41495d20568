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

// What every binding's offset must be a multiple of: 16 bytes (vec4 views), and the device's storage
// and texel-buffer offset alignments.
VkDeviceSize alignmentOf(Context& ctx) {
  const auto& limits = ctx.properties().limits;
  return std::max<VkDeviceSize>({16, limits.minStorageBufferOffsetAlignment, limits.minTexelBufferOffsetAlignment});
}

// AdamState::stepped: in order, apart, inside the set, each start a bound offset.
const std::vector<ParameterRange>& checkedParts(const std::vector<ParameterRange>& parts, uint32_t count, VkDeviceSize align) {
  uint64_t end = 0;
  for (const ParameterRange& r : parts) {
    const std::string which = "Adam: the stepped part [" + std::to_string(r.first) + ", " +
                              std::to_string(uint64_t(r.first) + r.count) + ")";
    if (r.first < end) throw Error(which + " overlaps or precedes the one before it");
    if (uint64_t(r.first) + r.count > count) throw Error(which + " ends past the " + std::to_string(count) + " parameters");
    if ((4 * VkDeviceSize(r.first)) % align) throw Error(which + " starts off a " + std::to_string(align) + "-byte boundary");
    end = uint64_t(r.first) + r.count;
  }
  return parts;
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
                     gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage},
                    sizeof(Push),
                    {}}),
      dummy_(ctx, 16) {}

void Adam::record(gpu::Recorder& rec, const AdamState& state, uint32_t step, float lr) {
  const uint32_t count = state.count;
  if (step == 0) throw Error("Adam: the step number is 1-based, got 0");
  if (count == 0) return;
  const VkDeviceSize align = alignmentOf(ctx_);
  for (const gpu::BufferRange* r : {&state.params, &state.grads, &state.m, &state.v}) {
    if (r->offset % align)
      throw Error("Adam: buffer offsets must be multiples of " + std::to_string(align) + " bytes");
    if (gpu::boundBytes(*r) < VkDeviceSize(count) * 4)
      throw Error("Adam: a bound range holds fewer than " + std::to_string(count) + " floats");
    if (r->buffer->size() - r->offset < 16) throw Error("Adam: buffers must extend at least 16 bytes past their offset");
  }
  const std::vector<ParameterRange> parts =
      state.stepped.empty() ? std::vector<ParameterRange>{{0, count}} : checkedParts(state.stepped, count, align);
  // In double: 1 - beta2^t at t = 1 is 1e-3 and loses digits in float.
  const double c1 = 1.0 / (1.0 - std::pow(double(config_.beta1), double(step)));
  const double c2 = 1.0 / (1.0 - std::pow(double(config_.beta2), double(step)));
  const Push base{lr, config_.beta1, config_.beta2, config_.epsilon, float(c1), float(c2), 0, 0, 0, 0};
  // Each part's vec4s before skipZeroGradientsFrom and its leftovers take the dense kernel; the
  // vec4s from there on go through one list of the touched ones over all parts.
  std::vector<SparseSpan> sparse;
  for (const ParameterRange& part : parts) {
    const SparseSpan s = recordDense(rec, state, part, base);
    if (s.end4 > s.first4) sparse.push_back(s);
  }
  if (!sparse.empty()) recordSparse(rec, state, sparse, base);
}

Adam::SparseSpan Adam::recordDense(gpu::Recorder& rec, const AdamState& whole, const ParameterRange& part,
                                   const Push& base) {
  const uint32_t count = part.count;
  if (count == 0) return {};
  const VkDeviceSize align = alignmentOf(ctx_);
  auto sub = [&](const gpu::BufferRange& r) {
    return gpu::BufferRange(*r.buffer, r.offset + 4 * VkDeviceSize(part.first), 4 * VkDeviceSize(count));
  };
  // The count % 4 leftovers go through SSBO views ending at the last parameter and starting at an
  // aligned offset at least 16 bytes before that (descriptors bind at least 16 bytes). The offsets
  // are all multiples of `align`, so the leftovers sit at the same index in each view.
  const VkDeviceSize full = count / 4, tailStart = 16 * full, tailEnd = 4 * VkDeviceSize(count);
  const VkDeviceSize tailBase = tailEnd >= 16 ? (tailEnd - 16) / align * align : 0;
  auto tail = [&](const gpu::BufferRange& whole) {
    const gpu::BufferRange r = sub(whole);
    return count % 4 ? gpu::BufferRange(*r.buffer, r.offset + tailBase, tailEnd - tailBase)
                     : gpu::BufferRange(*r.buffer, r.offset, 16);
  };
  // skipZeroGradientsFrom counts from the start of the whole set; here from the part's (both multiples of 4).
  const uint64_t skip = config_.skipZeroGradientsFrom;
  const uint32_t skipHere = uint32_t(std::min<uint64_t>(skip > part.first ? skip - part.first : 0, count + 3ull) / 4 * 4);
  const uint32_t sparseFrom4 = uint32_t(std::min<uint64_t>(full, skipHere / 4));
  Push p = base;
  p.count = count;
  p.skipZeroFrom = skipHere;
  p.tailIndex = uint32_t((tailStart - tailBase) / 4);
  p.body4 = sparseFrom4;
  // The vec4 part, exactly; with fewer than 4 parameters a dummy keeps the unused views valid.
  auto body = [&](const gpu::BufferRange& whole) {
    const gpu::BufferRange r = sub(whole);
    return full ? gpu::BufferRange(*r.buffer, r.offset, 16 * full) : gpu::BufferRange(dummy_);
  };
  // One invocation per 4 parameters, plus one for the leftovers.
  const uint32_t invocations = sparseFrom4 + (count % 4 ? 1 : 0);
  if (invocations)
    rec.dispatch(kernel_,
                 {body(whole.params), body(whole.grads), body(whole.m), body(whole.v), tail(whole.params),
                  tail(whole.grads), tail(whole.m), tail(whole.v), body(whole.params), body(whole.grads), body(whole.m),
                  body(whole.v)},
                 p, gpu::groupsFor(invocations, kLocal), 1, 1, "adam");
  return {part.first / 4 + sparseFrom4, part.first / 4 + uint32_t(full)};
}

void Adam::recordSparse(gpu::Recorder& rec, const AdamState& whole, const std::vector<SparseSpan>& spans,
                        const Push& base) {
  uint32_t capacity = 0;
  for (const SparseSpan& s : spans) capacity += s.end4 - s.first4;
  constexpr uint32_t kTouchedPerGroup = 64 * 16;  // adam_touched.comp's invocations x vec4s each
  for (const SparseSpan& s : spans)
    if (gpu::groupsFor(s.end4 - s.first4, kTouchedPerGroup) > ctx_.properties().limits.maxComputeWorkGroupCount[0])
      throw Error("Adam: " + std::to_string(4ull * (s.end4 - s.first4)) +
                  " parameters with sparse gradients exceed one dispatch of the device");
  if (!touched_) {
    using gpu::Binding;
    touched_ = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::adam_touched, {Binding::TexelRgba32f, Binding::Storage, Binding::Storage},
                              sizeof(glsl::AdamTouchedPush), {}});
    sparse_ = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::adam_sparse,
                              {Binding::TexelRgba32f, Binding::TexelRgba32f, Binding::TexelRgba32f, Binding::TexelRgba32f,
                               Binding::Storage, Binding::Storage, Binding::Storage, Binding::Storage, Binding::Storage,
                               Binding::Storage},
                              sizeof(glsl::AdamSparsePush), {}});
    listCount_ = std::make_unique<gpu::Buffer>(gpu::Buffer::zeros(ctx_, 16));
    limited_ = std::make_unique<gpu::LimitedDispatch>(ctx_);
  }
  if (!list_ || list_->size() < VkDeviceSize(capacity) * 4)
    list_ = std::make_unique<gpu::Buffer>(gpu::Buffer::zeros(ctx_, VkDeviceSize(capacity) * 4, "Adam's touched parameters"));
  // The vec4 bodies of the whole set: the list holds vec4 indices into them.
  const uint32_t full4 = whole.count / 4;
  auto body = [&](const gpu::BufferRange& r) { return gpu::BufferRange(*r.buffer, r.offset, 16 * VkDeviceSize(full4)); };
  // Every span appends to the one list (each workgroup takes its place with an atomic on the count).
  rec.fill(*listCount_, 0);
  for (const SparseSpan& s : spans)
    rec.dispatch(*touched_, {body(whole.grads), *list_, *listCount_}, glsl::AdamTouchedPush{s.first4, s.end4 - s.first4},
                 gpu::groupsFor(s.end4 - s.first4, kTouchedPerGroup), 1, 1, "adam touched");
  const glsl::AdamSparsePush sp{base.lr, base.beta1, base.beta2, base.epsilon, base.correction1, base.correction2, capacity, 0};
  const gpu::BufferRange count(*listCount_, 0, 4);
  limited_->begin(rec, &count, capacity, capacity, {kLocal});
  gpu::dispatchLimited(rec, *sparse_,
                       {body(whole.params), body(whole.grads), body(whole.m), body(whole.v), *list_, body(whole.params),
                        body(whole.grads), body(whole.m), body(whole.v)},
                       sp, limited_->rows(0, 0), gpu::groupsFor(capacity, kLocal), "adam sparse");
}

}  // namespace vknerf::nerf
