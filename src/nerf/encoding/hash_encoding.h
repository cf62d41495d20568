#pragma once
// Multiresolution hash encoding (instant-ngp's grid; shaders/encoding/encode_hash.comp and
// shaders/encoding/encode_hash_backward.comp). Layouts (table, levels) are documented in
// src/core/layouts/hash_grid_layout.h, the hashing in tests/reference/encoding/hash_encoding.h.
// Inputs are vec4 positions already in [-1, 1]^3 (sample_points.comp); the L * F features of a
// sample go into a row-major feature matrix (row stride a multiple of 4 floats) at a column offset
// that is a multiple of 4, as paddedDims() = L * F rounded up to 4 columns, padding written as 0 and
// columns outside the block untouched (as FrequencyEncoding).
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/limited_dispatch.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/encoding.h"
#include "core/layouts/hash_grid_layout.h"
#include "encoding/encode_hash_shared.h"
#include "encoding/hash_sort_shared.h"

namespace vknerf::gpu {
class PrefixSum;
}  // namespace vknerf::gpu

namespace vknerf::nerf {

using HashGridConfig = core::HashGridConfig;

// How the backward pass scatters into the table. Atomic is the default where the device has float
// atomics (nerf/network/gradient_paths.h), CompareSwap elsewhere: on lavapipe Atomic was the
// fastest in every same-run comparison (`vknerf bench hash`; the table and the reasons are in
// docs/performance.md, "Hash-table gradient"): SubgroupMerged took 1.1-1.5x its time, SortReduce
// 2.0-3.0x at F = 2 and 1.6-1.9x at F = 8. An atomic there is a scalar loop over the lanes, uint or
// float, contended or not, so the contention sorting removes costs nothing, while SortReduce pays
// two uint atomics and a scattered 16-byte slot store per contribution, plus the reduce.
// CompareSwap (1.2-1.9x Atomic's time) and SortReduce are for devices without float atomics,
// SortReduce where a deterministic gradient matters or contended swaps are slow; SubgroupMerged for
// devices where contended coarse-level atomics are slow.
enum class HashBackwardMode : uint32_t {
  Atomic = 0,          // one float atomicAdd per lane, corner and feature (none for an all-zero level group)
  SubgroupMerged = 1,  // lanes of a subgroup hitting the same entry add first, then one atomic
                       // (needs subgroup vote and arithmetic as well)
  // Counting sort of the contributions by table entry (uint atomics), then a per-entry sum in exact
  // fixed point: deterministic, no float atomics (so also on devices without them). A non-finite
  // term makes its entry's gradient non-finite (NaN). Needs 2^T at most the prefix sum's capacity
  // (maxComputeWorkGroupCount[0] * 256: T <= 23 on lavapipe).
  // shaders/encoding/encode_hash_backward_{count,scatter,reduce}.comp.
  SortReduce = 2,
  // Atomic's scatter with each add a compare-and-swap loop on the float's bits (core uint atomics):
  // no float atomics either, and on lavapipe as fast as Atomic (an uncontended swap is one scalar
  // atomic, as atomicAdd is). A contended coarse entry retries; SortReduce never does.
  CompareSwap = 3,
};

// Where recordBackward also writes the position gradient (recordPositionGradient's arguments).
struct PositionGradientTarget {
  gpu::BufferRange params, dPositions;
};

class HashEncoding final : public Encoding {
 public:
  // Limits: 1..24 levels, F in {1, 2, 4, 8}, T in 2..24, N_min >= 1, b >= 1, and the whole table
  // within one storage binding (maxStorageBufferRange: 128 MiB on lavapipe, e.g. L=16 F=2 T=20).
  // Without a mode: the device's (gradientPathsFor(ctx).hash).
  HashEncoding(Context& ctx, HashGridConfig config);
  HashEncoding(Context& ctx, HashGridConfig config, HashBackwardMode mode);
  ~HashEncoding();

