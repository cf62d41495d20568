#include "models/common/loss_report.h"

#include <algorithm>

#include "vknerf/error.h"

namespace vknerf::models {

namespace {
// Every block starts 256 bytes apart: the largest minStorageBufferOffsetAlignment a device may ask.
constexpr uint64_t kBlockAlignFloats = 256 / sizeof(float);
}  // namespace

LossReport::LossReport(Context& ctx, uint32_t rayCapacity)
    : ctx_(ctx), rayCapacity_(rayCapacity), floats_(blockFloats(rayCapacity)), sums_(ctx) {
  allocate();
}

uint64_t LossReport::blockFloats(uint32_t items) const {
  // (The photometric loss's partials are per 128 rays too.)
  static_assert(nerf::PartialSums::kPerPartial == nerf::PhotometricLoss::kRaysPerPartial);
  const uint64_t n = nerf::PartialSums::partialCount(std::max(items, 1u));
  return (n + kBlockAlignFloats - 1) / kBlockAlignFloats * kBlockAlignFloats;
}

void LossReport::allocate() { partials_ = gpu::Buffer::zeros(ctx_, floats_ * sizeof(float), "the loss partials"); }

const ConfigField& LossReport::row(const std::string& key) {
  for (const ConfigField& f : configFields())
    if (key == f.key) return f;
  throw Error("loss report: no configuration field " + key + " weighs a loss term");
}

uint32_t LossReport::addTerm(const ConfigField& weightField, bool perRay, uint32_t items) {
  const uint32_t n = perRay ? rayCapacity_ : items;
  if (n == 0) throw Error("loss report: term " + weightField.path() + " sums no values");
  terms_.push_back({weightField.path(), perRay, n, floats_});
  floats_ += blockFloats(n);
  allocate();
  return uint32_t(terms_.size() - 1);
}

gpu::BufferRange LossReport::photometricPartials() const {
  return gpu::BufferRange(partials_, 0, uint64_t(nerf::PartialSums::partialCount(rayCapacity_)) * sizeof(float));
}

void LossReport::recordTerm(gpu::Recorder& rec, uint32_t term, const nerf::SummedValues& in) {
  const Term& t = terms_.at(term);
  if (in.count > t.items) throw Error("loss report: term " + t.name + " given more values than it was sized for");
  sums_.record(rec, in, gpu::BufferRange(partials_, t.first * sizeof(float), blockFloats(t.items) * sizeof(float)));
}

LossBreakdown LossReport::summarize(std::span<const float> partials, uint32_t rays) const {
  LossBreakdown b;
  const uint32_t photometric = nerf::PartialSums::partialCount(rays);
  b.photometric = nerf::PhotometricLoss::summarize(partials.first(std::min<size_t>(photometric, partials.size())), rays);
  for (const Term& t : terms_) {
    const uint32_t items = t.perRay ? rays : t.items;
    const uint64_t n = nerf::PartialSums::partialCount(items);
    double sum = 0;
    for (uint64_t i = 0; i < n && t.first + i < partials.size(); ++i) sum += partials[t.first + i];
    b.terms.emplace_back(t.name, sum);
  }
  return b;
}

}  // namespace vknerf::models
