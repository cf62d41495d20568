// random_background.comp and loss_photometric.comp against the CPU reference (tests/reference/loss/photometric_loss.h).
#include <cmath>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/random_values.h"
#include "support/submit_once.h"
#include "nerf/loss/background_colors.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/loss/pixel_bindings.h"
#include "nerf/rays/rays.h"
#include "reference/loss/photometric_loss.h"

using namespace vknerf;

namespace {

using Vec4 = std::array<double, 4>;
using Vec3 = std::array<double, 3>;

uint32_t rgba8(uint32_t r, uint32_t g, uint32_t b, uint32_t a) { return r | g << 8 | b << 16 | a << 24; }

// A small training set: cameras of different sizes, random RGBA8 pixels whose alphas are 0, 255 or
// anything in between, random (camera, pixel) ids per ray.
struct Scene {
  std::vector<nerf::CameraGpu> cameras;
  std::vector<uint32_t> pixels;
  std::vector<uint32_t> ids;  // 2 per ray
};

Scene makeScene(uint32_t numRays, uint32_t seed) {
  std::vector<Camera> cams(3);
  const uint32_t sizes[3][2] = {{17, 9}, {5, 31}, {12, 12}};
  for (int c = 0; c < 3; ++c) {
    cams[c].width = sizes[c][0];
    cams[c].height = sizes[c][1];
  }
  Scene s;
  s.cameras = nerf::packCameras(cams);
  std::mt19937 gen(seed);
  uint32_t total = s.cameras.back().size[2] + 12 * 12;
  for (uint32_t i = 0; i < total; ++i) {
    uint32_t a = i % 3 == 0 ? 0 : i % 3 == 1 ? 255 : gen() & 0xff;
    s.pixels.push_back(rgba8(gen() & 0xff, gen() & 0xff, gen() & 0xff, a));
  }
  for (uint32_t r = 0; r < numRays; ++r) {
    uint32_t c = gen() % 3;
    s.ids.push_back(c);
    s.ids.push_back(gen() % (s.cameras[c].size[0] * s.cameras[c].size[1]));
  }
  return s;
}

uint32_t pixelOf(const Scene& s, uint32_t ray) { return s.pixels[s.cameras[s.ids[2 * ray]].size[2] + s.ids[2 * ray + 1]]; }

struct LossRun {
  std::vector<float> background, dPred, partials;
  nerf::LossStats stats;
};

// rayLimit: the rays to count as a uint on the device (the training batch's whole rays), or none.
LossRun runLoss(Context& ctx, const Scene& s, const std::vector<float>& pred, uint32_t numRays, float gradScale,
                uint32_t bgSeed, const uint32_t* rayLimit = nullptr) {
  nerf::BackgroundColors bg(ctx);
  nerf::PhotometricLoss loss(ctx);
  auto predB = gpu::Buffer::of(ctx, pred), idB = gpu::Buffer::of(ctx, s.ids), pixB = gpu::Buffer::of(ctx, s.pixels),
       camB = gpu::Buffer::of(ctx, s.cameras);
  gpu::Buffer bgB(ctx, 16 * numRays), partB(ctx, 4 * loss.partialCount(numRays));
  auto dB = gpu::Buffer::of(ctx, std::vector<float>(4 * size_t(numRays), -777.0f));
  auto limitB = gpu::Buffer::of(ctx, std::vector<uint32_t>{rayLimit ? *rayLimit : 0u, 0, 0, 0});
  nerf::LossRays rays{numRays, predB, idB, bgB};
  if (rayLimit) rays.rayLimit = gpu::BufferRange(limitB, 0, 4);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    bg.recordRandom(rec, bgB, numRays, bgSeed);
    loss.record(rec, rays, pixB, camB, {dB, partB, gradScale});
  });
  return {bgB.download<float>(), dB.download<float>(), partB.download<float>(), loss.read(partB, numRays)};
}

class Loss : public test::GpuTest {};

}  // namespace

TEST(LossReference, GradientMatchesCentralDifferences) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(0, 1);
  const size_t n = 9;
  std::vector<Vec4> pred(n);
  std::vector<Vec3> target(n);
  for (size_t r = 0; r < n; ++r) {
    for (auto& x : pred[r]) x = u(gen);
    for (auto& x : target[r]) x = u(gen);
  }
  const double scale = 0.7, h = 1e-5;
  std::vector<Vec4> grad;
  ref::photometricLoss<double>(pred, target, scale, &grad);
  for (size_t r = 0; r < n; ++r) {
    for (int c = 0; c < 4; ++c) {
      auto plus = pred, minus = pred;
      plus[r][c] += h;
      minus[r][c] -= h;
      double fd = scale * (ref::photometricLoss<double>(plus, target) - ref::photometricLoss<double>(minus, target)) / (2 * h);
      // The loss is quadratic, so central differences are exact up to rounding: ~1e-16 / h.
      EXPECT_NEAR(grad[r][c], fd, 1e-9) << r << "," << c;
    }
    EXPECT_EQ(grad[r][3], 0.0);  // opacity takes no part in the loss
  }
}

