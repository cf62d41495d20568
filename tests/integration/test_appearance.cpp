// The fast model's per-photo appearance embedding (models/common/appearance.h) end to end: photos of
// one scene whose exposures differ train vectors that tell the dark photos from the bright ones,
// training works with it, and a loaded model renders as the trainer's does (the mean vector).
#include <cmath>
#include <numeric>

#include "io/checkpoint/checkpoint.h"
#include "support/gpu_test.h"
#include "support/sample_scene.h"
#include "support/temp_dir.h"
#include "vknerf/error.h"
#include "vknerf/trainer.h"

using namespace vknerf;

namespace {

using test::sharedContext;

class AppearanceTraining : public test::GpuTest {};

constexpr uint32_t kDims = 8;

// Photo i's exposure: 0.7 .. 1.3 across the training photos, in an order unrelated to the views'
// (every third photo in turn), so that no view's content stands in for its brightness.
double exposure(uint32_t i, uint32_t n) { return 0.7 + 0.6 * double((i * 7) % n) / double(n - 1); }

Dataset exposedScene() {
  Dataset d = test::quarterSizeSampleScene();
  const uint32_t n = uint32_t(d.images.size());
  for (uint32_t i = 0; i < n; ++i)
    for (size_t p = 0; p < d.images[i].rgba.size(); ++p)
      if (p % 4 != 3) d.images[i].rgba[p] = uint8_t(std::min(255.0, std::round(d.images[i].rgba[p] * exposure(i, n))));
  return d;
}

TrainConfig appearanceConfig() {
  TrainConfig c = TrainConfig::fast(*sharedContext());
  c.fastModel().gridResolution = 16;
  c.fastModel().samplesPerBatch = 8192;
  c.fastModel().appearanceDims = kDims;
  c.raysPerBatch = 2048;
  return c;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / a.size(), mb = std::accumulate(b.begin(), b.end(), 0.0) / b.size();
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < a.size(); ++i) ab += (a[i] - ma) * (b[i] - mb), aa += (a[i] - ma) * (a[i] - ma), bb += (b[i] - mb) * (b[i] - mb);
  return ab / std::sqrt(aa * bb + 1e-300);
}

}  // namespace

TEST_F(AppearanceTraining, VectorsLearnEachPhotosExposure) {
  const test::TempDir tmp("appearance");
  const Dataset scene = exposedScene();
  const uint32_t n = uint32_t(scene.cameras.size());
  ASSERT_GE(n, 8u);
  Trainer t(sharedContext(), scene, appearanceConfig());
  double first = 0, last = 0;
  const int steps = 150;
  for (int i = 0; i < steps; ++i) {
    const auto st = t.step(i < 10 || i >= steps - 10);
    if (st.hasLoss) ASSERT_TRUE(std::isfinite(st.loss)) << "step " << i;
    if (i < 10) first += st.loss / 10;
    if (i >= steps - 10) last += st.loss / 10;
  }
  EXPECT_LT(last, 0.7 * first) << "first " << first << " last " << last;
  const auto path = tmp.file("appearance.vknerf");
  t.save(path);
  const auto table = io::Checkpoint::load(path).get<float>("appearance.params", size_t(n) * kDims);

  // The direction in which the vectors of the brighter half of the even photos differ from the
  // darker half's; along it, the odd photos' vectors (not used to find it) must order themselves
  // by exposure. Untrained (all zero) or random vectors give no correlation.
  std::vector<double> dir(kDims, 0.0);
  for (uint32_t i = 0; i < n; i += 2)
    for (uint32_t k = 0; k < kDims; ++k) dir[k] += (exposure(i, n) > 1.0 ? 1.0 : -1.0) * table[size_t(i) * kDims + k];
  std::vector<double> along, exposures;
  for (uint32_t i = 1; i < n; i += 2) {
    double s = 0;
    for (uint32_t k = 0; k < kDims; ++k) s += dir[k] * table[size_t(i) * kDims + k];
    along.push_back(s), exposures.push_back(exposure(i, n));
  }
  EXPECT_GT(correlation(along, exposures), 0.7);

  // A loaded model has the table and renders with the mean vector, as the trainer's model does
  // (tolerance: see FastModelLearnsTheFarFieldOfOpaquePhotos, the same two pipelines).
  Model m = Model::load(sharedContext(), path);
  const Camera cam = scene.cameras[1];
  RenderedImage a = t.model().render(cam), b = m.render(cam);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_NEAR(a.rgb[i], b.rgb[i], 1e-4 + 1e-5) << i;

  // A chosen photo's vector renders that photo's exposure: brighter for the brightest than the darkest.
  uint32_t dark = 0, bright = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (exposure(i, n) < exposure(dark, n)) dark = i;
    if (exposure(i, n) > exposure(bright, n)) bright = i;
  }
  auto meanOf = [](const RenderedImage& r) { return std::accumulate(r.rgb.begin(), r.rgb.end(), 0.0) / r.rgb.size(); };
  RenderSettings asDark, asBright;
  asDark.appearancePhoto = dark, asBright.appearancePhoto = bright;
  const double darkMean = meanOf(Model::load(sharedContext(), path, asDark).render(cam));
  const double brightMean = meanOf(Model::load(sharedContext(), path, asBright).render(cam));
  EXPECT_GT(brightMean, darkMean * 1.05) << "dark " << darkMean << " bright " << brightMean;

  RenderSettings missing;
  missing.appearancePhoto = n;
  EXPECT_THROW(Model::load(sharedContext(), path, missing), Error);
}
