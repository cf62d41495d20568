// A training forward's segments (nerf::SegmentRows, shaders/sampling/segment_rows.comp) against the
// compositor's cut on the CPU (ref::keptSamples, which the compositor matches bit for bit): segment
// [from, to) lists rows [from, min(to, n)) of exactly the rays whose compositing reaches sample
// `from`, i.e. that keep more than `from` samples. So the segments together list every row the
// compositor reads, and each row once. The densities cover the hard cases: 0, NaN, +inf, negative
// values (which the sanitizer takes as 0), opaque samples and rays of 0 to 40 samples.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "nerf/render/composite.h"
#include "nerf/sampling/segment_rows.h"
#include "reference/occupancy/occupancy_grid.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {
using SegmentRowsTest = vknerf::test::GpuTest;

struct Batch {
  std::vector<uint32_t> offsets;
  std::vector<float> samples, field;  // (t, delta); (r, g, b, sigma)
};

Batch randomBatch(uint32_t rays, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Batch b;
  b.offsets.assign(rays + 1, 0);
  for (uint32_t r = 0; r < rays; ++r) b.offsets[r + 1] = b.offsets[r] + gen() % 41;
  const uint32_t n = b.offsets[rays];
  for (uint32_t i = 0; i < n; ++i) {
    const float delta = gen() % 17 == 0 ? 0.0f : 0.01f + 0.02f * u(gen);
    b.samples.insert(b.samples.end(), {float(i) * 0.03f, delta});
    float sigma = 40.0f * u(gen) * u(gen);  // mostly faint, sometimes dense
    switch (gen() % 29) {
      case 0: sigma = 0.0f; break;
      case 1: sigma = std::numeric_limits<float>::quiet_NaN(); break;
      case 2: sigma = std::numeric_limits<float>::infinity(); break;
      case 3: sigma = -5.0f; break;
      case 4: sigma = 3000.0f; break;
      default: break;
    }
    b.field.insert(b.field.end(), {u(gen), u(gen), u(gen), sigma});
  }
  return b;
}

// The samples ray r keeps, cut on the CPU.
uint32_t keptOf(const Batch& b, size_t r, float maxDepth) {
  std::vector<float> sigma, delta;
  for (uint32_t i = b.offsets[r]; i < b.offsets[r + 1]; ++i)
    sigma.push_back(b.field[4 * size_t(i) + 3]), delta.push_back(b.samples[2 * size_t(i) + 1]);
  return ref::keptSamples(sigma, delta, maxDepth);
}

// The rows segment [from, to) must list.
std::vector<uint32_t> wantRows(const Batch& b, float maxDepth, uint32_t from, uint32_t to) {
  std::vector<uint32_t> rows;
  for (size_t r = 0; r + 1 < b.offsets.size(); ++r) {
    const uint32_t begin = b.offsets[r], n = b.offsets[r + 1] - begin;
    if (keptOf(b, r, maxDepth) <= from) continue;
    for (uint32_t j = from; j < std::min(to, n); ++j) rows.push_back(begin + j);
  }
  return rows;
}

}  // namespace

TEST_F(SegmentRowsTest, ListsTheRowsTheCompositorReadsSegmentBySegment) {
  constexpr uint32_t kCapacity = 60000;
  nerf::SegmentRows segments(ctx(), kCapacity);
  const float maxDepth = nerf::Compositor::maxOpticalDepth(1e-4f);
  for (uint32_t rays : {1u, 200u, 1400u}) {
    SCOPED_TRACE(testing::Message() << rays << " rays");
    Batch b = randomBatch(rays, rays);
    ASSERT_LE(b.offsets.back(), kCapacity);
    b.samples.resize(size_t(kCapacity) * 2), b.field.resize(size_t(kCapacity) * 4);
    auto offsets = gpu::Buffer::of(ctx(), b.offsets), samples = gpu::Buffer::of(ctx(), b.samples);
    auto field = gpu::Buffer::of(ctx(), b.field);
    const nerf::PackedSamples packed{offsets, samples, offsets, offsets};
    std::vector<uint32_t> listedOnce;
    for (const auto& segment : {std::pair{0u, 4u}, {4u, 8u}, {8u, 16u}, {16u, UINT32_MAX}, {3u, 5u}}) {
      const uint32_t from = segment.first, to = segment.second;  // plain names: a lambda captures them
      SCOPED_TRACE(testing::Message() << "segment [" << from << ", " << to << ")");
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) { segments.record(rec, rays, packed, field, maxDepth, from, to); });
      const uint32_t count = segments.count().buffer->download<uint32_t>(1)[0];
      std::vector<uint32_t> got = segments.rows().download<uint32_t>(count);
      std::sort(got.begin(), got.end());  // the rays' order in the list varies
      const std::vector<uint32_t> want = wantRows(b, maxDepth, from, to);
      ASSERT_EQ(got, want);
      if (from != 3u) listedOnce.insert(listedOnce.end(), got.begin(), got.end());
    }
    // Together the segments list each kept row once: none the compositor reads is missing.
    std::sort(listedOnce.begin(), listedOnce.end());
    EXPECT_TRUE(std::adjacent_find(listedOnce.begin(), listedOnce.end()) == listedOnce.end());
    std::vector<uint32_t> keptRows;
    for (uint32_t r = 0; r < rays; ++r)
      for (uint32_t j = 0; j < keptOf(b, r, maxDepth); ++j) keptRows.push_back(b.offsets[r] + j);
    EXPECT_TRUE(std::includes(listedOnce.begin(), listedOnce.end(), keptRows.begin(), keptRows.end()));
    if (rays > 1) EXPECT_LT(listedOnce.size(), b.offsets[rays]) << "the rows behind the cuts are not all listed";
  }
}

TEST_F(SegmentRowsTest, AnEmptySegmentOrShortBuffersAreErrors) {
  nerf::SegmentRows segments(ctx(), 100);
  auto offsets = gpu::Buffer::zeros(ctx(), 4 * 11), samples = gpu::Buffer::zeros(ctx(), 8 * 100);
  auto field = gpu::Buffer::zeros(ctx(), 16 * 100), small = gpu::Buffer::zeros(ctx(), 16 * 10);
  const nerf::PackedSamples packed{offsets, samples, offsets, offsets};
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    EXPECT_THROW(segments.record(rec, 10, packed, field, 9.2f, 4, 4), Error);
    EXPECT_THROW(segments.record(rec, 10, packed, small, 9.2f, 0, 4), Error);
    EXPECT_THROW(segments.record(rec, 11, packed, field, 9.2f, 0, 4), Error);
  });
}
