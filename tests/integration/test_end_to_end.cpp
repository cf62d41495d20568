// End to end on the shipped sample scene: train the vanilla recipe (small sizes) for a fixed number
// of steps, render held-out views, and require a PSNR that neither a broken renderer nor the best
// constant colour can reach.
#include <cmath>

#include "support/gpu_test.h"
#include "support/held_out.h"
#include "vknerf/trainer.h"

using namespace vknerf;

namespace {

class EndToEnd : public test::GpuTest {};

}  // namespace

TEST_F(EndToEnd, TrainsSampleSceneAboveConstantBaseline) {
  const std::string scene = std::string(VKNERF_SOURCE_DIR) + "/assets/tabletop";
  DatasetOptions opt;
  opt.downscale = 2;  // 50x50: the test budget is minutes on 2 cores
  Dataset train = Dataset::load(scene, opt);
  opt.split = "test";
  Dataset test = Dataset::load(scene, opt);
  ASSERT_EQ(train.images.size(), 100u);
  ASSERT_EQ(test.images.size(), 20u);

  TrainConfig cfg = TrainConfig::vanilla(test::context());
  VanillaModel& m = cfg.vanillaModel();
  m.width = 32;
  m.depth = 3;
  m.skipLayer = 2;
  // 8 + 16 samples a ray: on 50x50 views of this box the held-out PSNR after 80 steps is that of
  // 16 + 32 within 0.1 dB (the CLI, seeds 1 and 2: 16.64/16.11 against 16.68/16.19 dB over the
  // first 5 test views) at half the time.
  m.coarseSamples = 8;
  m.fineSamples = 16;
  Trainer trainer(test::sharedContext(), train, cfg);
  for (int i = 0; i < 80; ++i) trainer.step();

  // The best constant colour for these views (their mean) is the baseline a model that learned
  // nothing about geometry would approach (~14 dB on this scene; all-white scores ~13 dB).
  const auto score = test::scoreHeldOut(trainer.model(), test, 5);
  const double psnr = score.psnr, baseline = score.constantPsnr, ssim = score.ssim;
  std::printf("held-out PSNR %.2f dB (best constant %.2f dB), SSIM %.3f after %u steps\n", psnr, baseline, ssim,
              trainer.steps());
  // Measured: 18.24 dB after 80 steps (18.33 at 16 + 32 samples a ray). 3 dB over the constant is a quarter of the squared error
  // a constant leaves: only a model that placed the objects in 3-D gets there.
  EXPECT_GT(psnr, baseline + 3.0);
  EXPECT_GT(psnr, 16.5);
}
