// sum_partials.comp (nerf/loss/partial_sums.h): a loss term's values summed per group of 128 on the
// device, against the same sums in double.
#include <cmath>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/loss/partial_sums.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class PartialSums : public test::GpuTest {};

TEST_F(PartialSums, SumEachGroupOfOneComponent) {
  // 1000 rows of a vec4 (7 full groups and a partial one), the sum of component 2; the partials
  // after the last group's must stay as they were.
  const uint32_t count = 1000, stride = 4, component = 2;
  std::mt19937 gen(5);
  std::uniform_real_distribution<float> u(-1.0f, 3.0f);
  std::vector<float> values(size_t(count) * stride);
  for (float& v : values) v = u(gen);
  const uint32_t groups = nerf::PartialSums::partialCount(count);
  ASSERT_EQ(groups, 8u);
  auto vb = gpu::Buffer::of(ctx(), values);
  auto pb = gpu::Buffer::of(ctx(), std::vector<float>(groups + 2, -7.0f));
  nerf::PartialSums sums(ctx());
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) { sums.record(rec, {vb, count, stride, component}, pb); });
  const auto got = pb.download<float>();
  for (uint32_t g = 0; g < groups; ++g) {
    double want = 0, size = 0;
    for (uint32_t i = g * 128; i < std::min(count, (g + 1) * 128); ++i) {
      want += values[size_t(i) * stride + component];
      size += std::fabs(values[size_t(i) * stride + component]);
    }
    // A tree of 7 float additions per value: at most 7 roundings of 2^-24 of the magnitudes'
    // sum (8 with headroom).
    EXPECT_TRUE(test::near(got[g], want, 0, 8 * std::ldexp(size, -24))) << "group " << g << ": " << got[g] << " vs " << want;
  }
  EXPECT_EQ(got[groups], -7.0f);
  EXPECT_EQ(got[groups + 1], -7.0f);
}

TEST_F(PartialSums, BuffersTooSmallOrAComponentOutsideTheStrideAreErrors) {
  auto vb = gpu::Buffer::zeros(ctx(), 64 * 4), pb = gpu::Buffer::zeros(ctx(), 4);
  nerf::PartialSums sums(ctx());
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    EXPECT_THROW(sums.record(rec, {vb, 65, 1, 0}, pb), Error);   // more values than the buffer holds
    EXPECT_THROW(sums.record(rec, {vb, 129, 0, 0}, pb), Error);  // no stride
    EXPECT_THROW(sums.record(rec, {vb, 16, 4, 4}, pb), Error);   // the component past the stride
    EXPECT_THROW(sums.record(rec, {vb, 64, 1, 0}, gpu::BufferRange(pb, 0, 0)), Error);  // no room for a partial
  });
}

}  // namespace
