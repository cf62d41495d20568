#include "nerf/network/gradient_paths.h"

#include "nerf/encoding/hash_encoding.h"

namespace vknerf::nerf {

GradientPaths gradientPathsFor(const gpu::KernelFeatures& f) {
  GradientPaths p;
  // Where the device has them, float atomics are the faster path (on lavapipe: `vknerf bench mlp`
  // and `vknerf bench hash`, docs/performance.md).
  p.dwFloatAtomics = f.bufferFloatAtomicAdd;
  p.dwSubgroupReduce = f.subgroupArithmetic;
  p.hash = f.bufferFloatAtomicAdd ? HashBackwardMode::Atomic : HashBackwardMode::SortReduce;
  p.hashSubgroupMerge = f.bufferFloatAtomicAdd && f.subgroupArithmetic && f.subgroupVote;
  return p;
}

GradientPaths gradientPathsFor(const Context& ctx) {
  const gpu::Device& device = gpu::device(ctx);
  gpu::KernelFeatures f = device.features();
  if (!device.owned()) {
    const gpu::KernelFeatures supported = gpu::supportedKernelFeatures(device.physicalDevice());
    f.subgroupArithmetic = supported.subgroupArithmetic;
    f.subgroupVote = supported.subgroupVote;
    f.subgroupSize = supported.subgroupSize;
    f.bufferFloatAtomicAdd = ctx.floatAtomics();
  }
  return gradientPathsFor(f);
}

}  // namespace vknerf::nerf
