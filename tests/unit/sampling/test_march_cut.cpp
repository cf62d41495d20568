// The capacity cut on the device (PackedLayout::recordCutToWholeRays, shaders/sampling/march_cut.comp)
// against the CPU rule it replaces: a batch packed at the sample capacity keeps the rays that end
// below it, rounded down to a multiple of the alignment (at least one alignment, never more than
// the batch), and the rays after those get no samples.
#include <algorithm>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "nerf/sampling/packed_layout.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"

using namespace vknerf;

namespace {

using MarchCut = vknerf::test::GpuTest;
constexpr uint32_t kAlign = 64;

// Offsets of `rays` rays with random sample counts in [0, maxPerRay], clamped at the capacity (as the
// marcher's prefix sum clamps them).
std::vector<uint32_t> clampedOffsets(uint32_t rays, uint32_t maxPerRay, uint32_t capacity, uint32_t seed) {
  std::mt19937 gen(seed);
  std::vector<uint32_t> off(rays + 1, 0);
  for (uint32_t r = 0; r < rays; ++r) off[r + 1] = off[r] + gen() % (maxPerRay + 1);
  for (auto& o : off) o = std::min(o, capacity);
  return off;
}

// The rule on the CPU: (rays kept, samples kept).
std::pair<uint32_t, uint32_t> expectedCut(const std::vector<uint32_t>& off, uint32_t capacity) {
  const uint32_t n = uint32_t(off.size() - 1);
  if (off[n] < capacity) return {n, off[n]};
  uint32_t whole = uint32_t(std::upper_bound(off.begin() + 1, off.end(), capacity - 1) - (off.begin() + 1));
  whole = std::min(std::max(kAlign, whole / kAlign * kAlign), n);
  return {whole, off[whole]};
}

}  // namespace

TEST_F(MarchCut, KeepsTheWholeRaysAndEmptiesTheRest) {
  nerf::PackedLayout layout(ctx(), 5000);
  struct Case {
    uint32_t rays, maxPerRay, capacity;
  };
  for (const Case& c : {Case{1000, 10, 100000}, Case{1000, 10, 64 * 10 + 64}, Case{1000, 10, 3001},
                        Case{5000, 8, 9000}, Case{70, 20, 65 * 20}, Case{333, 4, 333 * 2}}) {
    for (uint32_t seed : {1u, 2u, 3u}) {
      SCOPED_TRACE(testing::Message() << c.rays << " rays, capacity " << c.capacity << ", seed " << seed);
      const auto before = clampedOffsets(c.rays, c.maxPerRay, c.capacity, seed);
      auto offsets = gpu::Buffer::of(ctx(), before);
      auto totals = gpu::Buffer::of(ctx(), std::vector<uint32_t>{before.back(), 7, 7, 7});
      auto whole = gpu::Buffer::of(ctx(), std::vector<uint32_t>{12345u, 0, 0, 0});
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
        layout.recordCutToWholeRays(rec, {c.rays, c.capacity, kAlign}, {.offsets = offsets, .totals = totals},
                                    gpu::BufferRange(whole, 0, 4));
      });
      const auto [rays, samples] = expectedCut(before, c.capacity);
      EXPECT_EQ(whole.download<uint32_t>(1)[0], rays);
      const auto t = totals.download<uint32_t>(4);
      EXPECT_EQ(t[0], samples);
      EXPECT_EQ(uint64_t(t[1]) * t[2], (samples + nerf::PackedLayout::kIndirectLocal - 1) / nerf::PackedLayout::kIndirectLocal);
      const auto after = offsets.download<uint32_t>(c.rays + 1);
      for (uint32_t r = 0; r <= c.rays; ++r)
        ASSERT_EQ(after[r], r <= rays ? before[r] : samples) << "offset " << r;
    }
  }
}
