// A render's segments put behind one another (nerf::SegmentAccumulator,
// shaders/render/accumulate_segment.comp) against ref::accumulateSegment: three rounds over rays
// with random segments (some opaque, some that did not fill the round's cap, some already ended),
// the colour, depth, transmittance, where each ray goes on, and the counts of live rays and samples.
#include <cmath>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "nerf/render/segment_accumulator.h"
#include "reference/render/segments.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {
using SegmentAccumulatorTest = vknerf::test::GpuTest;
constexpr float kMinTransmittance = 1e-4f;
}  // namespace

TEST_F(SegmentAccumulatorTest, PutsEachSegmentBehindTheLastAndEndsRaysAsTheReference) {
  constexpr uint32_t kRays = 777, kCap = 8;
  std::mt19937 gen(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  nerf::SegmentAccumulator acc(ctx(), kRays);
  std::vector<float> rays(size_t(kRays) * 8), background(size_t(kRays) * 4);
  for (uint32_t r = 0; r < kRays; ++r) {
    rays[8 * r + 3] = r % 13 == 0 ? -1.0f : u(gen);   // t_near; -1: the ray misses the box
    rays[8 * r + 7] = 2.0f + 2.0f * u(gen);           // t_far
    for (int k = 0; k < 3; ++k) background[4 * r + k] = u(gen);
  }
  auto raysBuf = gpu::Buffer::of(ctx(), rays), bgBuf = gpu::Buffer::of(ctx(), background);
  gpu::Buffer color(ctx(), VkDeviceSize(kRays) * 16), depth(ctx(), VkDeviceSize(kRays) * 4);
  std::vector<ref::SegmentedRay<double>> want(kRays);
  for (uint32_t r = 0; r < kRays; ++r) want[r].next = rays[8 * r + 3];

  for (uint32_t round = 0; round < 3; ++round) {
    SCOPED_TRACE(round);
    const bool first = round == 0, last = round == 2;
    // The round's march: rays that have ended get no samples; the others 0..kCap, often kCap.
    std::vector<uint32_t> offsets(kRays + 1, 0);
    std::vector<float> samples, segColor(size_t(kRays) * 4), segDepth(kRays);
    for (uint32_t r = 0; r < kRays; ++r) {
      const uint32_t n = want[r].next < 0 ? 0 : (gen() % 2 ? kCap : gen() % (kCap + 1));
      offsets[r + 1] = offsets[r] + n;
      float t = want[r].next;
      for (uint32_t j = 0; j < n; ++j, t += 0.05f) samples.insert(samples.end(), {t, 0.05f});
      // Opacity: transparent, partly opaque, or opaque; kept clear of the 1e-4 threshold below.
      const float a = n == 0 ? 0.0f : std::vector<float>{0.0f, 0.3f * u(gen), 0.5f + 0.4f * u(gen), 0.99999f}[gen() % 4];
      for (int k = 0; k < 3; ++k) segColor[4 * r + k] = a * u(gen);
      segColor[4 * r + 3] = a;
      segDepth[r] = a * (want[r].next + 0.1f);
    }
    if (samples.empty()) samples.assign(2, 0.0f);
    auto offsetsBuf = gpu::Buffer::of(ctx(), offsets), samplesBuf = gpu::Buffer::of(ctx(), samples);
    auto segColorBuf = gpu::Buffer::of(ctx(), segColor), segDepthBuf = gpu::Buffer::of(ctx(), segDepth);
    // The accumulator composites from its own segment buffers: copy the segment there.
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      rec.copy(segColorBuf, acc.segmentColor(), VkDeviceSize(kRays) * 16);
      rec.copy(segDepthBuf, acc.segmentDepth(), VkDeviceSize(kRays) * 4);
      acc.recordResetCounts(rec);
      acc.record(rec, {kCap, first, last, kMinTransmittance}, {raysBuf, kRays},
                 {.offsets = offsetsBuf, .samples = samplesBuf}, {bgBuf, color, depth});
    });
    uint32_t wantLive = 0, wantSamples = 0;
    for (uint32_t r = 0; r < kRays; ++r) {
      auto& w = want[r];
      if (!first && w.next < 0) continue;  // ended before: untouched
      const uint32_t n = offsets[r + 1] - offsets[r];
      wantSamples += n;
      ref::RayColor<double> seg;
      for (int k = 0; k < 3; ++k) seg.rgb[k] = segColor[4 * r + k];
      seg.opacity = segColor[4 * r + 3];
      seg.depth = segDepth[r];
      const double lastT = n ? samples[2 * (offsets[r + 1] - 1)] : 0.0, lastDelta = n ? 0.05 : 0.0;
      ASSERT_GT(std::fabs(w.transmittance * (1 - seg.opacity) / kMinTransmittance - 1), 1e-3) << "ray " << r;
      ref::accumulateSegment<double>(w, seg, n, kCap, lastT, lastDelta, rays[8 * r + 7], last, kMinTransmittance,
                                     {background[4 * r], background[4 * r + 1], background[4 * r + 2]});
      if (w.next >= 0) ++wantLive;
    }
    EXPECT_EQ(acc.active(), wantLive);
    EXPECT_EQ(acc.samples(), wantSamples);
    const auto gotColor = color.download<float>(size_t(kRays) * 4), gotDepth = depth.download<float>(kRays);
    const auto gotRays = raysBuf.download<float>(size_t(kRays) * 8);
    for (uint32_t r = 0; r < kRays; ++r) {
      const auto& w = want[r];
      // Sums of three or four products of values in [0, 4] in float, with T carried as an opacity
      // (1 - T, rounded): a few float roundings of values <= 4, so 2e-6 absolute.
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(test::near(gotColor[4 * r + k], w.rgb[k], 1e-6, 2e-6)) << "ray " << r;
      EXPECT_TRUE(test::near(gotColor[4 * r + 3], 1 - w.transmittance, 1e-6, 2e-6)) << "ray " << r;
      EXPECT_TRUE(test::near(gotDepth[r], w.depth, 1e-6, 2e-6)) << "ray " << r;
      // Where the ray goes on: the t after its last sample (one float addition), or -1.
      if (w.next < 0)
        EXPECT_EQ(gotRays[8 * r + 3], -1.0f) << "ray " << r;
      else
        EXPECT_TRUE(test::near(gotRays[8 * r + 3], w.next, 1e-6, 0)) << "ray " << r;
    }
    // The reference's t goes on from the float the device wrote (as the next march would).
    for (uint32_t r = 0; r < kRays; ++r)
      if (want[r].next >= 0) want[r].next = gotRays[8 * r + 3];
  }
  for (const auto& w : want) EXPECT_LT(w.next, 0) << "a ray is live after the last round";
}

TEST_F(SegmentAccumulatorTest, RejectsMoreRaysThanItWasBuiltForAndAZeroCap) {
  nerf::SegmentAccumulator acc(ctx(), 64);
  gpu::Buffer big(ctx(), 1 << 16);
  auto attempt = [&](uint32_t rays, uint32_t cap) {
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      acc.record(rec, {cap, true, false, kMinTransmittance}, {big, rays}, {big, big, big, big}, {big, big, big});
    });
  };
  EXPECT_THROW(attempt(65, 8), Error);
  EXPECT_THROW(attempt(64, 0), Error);
  EXPECT_NO_THROW(attempt(64, 8));
}
