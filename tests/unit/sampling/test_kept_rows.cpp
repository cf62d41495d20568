// The kept samples packed for the backward (nerf::KeptRows, shaders/sampling/kept_rows.comp) against
// the packing on the CPU: ray r's first kept[r] marched samples become consecutive packed rows, in
// ray order, each with the marched row it came from and that sample's position; the total is the
// sum of the kept counts.
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "nerf/sampling/kept_rows.h"
#include "support/gpu_test.h"
#include "support/random_values.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {
using KeptRowsTest = vknerf::test::GpuTest;
}  // namespace

TEST_F(KeptRowsTest, PacksEachRaysKeptSamplesInOrder) {
  constexpr uint32_t kMaxRays = 2000, kCapacity = 20000;
  nerf::KeptRows kept(ctx(), kMaxRays, kCapacity);
  auto positions = gpu::Buffer::of(ctx(), test::uniformFloats(size_t(kCapacity) * 4, 7));
  const auto pos = positions.download<float>();
  // Rays with no samples, rays that keep none, all or some of theirs, and a batch of one ray.
  for (uint32_t rays : {1u, 333u, kMaxRays}) {
    for (uint32_t seed : {1u, 2u}) {
      SCOPED_TRACE(testing::Message() << rays << " rays, seed " << seed);
      std::mt19937 gen(seed * 1000 + rays);
      std::vector<uint32_t> offsets(rays + 1, 0), counts(rays);
      for (uint32_t r = 0; r < rays; ++r) {
        const uint32_t n = gen() % 11;  // 0..10 marched samples
        offsets[r + 1] = offsets[r] + n;
        counts[r] = gen() % 3 == 0 ? n : (n ? gen() % (n + 1) : 0);
      }
      std::vector<uint32_t> wantRows;
      std::vector<float> wantPos;
      for (uint32_t r = 0; r < rays; ++r)
        for (uint32_t j = 0; j < counts[r]; ++j) {
          wantRows.push_back(offsets[r] + j);
          for (int k = 0; k < 4; ++k) wantPos.push_back(pos[size_t(offsets[r] + j) * 4 + k]);
        }
      auto offsetBuf = gpu::Buffer::of(ctx(), offsets);
      kept.counts().upload(counts);
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) { kept.record(rec, rays, offsetBuf, positions); });
      const uint32_t total = uint32_t(wantRows.size());
      ASSERT_EQ(kept.total().buffer->download<uint32_t>(1)[0], total);
      const auto rows = kept.rows().download<uint32_t>();
      const auto keptPos = kept.positions().download<float>(size_t(total) * 4);
      for (uint32_t i = 0; i < total; ++i) ASSERT_EQ(rows[i], wantRows[i]) << "packed row " << i;
      for (size_t i = 0; i < wantPos.size(); ++i) ASSERT_EQ(keptPos[i], wantPos[i]) << "position float " << i;
    }
  }
}

TEST_F(KeptRowsTest, RejectsMoreRaysThanItWasBuiltFor) {
  nerf::KeptRows kept(ctx(), 10, 100);
  auto offsets = gpu::Buffer::zeros(ctx(), 4 * 12);
  auto positions = gpu::Buffer::zeros(ctx(), 16 * 100);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    EXPECT_THROW(kept.record(rec, 11, offsets, positions), Error);
  });
}