TEST(LossReference, BlendingAtAlphaZeroAndOne) {
  Vec3 bg{0.25, 0.5, 0.75};
  auto clear = ref::blendTarget<double>(rgba8(200, 10, 99, 0), bg);
  auto opaque = ref::blendTarget<double>(rgba8(200, 10, 99, 255), bg);
  auto half = ref::blendTarget<double>(rgba8(255, 0, 51, 51), bg);  // a = 0.2
  for (int c = 0; c < 3; ++c) EXPECT_EQ(clear[c], bg[c]);
  EXPECT_DOUBLE_EQ(opaque[0], 200 / 255.0);
  EXPECT_DOUBLE_EQ(opaque[1], 10 / 255.0);
  EXPECT_DOUBLE_EQ(opaque[2], 99 / 255.0);
  EXPECT_NEAR(half[0], 0.2 + 0.8 * 0.25, 1e-15);
  EXPECT_NEAR(half[1], 0.8 * 0.5, 1e-15);
  EXPECT_NEAR(half[2], 0.2 * 0.2 + 0.8 * 0.75, 1e-15);
  EXPECT_NEAR(ref::psnrFromMse(0.01), 20.0, 1e-12);
  EXPECT_EQ(ref::psnrFromMse(0.0), 100.0);  // finite for a perfect fit
}

TEST_F(Loss, RandomBackgroundsMatchCounterRng) {
  const uint32_t n = 100, seed = 77;  // not a multiple of the 64-wide workgroup
  gpu::Buffer out = gpu::Buffer::of(ctx(), std::vector<float>(4 * (n + 4), -7.0f));
  nerf::BackgroundColors bg(ctx());
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    bg.recordRandom(rec, out, n, seed);
    bg.recordRandom(rec, out, 0, seed);  // empty: records nothing
  });
  auto v = out.download<float>();
  double mean = 0;
  for (uint32_t i = 0; i < n; ++i) {
    auto want = ref::randomBackground(seed, i);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(v[4 * i + c], want[c]);  // integer hash: bit for bit
    EXPECT_EQ(v[4 * i + 3], 1.0f);
    mean += v[4 * i] + v[4 * i + 1] + v[4 * i + 2];
    EXPECT_NE(v[4 * i], v[4 * i + 1]);  // independent streams per channel
  }
  EXPECT_NEAR(mean / (3 * n), 0.5, 0.06);  // 300 uniforms: standard error 0.017
  for (uint32_t i = 4 * n; i < v.size(); ++i) EXPECT_EQ(v[i], -7.0f);  // nothing past the batch

  test::submitOnce(ctx(), [&](gpu::Recorder& rec) { bg.recordConstant(rec, out, n, {0.1f, 0.2f, 0.3f}); });
  v = out.download<float>();
  for (uint32_t i = 0; i < n; ++i) {
    EXPECT_EQ(v[4 * i], 0.1f);
    EXPECT_EQ(v[4 * i + 1], 0.2f);
    EXPECT_EQ(v[4 * i + 2], 0.3f);
  }
}

TEST_F(Loss, MatchesReferenceWithRandomBackgrounds) {
  const uint32_t n = 1000;  // 8 partials, the last one partly filled
  const float scale = 0.5f;
  Scene s = makeScene(n, 5);
  const std::vector<float> pred = test::uniformFloats(4 * n, 6, 0, 1);
  LossRun run = runLoss(ctx(), s, pred, n, scale, 42);

  std::vector<Vec4> p(n);
  std::vector<Vec3> target(n);
  for (uint32_t r = 0; r < n; ++r) {
    auto bg = ref::randomBackground(42, r);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(run.background[4 * r + c], bg[c]);
    target[r] = ref::blendTarget<double>(pixelOf(s, r), {bg[0], bg[1], bg[2]});
    for (int c = 0; c < 4; ++c) p[r][c] = pred[4 * r + c];
  }
  std::vector<Vec4> grad;
  double loss = ref::photometricLoss<double>(p, target, double(scale), &grad);

  // Float error of one residual e = pred - target: byte / 255 and the blend are a few roundings of
  // values <= 1, so |de| <= 4 ulp(1) = 5e-7. The gradient is e times 2 scale / (3R) (2 more roundings).
  const double eAbs = 5e-7, gradFactor = 2.0 * scale / (3.0 * n);
  for (uint32_t r = 0; r < n; ++r) {
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(test::near(run.dPred[4 * r + c], grad[r][c], 4e-7, eAbs * gradFactor)) << r << "," << c;
    ASSERT_EQ(run.dPred[4 * r + 3], 0.0f);
  }
  // Each partial sums 128 squared residuals: d(e^2) <= 2 |e| de per channel, plus the float tree
  // sum's relative error of at most log2(128) + 1 roundings of the (nonnegative) total.
  ASSERT_EQ(run.partials.size(), 8u);
  double total = 0;
  for (uint32_t g = 0; g < 8; ++g) {
    double sum = 0, bound = 0;
    for (uint32_t r = g * 128; r < std::min(n, (g + 1) * 128); ++r)
      for (int c = 0; c < 3; ++c) {
        double e = p[r][c] - target[r][c];
        sum += e * e;
        bound += 2 * std::fabs(e) * eAbs + 2 * eAbs * eAbs;
      }
    EXPECT_TRUE(test::near(run.partials[g], sum, 8 * 6e-8, bound)) << "partial " << g;
    total += sum;
  }
  EXPECT_NEAR(total / (3 * n), loss, 1e-12);
  EXPECT_TRUE(test::near(run.stats.mse, loss, 1e-6, 1e-9));
  EXPECT_TRUE(test::near(run.stats.psnr, -10 * std::log10(loss), 1e-6, 1e-6));
}

