#pragma once
// Which variant of each gradient kernel a device runs, chosen here and nowhere else from the
// device's features. Vulkan requires neither float atomics on buffers (RADV has them from RDNA3,
// ANV from Arc, many mobile GPUs not at all) nor subgroup arithmetic or vote (1.1 requires only
// the basic subgroup operations). A kernel's SPIR-V declares the capabilities of every operation it
// contains, even in code a specialization constant turns off, and a pipeline declaring one the
// device lacks is invalid: each path is its own SPIR-V module.
#include <cstdint>

#include "gpu/device/device.h"

namespace vknerf::nerf {

enum class HashBackwardMode : uint32_t;  // nerf/encoding/hash_encoding.h

struct GradientPaths {
  // The dense weight gradient (shaders/network/mlp_dense_dw.glsl) adds its sums into the gradient
  // buffer with float atomicAdd, else with a compare-and-swap loop on the float's bits (uint atomics
  // on storage buffers are core Vulkan).
  bool dwFloatAtomics = false;
  // It sums a subgroup's invocations with subgroupAdd before adding, else a workgroup's in shared
  // memory.
  bool dwSubgroupReduce = false;
  // The hash table's gradient: Atomic with float atomics, else CompareSwap (SortReduce, also
  // without float atomics and deterministic, on request).
  HashBackwardMode hash{};
  // HashBackwardMode::SubgroupMerged can run (subgroup vote and arithmetic).
  bool hashSubgroupMerge = false;
};

GradientPaths gradientPathsFor(const gpu::KernelFeatures& features);
// The paths of ctx's device: its features in force (gpu::Device::features(), a profile's applied;
// for an adopted device, float atomics as the caller declared them and the subgroup operations the
// physical device supports, which need no enabling).
GradientPaths gradientPathsFor(const Context& ctx);

}  // namespace vknerf::nerf
