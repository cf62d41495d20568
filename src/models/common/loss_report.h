#pragma once
// A training step's loss as one list of terms, reported together: the photometric error (what the
// loss and the train PSNR have always been) first, then each regularizer a model adds, by the
// configuration field that weighs it ("model.distortion_loss", "model.camera_penalty"), its value
// with its weight applied. Every term's values are summed on the device into partials (a block of
// the one buffer per term), which the step copies for the host with the photometric partials: no
// extra transfer, and the log shows each term's share of what was minimised.
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/loss/partial_sums.h"
#include "nerf/loss/photometric_loss.h"
#include "vknerf/config_fields.h"

namespace vknerf::models {

struct LossBreakdown {
  nerf::LossStats photometric;
  std::vector<std::pair<std::string, double>> terms;  // the configuration field, the weighted value
};

class LossReport {
 public:
  // Partials for the photometric loss of up to rayCapacity rays.
  LossReport(Context& ctx, uint32_t rayCapacity);

  // A term summed over `items` values a step writes: one per ray of the step (perRay: the step's
  // rays, up to the capacity) or a fixed number (one per training photo), named by the
  // configuration field that weighs it (weightField). Before the first step.
  uint32_t addTerm(const ConfigField& weightField, bool perRay, uint32_t items = 0);
  // The configuration's row `key` ("distortion_loss"); throws for a key no row has.
  static const ConfigField& row(const std::string& key);

  // Where the photometric loss writes its partial sums.
  gpu::BufferRange photometricPartials() const;
  // Term `term`'s values (`in`, its weight applied) summed into its partials.
  void recordTerm(gpu::Recorder& rec, uint32_t term, const nerf::SummedValues& in);

  // Every partial, for the step's copy to the host.
  const gpu::Buffer& partials() const { return partials_; }
  // The loss of a step of `rays` rays from its copied partials (partials()'s floats).
  LossBreakdown summarize(std::span<const float> partials, uint32_t rays) const;

 private:
  struct Term {
    std::string name;
    bool perRay;
    uint32_t items;
    uint64_t first;  // its block's first float
  };
  uint64_t blockFloats(uint32_t items) const;
  void allocate();

  Context& ctx_;
  uint32_t rayCapacity_;
  std::vector<Term> terms_;
  uint64_t floats_;
  gpu::Buffer partials_;
  nerf::PartialSums sums_;
};

}  // namespace vknerf::models