TEST_F(Loss, TransparentAndOpaqueTargets) {
  // Alpha 0: the target is the background exactly, whatever the stored colour; predicting the
  // background gives a zero residual. Alpha 255: the target is the pixel colour, whatever the background.
  const uint32_t n = 200;
  Scene s = makeScene(n, 9);
  std::vector<float> pred(4 * n);
  std::vector<int> kind(n);
  for (uint32_t r = 0; r < n; ++r) {
    uint32_t px = pixelOf(s, r);
    uint32_t a = px >> 24;
    kind[r] = a == 0 ? 0 : a == 255 ? 1 : 2;
    auto bg = ref::randomBackground(3, r);
    for (int c = 0; c < 3; ++c) pred[4 * r + c] = kind[r] == 0 ? bg[c] : float(((px >> (8 * c)) & 0xff) / 255.0);
    pred[4 * r + 3] = 0.5f;
  }
  LossRun run = runLoss(ctx(), s, pred, n, 1.0f, 3);
  int seen[3] = {0, 0, 0};
  for (uint32_t r = 0; r < n; ++r) {
    seen[kind[r]]++;
    for (int c = 0; c < 3; ++c) {
      float g = run.dPred[4 * r + c];
      if (kind[r] == 0) EXPECT_EQ(g, 0.0f) << r;
      // byte / 255 on the device vs in double: a few ulp of a value <= 1, scaled by 2 / (3R).
      if (kind[r] == 1) EXPECT_LE(std::fabs(g), 5e-7 * 2.0 / (3 * n)) << r;
    }
  }
  EXPECT_GT(seen[0], 20);
  EXPECT_GT(seen[1], 20);
  EXPECT_GT(seen[2], 20);  // the remaining rays have a real residual, so the loss is not trivially 0
  EXPECT_GT(run.stats.mse, 1e-4);
}

TEST_F(Loss, SummaryAndEmptyBatch) {
  nerf::PhotometricLoss loss(ctx());
  EXPECT_EQ(loss.partialCount(0), 0u);
  EXPECT_EQ(loss.partialCount(128), 1u);
  EXPECT_EQ(loss.partialCount(129), 2u);
  std::vector<float> partials = {1.5f, 1.5f};  // 3 / (3 * 100) = 0.01
  auto st = nerf::PhotometricLoss::summarize(partials, 100);
  EXPECT_NEAR(st.mse, 0.01, 1e-12);
  EXPECT_NEAR(st.psnr, 20.0, 1e-9);
  // numRays 0 records nothing: buffers stay as they were.
  Scene s = makeScene(1, 1);
  auto pred = gpu::Buffer::of(ctx(), std::vector<float>(4, 0.5f)), ids = gpu::Buffer::of(ctx(), s.ids),
       pix = gpu::Buffer::of(ctx(), s.pixels), cams = gpu::Buffer::of(ctx(), s.cameras),
       bg = gpu::Buffer::of(ctx(), std::vector<float>(4, 0.0f)), d = gpu::Buffer::of(ctx(), std::vector<float>(4, 9.0f)),
       part = gpu::Buffer::of(ctx(), std::vector<float>(1, 9.0f));
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    loss.record(rec, {0, pred, ids, bg}, pix, cams, {d, part});
  });
  EXPECT_EQ(d.download<float>()[0], 9.0f);
  EXPECT_EQ(part.download<float>()[0], 9.0f);
}