  const HashGridConfig& config() const { return config_; }
  uint32_t outputDims() const override { return config_.levels * config_.featuresPerLevel; }
  size_t parameterCount() const override { return core::hashGridParameterCount(config_); }
  uint32_t resolution(uint32_t level) const { return core::hashGridResolution(config_, level); }
  bool dense(uint32_t level) const { return core::hashGridDense(config_, level); }
  HashBackwardMode backwardMode() const { return mode_; }
  // SortReduce: the most (sample, level, corner) contributions sorted in one pass (default: 128 MiB
  // of slots, 16 bytes each for F <= 2). Smaller budgets split a batch into more passes (tests; >= 8).
  uint32_t sortSlotBudget() const { return slotBudget_; }
  void setSortSlotBudget(uint32_t slots);
  // uniform(-1e-4, 1e-4), deterministic in the seed (core::hashGridInitialParameters).
  std::vector<float> initialParameters(uint32_t seed) const override;
  // The parts of the table a lookup can reach (core::hashGridUsedRuns): Adam's dense step would
  // otherwise run over the unused end of each dense level's slot too (2^17 entries a level on the
  // 800x800 object: 27% of the table).
  std::vector<ParameterRange> trainedParts() const override;

  // rows.inputs: `count` vec4 positions; params: parameterCount() floats (both bound as texel
  // buffers: offsets multiples of minTexelBufferOffsetAlignment); rows.features: the block written
  // (nerf/encoding/encoded_rows.h); rows at and past rows.rowLimit are left untouched.
  void recordForward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& params) override;
  // grads (parameterCount() floats, params' layout) += d(sum dFeatures . features) / d params, with
  // dFeatures read from rows.features (the forward's layout; its padding columns are ignored).
  // Atomic and SubgroupMerged need float atomics. SortReduce does not; it works in passes of at
  // most sortSlotBudget() contributions (levels x 8 corners x samples) through scratch buffers this
  // object owns, grown on demand. Grown buffers are kept, not freed, so every recording stays valid
  // while this object lives. The rows at and past rows.rowLimit add nothing to grads.
  // With `position`, also recordPositionGradient(rows, position->params, position->dPositions): in
  // the same pass over the corners with float atomics (Atomic, SubgroupMerged), after it otherwise.
  void recordBackward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& grads,
                      const std::optional<PositionGradientTarget>& position = std::nullopt);
  // The same through the encodings' contract: gradients.dInputs is the position gradient.
  void recordBackward(gpu::Recorder& rec, const EncodedRows& rows, const EncodingGradients& gradients) override;
  // dPositions (vec4 per row, w = 0) = d(sum dFeatures . features) / d position, the position in
  // [-1, 1]^3 as rows.inputs hold it (0 along an axis where it lies outside); rows as recordBackward
  // reads them, params as recordForward. Rows past rows.rowLimit are left untouched. The kernel is
  // built by the first call (only camera refinement needs it).
  void recordPositionGradient(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& params,
                              const gpu::BufferRange& dPositions);

 private:
  using Push = glsl::HashPush;
  gpu::BufferRange exactly(const gpu::BufferRange& table) const;
  void checkPositionGradient(const EncodedRows& rows, const gpu::BufferRange& params,
                             const gpu::BufferRange& dPositions, const char* what) const;
  template <class Fn>
  void forChunks(const EncodedRows& rows, const gpu::BufferRange& table, const char* what, Fn&& fn);

  // Count and scatter kernels' push constants (shaders/encoding/hash_sort_shared.h).
  using SortPush = glsl::HashSortPush;
  void recordSortReduce(gpu::Recorder& rec, const gpu::BufferRange& positions, const gpu::BufferRange& dFeatures,
                        const Push& p, const gpu::BufferRange& grads, const gpu::LimitedRows& limited);
  void ensureSortScratch(uint64_t slots, uint64_t entries);

  Context& ctx_;
  HashGridConfig config_;
  HashBackwardMode mode_;
  Push push_{};
  gpu::Kernel forward_, backward_;
  // SortReduce: kernels and scratch (capacities in slots and in entries per pass).
  gpu::Kernel count_, scatter_, reduce_[3];
  uint32_t slotBudget_ = 0;
  uint64_t slotCap_ = 0, entryCap_ = 0;
  gpu::Buffer counts_, cursor_, slots_, spanMax_, spanAcc_;
  std::unique_ptr<gpu::PrefixSum> scan_;
  std::vector<gpu::Buffer> retired_;  // outgrown scratch: earlier recordings may still use it
  std::vector<std::unique_ptr<gpu::PrefixSum>> retiredScans_;
  std::optional<gpu::Kernel> positionGradient_, backwardWithPosition_;  // built by their first use
  gpu::LimitedDispatch limited_, limitedBackward_, limitedPosition_;  // workgroup counts under a row limit
};

}  // namespace vknerf::nerf
