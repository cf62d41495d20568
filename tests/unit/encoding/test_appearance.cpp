// The appearance embedding's kernels (nerf/encoding/appearance_embedding.h: appearance_rows.comp,
// appearance_gradient.comp, appearance_mean.comp) against the CPU reference
// (src/reference/encoding/appearance.h).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "nerf/encoding/appearance_embedding.h"
#include "reference/encoding/appearance.h"
#include "reference/rays/camera_runs.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class Appearance : public test::GpuTest {};

constexpr uint32_t kPhotos = 70;  // the per-photo sums: several workgroups, the last partly filled
constexpr uint32_t kDims = 8, kStride = 28, kOffset = 16;  // [SH 16 | vector 8 | 4 unused]
constexpr uint32_t kRays = 200, kRows = 900;
constexpr float kSentinel = -7.0f;

std::vector<float> uniform(size_t n, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> v(n);
  for (auto& x : v) x = u(gen);
  return v;
}

// Each ray's photo (pixelIds.x) and the packed (photo, pixel) words the kernels read.
struct Batch {
  std::vector<uint32_t> rayPhoto, pixelIds, sampleRay, rowOffsets;
};

// `rays` rays in runs of one photo each, as a training batch comes (ref::groupedCamera).
Batch randomBatch(uint32_t seed, uint32_t rays = kRays) {
  std::mt19937 gen(seed);
  Batch b;
  for (uint32_t r = 0; r < rays; ++r) {
    b.rayPhoto.push_back(ref::groupedCamera(seed, r, rays, kPhotos));
    b.pixelIds.insert(b.pixelIds.end(), {b.rayPhoto.back(), uint32_t(gen() % 1000)});
  }
  // Rays of 0..8 rows each, packed in order (as the march and KeptRows write them).
  b.rowOffsets.push_back(0);
  for (uint32_t r = 0; r < rays; ++r) b.rowOffsets.push_back(b.rowOffsets.back() + gen() % 9);
  for (uint32_t q = 0; q < kRows; ++q) b.sampleRay.push_back(gen() % kRays);
  return b;
}

}  // namespace

// Training: every row below the device's limit gets its ray's photo's vector, bit for bit (a
// copy); the SH columns, the columns past the vector and the rows past the limit are untouched.
TEST_F(Appearance, TrainingRowsCopyTheirRaysPhotosVectors) {
  nerf::AppearanceEmbedding emb(ctx(), kDims);
  const auto table = uniform(size_t(kPhotos) * kDims, 1);
  const Batch b = randomBatch(2);
  const uint32_t limit = 777;
  auto tableBuf = gpu::Buffer::of(ctx(), table), ids = gpu::Buffer::of(ctx(), b.pixelIds);
  auto rays = gpu::Buffer::of(ctx(), b.sampleRay);
  auto features = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * kStride, kSentinel));
  auto limitBuf = gpu::Buffer::of(ctx(), std::vector<uint32_t>{limit, 0, 0, 0});
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    nerf::AppearanceRows rows{kRows, features, kStride, kOffset, gpu::BufferRange(limitBuf, 0, 4)};
    rows.pixelIds = gpu::BufferRange(ids), rows.sampleRay = gpu::BufferRange(rays);
    emb.recordRows(rec, rows, tableBuf);
  });
  std::vector<float> want(size_t(kRows) * kStride, kSentinel);
  ref::appearanceRows(table, kDims, b.rayPhoto, b.sampleRay, limit, kStride, kOffset, -1, want);
  const auto got = features.download<float>(want.size());
  ASSERT_EQ(std::memcmp(got.data(), want.data(), want.size() * 4), 0);
  // The test must see something: the written rows differ from the sentinel.
  EXPECT_NE(got[kOffset], kSentinel);
}

