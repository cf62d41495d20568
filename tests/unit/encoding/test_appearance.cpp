// The appearance embedding's kernels (nerf/encoding/appearance_embedding.h: appearance_bias.comp,
// appearance_gradient.comp, appearance_weights_gradient.comp, appearance_mean.comp) against the CPU
// reference (tests/reference/encoding/appearance.h), and that reference against finite differences of
// the network it stands for: the vector as input columns of the colour layer.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/appearance_embedding.h"
#include "reference/encoding/appearance.h"
#include "reference/network/mlp.h"
#include "reference/rays/camera_runs.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class Appearance : public test::GpuTest {};

constexpr uint32_t kPhotos = 70;  // the per-photo sums: several workgroups, the last partly filled
constexpr uint32_t kDims = 8, kWidth = 32;  // the fast model's colour layer: 64 / 2
constexpr uint32_t kRays = 200;
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
  std::vector<uint32_t> rayPhoto, pixelIds, rowOffsets;
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
  return b;
}

}  // namespace

// A photo's bias is its vector times W_a: dims products summed in float in the reference's order
// (k ascending), so 2e-6 relative and absolute (dims * 2^-24 of terms of magnitude <= 1 each:
// 8 * 6e-8 * 8 ~ 4e-6 at worst for dims 8) against a wrong row or column (an error of a whole term).
// The rows [first, first + count): the training photos, a chosen photo's one row, and the mean's.
// The mean sums kPhotos floats in order: below kPhotos * 2^-24 * sum|v| ~ 4e-6 for |v| <= 1, and
// dividing adds one rounding; 1e-5 leaves a margin while a wrong photo count (an error of at least
// 1/70 of the mean) still fails.
TEST_F(Appearance, BiasIsEachVectorTimesItsWeights) {
  nerf::AppearanceEmbedding emb(ctx(), kDims, kWidth);
  const auto vectors = uniform(size_t(kPhotos) * kDims, 1), weights = uniform(size_t(kDims) * kWidth, 2);
  auto vBuf = gpu::Buffer::of(ctx(), vectors), wBuf = gpu::Buffer::of(ctx(), weights);
  auto all = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kPhotos) * kWidth, kSentinel));
  auto chosen = gpu::Buffer::of(ctx(), std::vector<float>(2 * kWidth, kSentinel));
  auto mean = gpu::Buffer::zeros(ctx(), kDims * 4), meanBias = gpu::Buffer::zeros(ctx(), kWidth * 4);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    emb.recordBias(rec, {vBuf, wBuf}, 0, kPhotos, all);
    emb.recordBias(rec, {vBuf, wBuf}, 41, 1, chosen);
    emb.recordMean(rec, kPhotos, vBuf, mean);
    emb.recordBias(rec, {mean, wBuf}, 0, 1, meanBias);
  });
  auto expectRows = [](const std::vector<float>& got, const std::vector<double>& want, double tol, const char* what) {
    for (size_t i = 0; i < want.size(); ++i)
      EXPECT_TRUE(test::near(got[i], want[i], tol, tol)) << what << " [" << i << "]";
  };
  expectRows(all.download<float>(size_t(kPhotos) * kWidth), ref::appearanceBias(vectors, weights, kDims, kWidth, 0, kPhotos),
             2e-6, "every photo");
  const auto one = chosen.download<float>(2 * kWidth);
  expectRows(one, ref::appearanceBias(vectors, weights, kDims, kWidth, 41, 1), 2e-6, "photo 41");
  EXPECT_EQ(one[kWidth], kSentinel) << "a row past the count was written";
  const auto m = ref::appearanceMean(vectors, kDims, kPhotos);
  expectRows(mean.download<float>(kDims), m, 1e-5, "mean");
  const std::vector<float> mf(m.begin(), m.end());
  expectRows(meanBias.download<float>(kWidth), ref::appearanceBias(mf, weights, kDims, kWidth, 0, 1), 1e-5, "mean bias");
}

