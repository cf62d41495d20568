#include "models/fast/adaptive_batch.h"

#include <algorithm>

namespace vknerf::models {

AdaptiveBatch::AdaptiveBatch(Context& ctx, uint32_t rayCapacity, uint32_t rayAlign, uint32_t samplesPerBatch)
    : rayCapacity_(rayCapacity), rayAlign_(rayAlign), samplesPerBatch_(samplesPerBatch) {
  for (auto& c : counts_) c = gpu::Buffer::hostReadable(ctx, 16, "a training step's counts");
  raysFor_.fill(std::min(rayCapacity, 1024u));
}

void AdaptiveBatch::recordCopy(gpu::Recorder& rec, uint32_t slot, const DeviceCounts& counts) {
  // Copied within the step's own recording: after the step's fence the host reads three words with
  // no transfer of its own (a download of a discrete GPU's buffer is a submission and a wait each).
  rec.copy(counts.wholeRays, counts_[slot], 4, 0, 0);
  rec.copy(counts.marched, counts_[slot], 4, 0, 4);
  kept_[slot] = counts.kept != nullptr;
  if (counts.kept) rec.copy(*counts.kept, counts_[slot], 4, 0, 8);
}

FieldPipeline::StepSize AdaptiveBatch::collect(uint32_t slot) {
  const auto counts = counts_[slot].download<uint32_t>(3);
  const uint32_t rays = counts[0], marched = counts[1];
  marchedSamples_ += marched;
  marchedRays_ += rays;
  // The samples the loss saw (all marched ones without early termination).
  const uint32_t samples = kept_[slot] ? counts[2] : marched;
  keptSamples_ += samples;

  lastRays_ = rays;
  lastSamples_ = marched;
  // The step kSlots later (the next one to use this slot): as many rays as this step's marched
  // samples per ray say fit the sample budget.
  const double samplesPerRay = rays ? std::max(1.0, double(marched) / rays) : 1.0;
  lastSamplesPerRay_ = rays ? double(marched) / rays : 0.0;
  lastKeptFraction_ = marched ? double(samples) / marched : 1.0;
  raysFor_[slot] = uint32_t(std::clamp(double(samplesPerBatch_) / samplesPerRay, double(rayAlign_), double(rayCapacity_)));
  return {rays, samples};
}

void AdaptiveBatch::addStatistics(ModelStatistics& s) const {
  s.samplesPerRay = lastSamplesPerRay_;
  s.raysPerStep = lastRays_;
  s.samplesPerStep = lastSamples_;
  if (marchedRays_) s.meanSamplesPerRay = double(marchedSamples_) / double(marchedRays_);
  s.keptByEarlyTermination = marchedSamples_ ? double(keptSamples_) / double(marchedSamples_) : 1.0;
}

}  // namespace vknerf::models