// A render: every row gets one table row (a chosen photo's), or the mean of the photos' vectors.
// The mean sums kPhotos floats in order: the float error is below kPhotos * 2^-24 * sum|v| ~ 4e-6
// for |v| <= 1, and dividing adds one rounding; 1e-5 absolute + 1e-5 relative leaves a margin while
// a wrong photo count (an error of at least 1/70 of the mean) still fails.
TEST_F(Appearance, RenderRowsGetAChosenPhotosVectorOrTheMean) {
  nerf::AppearanceEmbedding emb(ctx(), kDims);
  const auto table = uniform(size_t(kPhotos) * kDims, 3);
  auto tableBuf = gpu::Buffer::of(ctx(), table), mean = gpu::Buffer::zeros(ctx(), kDims * 4);
  auto chosen = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * kStride, kSentinel));
  auto averaged = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * kStride, kSentinel));
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    nerf::AppearanceRows rows{kRows, chosen, kStride, kOffset};
    rows.fixedRow = 41;
    emb.recordRows(rec, rows, tableBuf);
    emb.recordMean(rec, kPhotos, tableBuf, mean);
    rows.features = averaged, rows.fixedRow = 0;
    emb.recordRows(rec, rows, mean);
  });
  std::vector<float> want(size_t(kRows) * kStride, kSentinel);
  ref::appearanceRows(table, kDims, {}, {}, kRows, kStride, kOffset, 41, want);
  const auto got = chosen.download<float>(want.size());
  ASSERT_EQ(std::memcmp(got.data(), want.data(), want.size() * 4), 0);
  const auto m = ref::appearanceMean(table, kDims, kPhotos);
  const auto rowsGot = averaged.download<float>(want.size());
  for (uint32_t row = 0; row < kRows; row += 97)
    for (uint32_t k = 0; k < kStride; ++k) {
      const float v = rowsGot[size_t(row) * kStride + k];
      if (k < kOffset || k >= kOffset + kDims) ASSERT_EQ(v, kSentinel) << "column " << k << " written";
      else EXPECT_TRUE(test::near(v, m[k - kOffset], 1e-5, 1e-5)) << "row " << row << " column " << k;
    }
}

// The per-photo sum of dL/d(vector columns) over the rows of the photo's rays, cut to the device's
// ray count, over a batch in runs of one photo each. Each entry sums up to a few dozen floats in a
// fixed order (a lane's rows in turn, then a tree over the lanes): the float error is below
// n * 2^-24 * sum|terms| with n below 64 + 3 (a photo's rows here, then the tree's levels), so the absolute tolerance is 1e-5 * sum|terms| (the
// reference's sum of magnitudes, entry by entry), which any missing or doubled row (at least one
// whole term) exceeds. Two runs agree bit for bit.
TEST_F(Appearance, GradientSumsEachPhotosRowsDeterministically) {
  // A few dims (12: a vec4 count that is not a power of two), and the most the configuration
  // allows (every vec4 slot of the kernel's shared sums). More rays than photos (each photo a run
  // of 2 or 3), and fewer (runs of one ray: 20 photos have none, and a zero gradient).
  for (const uint32_t dims : {8u, 12u, 64u})
    for (const uint32_t rays : {kRays, 50u}) {
      SCOPED_TRACE(testing::Message() << dims << " dims, " << rays << " rays");
      const uint32_t kDims = dims, kStride = 16 + dims + 4;  // [SH 16 | vector | 4 unused]
      nerf::AppearanceEmbedding emb(ctx(), kDims);
      const Batch b = randomBatch(4, rays);
      const uint32_t trained = rays * 3 / 4;  // the device's ray count: the rays past it add nothing
      const uint32_t rows = b.rowOffsets.back();
      const auto dDir = uniform(size_t(rows) * kStride, 5);
      auto ids = gpu::Buffer::of(ctx(), b.pixelIds), offsets = gpu::Buffer::of(ctx(), b.rowOffsets);
      auto dDirBuf = gpu::Buffer::of(ctx(), dDir);
      auto count = gpu::Buffer::of(ctx(), std::vector<uint32_t>{trained, 0, 0, 0});
      auto run = [&] {
        auto grads = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kPhotos) * kDims, kSentinel));
        test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
          emb.recordGradient(rec, {rays, ids, offsets, dDirBuf, gpu::BufferRange(count, 0, 4), kStride, kOffset}, kPhotos,
                             grads);
        });
        return grads.download<float>(size_t(kPhotos) * kDims);
      };
      const auto got = run(), again = run();
      const auto want = ref::appearanceGradient(dDir, kDims, kStride, kOffset, b.rayPhoto, b.rowOffsets, trained, kPhotos);
      std::vector<float> absDir(dDir.size());
      for (size_t i = 0; i < dDir.size(); ++i) absDir[i] = std::fabs(dDir[i]);
      const auto scale =
          ref::appearanceGradient(absDir, kDims, kStride, kOffset, b.rayPhoto, b.rowOffsets, trained, kPhotos);
      int nonzero = 0;
      for (size_t i = 0; i < want.size(); ++i) {
        EXPECT_TRUE(test::near(got[i], want[i], 0.0, 1e-5 * scale[i] + 1e-30))
            << "photo " << i / kDims << " entry " << i % kDims;
        nonzero += want[i] != 0.0;
      }
      EXPECT_GT(nonzero, int(want.size()) * int(trained) / int(2 * std::max(rays, kPhotos)));  // the photos with rows
      ASSERT_EQ(std::memcmp(got.data(), again.data(), got.size() * 4), 0) << "the sums differ between runs";
    }
}

TEST_F(Appearance, DimsThatCannotWorkAreErrors) {
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), 0), Error);
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), 6), Error);
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), 68), Error);
}
