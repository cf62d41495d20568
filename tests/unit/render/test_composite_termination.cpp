// Early termination inside composite_forward.comp / composite_backward.comp: the samples each ray
// keeps match the CPU reference (ref::keptSamples) exactly, the kept samples get bit for bit what
// compositing a batch of only them gives, the dropped ones weight 0 and gradient 0, and what was
// dropped was invisible (the colour moves by less than the cut-off transmittance).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/render/composite.h"
#include "reference/occupancy/occupancy_grid.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class CompositeTermination : public test::GpuTest {};

struct PackedBatch {
  std::vector<uint32_t> offsets{0};
  std::vector<float> samples, field, background, dColor, dDepth;  // 2 and 4 per sample, 4, 4, 1 per ray
};

// Rays of 0..60 samples; sigma scaled per ray from faint (never terminates) to opaque, with NaN,
// negative and infinite densities sprinkled in; random backgrounds and upstream gradients.
PackedBatch randomBatch(uint32_t numRays, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  PackedBatch b;
  for (uint32_t r = 0; r < numRays; ++r) {
    uint32_t n = rng() % 61;
    float scale = std::pow(10.0f, 3.0f * uni(rng) - 1.0f), t = uni(rng);
    for (uint32_t i = 0; i < n; ++i) {
      float delta = 0.01f + 0.09f * uni(rng), sigma = scale * uni(rng);
      uint32_t hard = rng() % 200;
      if (hard == 0) sigma = NAN;
      if (hard == 1) sigma = -5.0f;
      if (hard == 2) sigma = INFINITY;
      b.samples.insert(b.samples.end(), {t, delta});
      b.field.insert(b.field.end(), {uni(rng), uni(rng), uni(rng), sigma});
      t += delta;
    }
    b.offsets.push_back(uint32_t(b.samples.size() / 2));
    b.background.insert(b.background.end(), {uni(rng), uni(rng), uni(rng), 0});
    b.dColor.insert(b.dColor.end(), {uni(rng) - 0.5f, uni(rng) - 0.5f, uni(rng) - 0.5f, uni(rng) - 0.5f});
    b.dDepth.push_back(uni(rng) - 0.5f);
  }
  return b;
}

// The first keep[r] samples of every ray.
PackedBatch prefixes(const PackedBatch& b, const std::vector<uint32_t>& keep) {
  PackedBatch c = b;
  c.offsets = {0};
  c.samples.clear();
  c.field.clear();
  for (size_t r = 0; r + 1 < b.offsets.size(); ++r) {
    const uint32_t first = b.offsets[r];
    c.samples.insert(c.samples.end(), b.samples.begin() + 2 * first, b.samples.begin() + 2 * (first + keep[r]));
    c.field.insert(c.field.end(), b.field.begin() + 4 * first, b.field.begin() + 4 * (first + keep[r]));
    c.offsets.push_back(uint32_t(c.samples.size() / 2));
  }
  return c;
}

struct Outputs {
  std::vector<float> color, depth, weights, dField;
  std::vector<uint32_t> kept;
};

// Forward then backward in one recording, as a training step does; NaN sentinels in every output.
// The distortion loss measures every ray over [0, 8] in cone steps (t in [0, ~7] here) with all
// three pieces of its spacing in range.
Outputs composite(Context& ctx, const PackedBatch& b, float maxOpticalDepth, float distortionWeight) {
  const uint32_t rays = uint32_t(b.offsets.size() - 1), n = b.offsets.back();
  auto sized = [&](const std::vector<float>& v) { return gpu::Buffer::of(ctx, v.empty() ? std::vector<float>(4) : v); };
  auto offsets = gpu::Buffer::of(ctx, b.offsets);
  auto samples = sized(b.samples), field = sized(b.field), bg = sized(b.background), dColor = sized(b.dColor),
       dDepth = sized(b.dDepth);
  const std::vector<float> nan(4 * std::max<size_t>({n, rays, 1}), std::numeric_limits<float>::quiet_NaN());
  auto color = gpu::Buffer::of(ctx, nan), depth = gpu::Buffer::of(ctx, nan), weights = gpu::Buffer::of(ctx, nan),
       dField = gpu::Buffer::of(ctx, nan), kept = gpu::Buffer::of(ctx, nan);
  std::vector<float> rayData;
  for (uint32_t r = 0; r < std::max(rays, 1u); ++r) rayData.insert(rayData.end(), {0, 0, 0, 0, 0, 0, -1, 8});
  auto rayBuf = gpu::Buffer::of(ctx, rayData);
  const nerf::DistortionLoss distortion{distortionWeight, 1.0f / 64, 0.01f, 0.08f, rayBuf};
  nerf::Compositor comp(ctx);
  const nerf::CompositeInputs in{rays, 0, offsets, samples, field, {0, 0, 0}, gpu::BufferRange(bg), maxOpticalDepth};
  const bool terminate = maxOpticalDepth < nerf::Compositor::kNoTermination;
  nerf::CompositeOutputs out{color, depth, weights};
  if (terminate) out.keptCounts = gpu::BufferRange(kept);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    comp.recordForward(rec, in, out);
    comp.recordBackward(rec, in, {dColor, dDepth, dField, {distortion}});
  });
  return {color.download<float>(4 * rays), depth.download<float>(rays), weights.download<float>(n),
          dField.download<float>(4 * n), terminate ? kept.download<uint32_t>(rays) : std::vector<uint32_t>{}};
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

