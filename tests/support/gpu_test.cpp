#include "support/gpu_test.h"

#include <cstdio>

#include "gpu/device/device.h"
#include "nerf/encoding/hash_encoding.h"

namespace vknerf::test {

Context& context() {
  static std::shared_ptr<Context> ctx = [] {
    auto c = Context::create();
    std::fprintf(stderr, "vknerf tests on %s%s\n", c->describe().c_str(),
                 c->validationEnabled() ? " with validation" : "");
    return c;
  }();
  return *ctx;
}

std::shared_ptr<Context> sharedContext() { return std::shared_ptr<Context>(&context(), [](Context*) {}); }

bool deviceRuns(bool floatAtomics, bool subgroupArithmetic, bool subgroupVote) {
  const gpu::KernelFeatures& f = gpu::device(context()).features();
  return (!floatAtomics || f.bufferFloatAtomicAdd) && (!subgroupArithmetic || f.subgroupArithmetic) &&
         (!subgroupVote || f.subgroupVote);
}

bool deviceRuns(nerf::HashBackwardMode mode) {
  switch (mode) {
    case nerf::HashBackwardMode::Atomic: return deviceRuns(true, false);
    case nerf::HashBackwardMode::SubgroupMerged: return deviceRuns(true, true, true);
    case nerf::HashBackwardMode::SortReduce:
    case nerf::HashBackwardMode::CompareSwap: return true;
  }
  return false;
}

}  // namespace vknerf::test
