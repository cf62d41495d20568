#include "nerf/network/gradient_paths.h"

#include "nerf/encoding/hash_encoding.h"

namespace vknerf::nerf {

GradientPaths gradientPathsFor(const gpu::KernelFeatures& f) {
  GradientPaths p;
  // Where the device has them, float atomics and subgroupAdd. On lavapipe the dW's compare-and-swap
  // adds after subgroupAdd were as fast (an uncontended one is a scalar atomic, as atomicAdd is:
  // 39-47 against 37-40 GFLOP/s at widths 64 and 128, `VKNERF_MLP_TUNING=dwFloatAtomics=0 vknerf
  // bench mlp`), the workgroup reduction 10-20% slower (30-37, `dwSubgroup=0`). The hash grid's
  // compare-and-swap scatter took 1.2-1.9x Atomic's time, SortReduce 2.5-3.0x (`vknerf bench hash`;
  // the contended case, the samples of rays in coarse levels, costs the swaps most).
  p.dwFloatAtomics = f.bufferFloatAtomicAdd;
  p.dwSubgroupReduce = f.subgroupArithmetic;
  p.hash = f.bufferFloatAtomicAdd ? HashBackwardMode::Atomic : HashBackwardMode::CompareSwap;
  p.hashSubgroupMerge = f.bufferFloatAtomicAdd && f.subgroupArithmetic && f.subgroupVote;
  return p;
}

GradientPaths gradientPathsFor(const Context& ctx) {
  return gradientPathsFor(gpu::device(ctx).features());
}

}  // namespace vknerf::nerf