// Colour of one ray from samples [first, first + n), in double.
std::array<double, 3> compositeRay(const PackedBatch& b, uint32_t first, uint32_t n) {
  std::array<double, 3> c{0, 0, 0};
  double trans = 1;
  for (uint32_t i = first; i < first + n; ++i) {
    double sigma = ref::sanitizeDensity<double>(b.field[4 * i + 3]);
    double alpha = 1 - std::exp(-sigma * b.samples[2 * i + 1]);
    for (int k = 0; k < 3; ++k) c[k] += trans * alpha * b.field[4 * i + k];
    trans *= 1 - alpha;
  }
  return c;
}

}  // namespace

TEST_F(CompositeTermination, KeepsSamplesUntilOpaqueAsABatchOfOnlyThem) {
  const uint32_t n = 700;
  const float minT = 1e-4f;
  const float maxDepth = nerf::Compositor::maxOpticalDepth(minT);
  auto b = randomBatch(n, 31);
  std::vector<uint32_t> expected(n);
  uint32_t truncated = 0, whole = 0;
  for (uint32_t r = 0; r < n; ++r) {
    const uint32_t first = b.offsets[r], count = b.offsets[r + 1] - first;
    std::vector<float> sigma, delta;
    for (uint32_t i = first; i < first + count; ++i) {
      sigma.push_back(b.field[4 * i + 3]);
      delta.push_back(b.samples[2 * i + 1]);
    }
    expected[r] = ref::keptSamples<float>(sigma, delta, maxDepth);
    truncated += expected[r] < count;
    whole += expected[r] == count && count > 0;
    // What was dropped was invisible: the colour changes by less than the cut-off transmittance
    // (colours are in [0, 1]); 1% slack for the float optical depth against double exp().
    auto full = compositeRay(b, first, count), cut = compositeRay(b, first, expected[r]);
    for (int k = 0; k < 3; ++k) EXPECT_LE(std::fabs(full[k] - cut[k]), 1.01 * minT) << "ray " << r;
  }
  EXPECT_GT(truncated, 100u);  // both outcomes occur often enough to matter
  EXPECT_GT(whole, 100u);

  const auto c = prefixes(b, expected);
  // With the distortion loss too: its sums run over the kept samples only, as in a batch of them.
  for (float distortion : {0.0f, 0.1f}) {
    SCOPED_TRACE(distortion);
    const auto cut = composite(ctx(), b, maxDepth, distortion);
    const auto only = composite(ctx(), c, nerf::Compositor::kNoTermination, distortion);
    for (uint32_t r = 0; r < n; ++r) {
      // Same float sum in the same order as the reference: the kept counts match exactly.
      ASSERT_EQ(cut.kept[r], expected[r]) << "ray " << r;
      for (int k = 0; k < 4; ++k) ASSERT_TRUE(sameBits(cut.color[4 * r + k], only.color[4 * r + k])) << "ray " << r;
      ASSERT_TRUE(sameBits(cut.depth[r], only.depth[r])) << "ray " << r;
      for (uint32_t i = 0; i < b.offsets[r + 1] - b.offsets[r]; ++i) {
        const uint32_t src = b.offsets[r] + i, dst = c.offsets[r] + i;
        if (i < expected[r]) {
          ASSERT_TRUE(sameBits(cut.weights[src], only.weights[dst])) << "ray " << r << " sample " << i;
          for (int k = 0; k < 4; ++k)
            ASSERT_TRUE(sameBits(cut.dField[4 * src + k], only.dField[4 * dst + k])) << "ray " << r << " sample " << i;
        } else {
          ASSERT_EQ(cut.weights[src], 0.0f) << "ray " << r << " sample " << i;
          for (int k = 0; k < 4; ++k) ASSERT_EQ(cut.dField[4 * src + k], 0.0f) << "ray " << r << " sample " << i;
        }
      }
    }
  }
}

TEST(CompositeTerminationHost, RejectsThresholdsOutsideTheUnitInterval) {
  EXPECT_THROW(nerf::Compositor::maxOpticalDepth(0.0f), Error);
  EXPECT_THROW(nerf::Compositor::maxOpticalDepth(1.5f), Error);
  EXPECT_EQ(nerf::Compositor::maxOpticalDepth(1.0f), 0.0f);
}