// Training pixels spread over more bindings than one dispatch sees (PhotometricLoss::kPixelBindings):
// every ray reads its own image wherever that lies, and the passes' sums add up to the loss.
TEST_F(Loss, PixelsOverManyBindingsMatchReference) {
  const uint32_t numCameras = 13, n = 700;
  std::mt19937 gen(21);
  std::vector<Camera> cams(numCameras);
  std::vector<uint64_t> counts;
  for (auto& c : cams) {
    c.width = 7 + gen() % 5;
    c.height = 5 + gen() % 4;
    counts.push_back(uint64_t(c.width) * c.height);
  }
  // 35 to 88 pixels per image, 96 per binding: one or two images each, 9 or more bindings, so two
  // dispatches.
  auto layout = nerf::planPixelBindings(counts, 96 * 4);
  ASSERT_GT(layout.bindingPixels.size(), nerf::PhotometricLoss::kPixelBindings);
  nerf::TrainingPixels pixels(ctx(), layout);
  std::vector<std::vector<uint32_t>> images(numCameras);
  for (uint32_t c = 0; c < numCameras; ++c) {
    for (uint64_t i = 0; i < counts[c]; ++i) images[c].push_back(rgba8(gen() & 0xff, gen() & 0xff, gen() & 0xff, gen() & 0xff));
    pixels.upload(c, reinterpret_cast<const uint8_t*>(images[c].data()));
  }
  std::vector<uint32_t> ids;
  std::vector<float> pred(4 * n);
  std::uniform_real_distribution<float> u(0, 1);
  for (uint32_t r = 0; r < n; ++r) {
    const uint32_t c = gen() % numCameras;
    ids.push_back(c);
    ids.push_back(uint32_t(gen() % counts[c]));
    for (int k = 0; k < 4; ++k) pred[4 * r + k] = u(gen);
  }
  nerf::BackgroundColors bg(ctx());
  nerf::PhotometricLoss loss(ctx());
  auto predB = gpu::Buffer::of(ctx(), pred), idB = gpu::Buffer::of(ctx(), ids),
       camB = gpu::Buffer::of(ctx(), nerf::packCameras(cams, layout.images));
  gpu::Buffer bgB(ctx(), 16 * n), dB(ctx(), 16 * n), partB(ctx(), 4 * loss.partialCount(n));
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    bg.recordRandom(rec, bgB, n, 8);
    loss.record(rec, {n, predB, idB, bgB}, {pixels.bindings(), camB}, {dB, partB});
  });
  std::vector<Vec4> p(n);
  std::vector<Vec3> target(n);
  for (uint32_t r = 0; r < n; ++r) {
    auto b = ref::randomBackground(8, r);
    target[r] = ref::blendTarget<double>(images[ids[2 * r]][ids[2 * r + 1]], {b[0], b[1], b[2]});
    for (int c = 0; c < 4; ++c) p[r][c] = pred[4 * r + c];
  }
  std::vector<Vec4> grad;
  const double want = ref::photometricLoss<double>(p, target, 1.0, &grad);
  // Tolerances as in MatchesReferenceWithRandomBackgrounds.
  const double eAbs = 5e-7, gradFactor = 2.0 / (3.0 * n);
  auto d = dB.download<float>();
  for (uint32_t r = 0; r < n; ++r)
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(test::near(d[4 * r + c], grad[r][c], 4e-7, eAbs * gradFactor)) << r << "," << c;
  EXPECT_TRUE(test::near(loss.read(partB, n).mse, want, 1e-6, 1e-9));
}

// A batch whose ray count only the device knows (the training batch cut to whole rays): the rays
// below the device count give exactly what a batch of that many rays gives (itself checked against
// the reference above), the rest a zero gradient and nothing in the partials.
TEST_F(Loss, DeviceRayCountEqualsTheBatchOfThatMany) {
  const uint32_t n = 1000;
  Scene s = makeScene(n, 7);
  const std::vector<float> pred = test::uniformFloats(4 * n, 8, 0, 1);
  for (uint32_t k : {1u, 127u, 128u, 640u, 999u, n}) {
    SCOPED_TRACE(testing::Message() << k << " rays counted");
    const LossRun want = runLoss(ctx(), s, pred, k, 0.5f, 42);
    const LossRun got = runLoss(ctx(), s, pred, n, 0.5f, 42, &k);
    for (uint32_t i = 0; i < 4 * n; ++i)
      ASSERT_EQ(got.dPred[i], i < 4 * k ? want.dPred[i] : 0.0f) << "dPred float " << i;
    for (uint32_t g = 0; g < got.partials.size(); ++g)
      ASSERT_EQ(got.partials[g], g < want.partials.size() ? want.partials[g] : 0.0f) << "partial " << g;
    EXPECT_EQ(nerf::PhotometricLoss::summarize(got.partials, k).mse, want.stats.mse);
  }
}