// The per-photo sums g of dL/d(colour pre-activation) over the rows of the photo's rays, cut to the
// device's ray count, over a batch in runs of one photo each, and from them the gradients of the
// vectors (W_a g) and of W_a (sum over photos of a g). Each entry of g sums up to a few dozen floats
// in a fixed order (a lane's rows in turn, then a tree over the lanes): below n * 2^-24 * sum|terms|
// with n under 64 + 3, so the tolerance is 1e-5 * sum|terms| (the reference's sums of magnitudes,
// entry by entry, through the same products for the two gradients), which any missing or doubled
// row (at least one whole term) exceeds. Two runs agree bit for bit.
TEST_F(Appearance, GradientSumsEachPhotosRowsDeterministically) {
  // A few dims (12: a vec4 count that is not a power of two) and widths (the widest the kernel's
  // shared sums hold: 64); more rays than photos (each photo a run of 2 or 3), and fewer (runs of
  // one ray: 20 photos have none, and a zero gradient).
  struct Case {
    uint32_t dims, width;
  };
  for (const Case k : {Case{8, 32}, Case{12, 16}, Case{64, 64}})
    for (const uint32_t rays : {kRays, 50u}) {
      SCOPED_TRACE(testing::Message() << k.dims << " dims, width " << k.width << ", " << rays << " rays");
      nerf::AppearanceEmbedding emb(ctx(), k.dims, k.width);
      const Batch b = randomBatch(4, rays);
      const uint32_t trained = rays * 3 / 4;  // the device's ray count: the rays past it add nothing
      const uint32_t rows = b.rowOffsets.back();
      const auto dColour = uniform(size_t(rows) * k.width, 5);
      const auto vectors = uniform(size_t(kPhotos) * k.dims, 6), weights = uniform(size_t(k.dims) * k.width, 7);
      auto ids = gpu::Buffer::of(ctx(), b.pixelIds), offsets = gpu::Buffer::of(ctx(), b.rowOffsets);
      auto dBuf = gpu::Buffer::of(ctx(), dColour), vBuf = gpu::Buffer::of(ctx(), vectors), wBuf = gpu::Buffer::of(ctx(), weights);
      auto count = gpu::Buffer::of(ctx(), std::vector<uint32_t>{trained, 0, 0, 0});
      auto run = [&] {
        auto dv = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kPhotos) * k.dims, kSentinel));
        auto dw = gpu::Buffer::of(ctx(), std::vector<float>(size_t(k.dims) * k.width, kSentinel));
        auto sums = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kPhotos) * k.width, kSentinel));
        test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
          emb.recordGradient(rec, {rays, ids, offsets, dBuf, gpu::BufferRange(count, 0, 4)}, kPhotos, {vBuf, wBuf},
                             {dv, dw, sums});
        });
        return std::array<std::vector<float>, 3>{sums.download<float>(size_t(kPhotos) * k.width),
                                                 dv.download<float>(size_t(kPhotos) * k.dims),
                                                 dw.download<float>(size_t(k.dims) * k.width)};
      };
      const auto got = run(), again = run();
      const auto want = ref::appearanceGradient(dColour, k.width, b.rayPhoto, b.rowOffsets, trained, kPhotos, vectors,
                                                weights, k.dims);
      auto absOf = [](const std::vector<float>& v) {
        std::vector<float> a(v.size());
        for (size_t i = 0; i < v.size(); ++i) a[i] = std::fabs(v[i]);
        return a;
      };
      const auto scale = ref::appearanceGradient(absOf(dColour), k.width, b.rayPhoto, b.rowOffsets, trained, kPhotos,
                                                 absOf(vectors), absOf(weights), k.dims);
      const std::vector<double>* wants[] = {&want.photoSums, &want.vectors, &want.weights};
      const std::vector<double>* scales[] = {&scale.photoSums, &scale.vectors, &scale.weights};
      const char* names[] = {"photo sums", "vector gradients", "weight gradients"};
      for (int part = 0; part < 3; ++part) {
        int nonzero = 0;
        for (size_t i = 0; i < wants[part]->size(); ++i) {
          EXPECT_TRUE(test::near(got[part][i], (*wants[part])[i], 0.0, 1e-5 * (*scales[part])[i] + 1e-30))
              << names[part] << " [" << i << "]";
          nonzero += (*wants[part])[i] != 0.0;
        }
        EXPECT_GT(nonzero, int(wants[part]->size()) * int(trained) / int(2 * std::max(rays, kPhotos))) << names[part];
        ASSERT_EQ(std::memcmp(got[part].data(), again[part].data(), got[part].size() * 4), 0)
            << names[part] << " differ between runs";
      }
    }
}

// The reference's gradients (from dL/d(colour pre-activation), ref::nerfBackward's dColour) against
// central differences of the loss sum over rows of dOut . out of the network whose direction input
// is [dir | the row's photo's vector] and whose colour layer has W_a as those columns' rows, in
// double: every vector entry and every entry of W_a. Differences with a step of 1e-6 on a smooth
// function (ReLU kinks aside: a row whose pre-activation is within the step of 0 would be off, which
// these random inputs do not hit) are good to ~1e-8; 1e-6 absolute + 1e-5 relative.
TEST(AppearanceReference, GradientsMatchFiniteDifferences) {
  constexpr uint32_t kD = 4, kPh = 3, kR = 6, kDir = 4, kPos = 8;
  const ref::NerfShape s = ref::NerfShape::make(1, 16, 0, kPos, kDir + kD, DensityActivation::Softplus, 8);
  const uint32_t W2 = 8;
  std::vector<double> p(s.total);
  const auto initial = ref::initialParameters(s.layers, s.total, 3);
  for (size_t i = 0; i < p.size(); ++i) p[i] = initial[i];
  const ref::DenseShape& colour = s.colour();
  auto weightIndex = [&](uint32_t k, uint32_t n) { return colour.offset + size_t(colour.rowB(kDir + k)) * colour.n4() + n; };
  std::vector<float> vectors = uniform(kPh * kD, 8), weights(kD * W2);
  for (uint32_t k = 0; k < kD; ++k)
    for (uint32_t n = 0; n < W2; ++n) weights[k * W2 + n] = float(p[weightIndex(k, n)]);
  const auto pos = uniform(kR * kPos, 9), dir = uniform(kR * kDir, 10), dOut = uniform(kR * 4, 11);
  // Rays = rows here: row r is ray r, of photo r % kPh.
  std::vector<uint32_t> rayPhoto(kR), rowOffsets(kR + 1);
  for (uint32_t r = 0; r < kR; ++r) rayPhoto[r] = r % kPh, rowOffsets[r + 1] = r + 1;

  auto rowInput = [&](uint32_t r, const std::vector<double>& v, std::vector<double>& x, std::vector<double>& d) {
    for (uint32_t k = 0; k < kPos; ++k) x[k] = pos[r * kPos + k];
    for (uint32_t k = 0; k < kDir; ++k) d[k] = dir[r * kDir + k];
    for (uint32_t k = 0; k < kD; ++k) d[kDir + k] = v[rayPhoto[r] * kD + k];
  };
  auto loss = [&](const std::vector<double>& params, const std::vector<double>& v) {
    double l = 0;
    std::vector<double> x(kPos), d(kDir + kD);
    for (uint32_t r = 0; r < kR; ++r) {
      rowInput(r, v, x, d);
      const auto fw = ref::nerfForward<double>(s, params, x.data(), d.data());
      for (int k = 0; k < 4; ++k) l += dOut[r * 4 + k] * fw.out[k];
    }
    return l;
  };
  const std::vector<double> v(vectors.begin(), vectors.end());
  std::vector<double> dColour(kR * W2), g(s.total), x(kPos), d(kDir + kD);
  for (uint32_t r = 0; r < kR; ++r) {
    rowInput(r, v, x, d);
    const auto fw = ref::nerfForward<double>(s, p, x.data(), d.data());
    const std::array<double, 4> dO{dOut[r * 4], dOut[r * 4 + 1], dOut[r * 4 + 2], dOut[r * 4 + 3]};
    ref::nerfBackward(s, p, x.data(), d.data(), fw, dO, g, (double*)nullptr, (double*)nullptr, &dColour[r * W2]);
  }
  const auto got = ref::appearanceGradient(dColour, W2, rayPhoto, rowOffsets, kR, kPh, vectors, weights, kD);
  constexpr double h = 1e-6;
  for (uint32_t i = 0; i < kPh * kD; ++i) {
    auto up = v, down = v;
    up[i] += h, down[i] -= h;
    const double fd = (loss(p, up) - loss(p, down)) / (2 * h);
    EXPECT_NEAR(got.vectors[i], fd, 1e-6 + 1e-5 * std::fabs(fd)) << "vector entry " << i;
  }
  int nonzero = 0;
  for (uint32_t k = 0; k < kD; ++k)
    for (uint32_t n = 0; n < W2; ++n) {
      auto up = p, down = p;
      up[weightIndex(k, n)] += h, down[weightIndex(k, n)] -= h;
      const double fd = (loss(up, v) - loss(down, v)) / (2 * h);
      EXPECT_NEAR(got.weights[k * W2 + n], fd, 1e-6 + 1e-5 * std::fabs(fd)) << "W_a [" << k << "][" << n << "]";
      nonzero += fd != 0.0;
    }
  EXPECT_GT(nonzero, int(kD * W2) / 2);  // the test must see gradients
}

TEST_F(Appearance, DimsAndWidthsThatCannotWorkAreErrors) {
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), 0, kWidth), Error);
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), 6, kWidth), Error);
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), 68, kWidth), Error);
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), kDims, 0), Error);
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), kDims, 30), Error);
  EXPECT_THROW(nerf::AppearanceEmbedding(ctx(), kDims, 68), Error);
}
