// The rendering kernels chained on an analytic field, against the double CPU reference.
#include "support/gpu_test.h"
#include "kernels/selfcheck.h"

using namespace vknerf;

class SelfCheck : public test::GpuTest {};

TEST_F(SelfCheck, AnalyticSceneMatchesReference) {
  auto r = nerf::selfCheck(ctx(), 32, 32, 32);
  // Float t carries a few ulps of error (~1e-6 absolute at t ~ 3). Through the density ramp
  // (slope 800 per unit: 40 over a 0.05 shell) a shell sample's sigma moves by ~1e-3, and with
  // deltas ~0.03 its weight by ~3e-5; over the few shell samples of a ray, colour and opacity
  // stay within 2e-4. Depth sums w * t with t ~ 3, so 10x that. (Measured: 6e-6, 1e-5, 3e-5.)
  EXPECT_LT(r.maxColorError, 2e-4);
  EXPECT_LT(r.maxOpacityError, 2e-4);
  EXPECT_LT(r.maxDepthError, 2e-3);
  // The scene is visible: some pixels are opaque, some see the white background.
  int opaque = 0, empty = 0;
  for (size_t p = 0; p < r.rgb.size() / 3; ++p) {
    bool white = r.rgb[3 * p] > 0.999f && r.rgb[3 * p + 1] > 0.999f && r.rgb[3 * p + 2] > 0.999f;
    empty += white;
    opaque += !white;
  }
  EXPECT_GT(opaque, 100);
  EXPECT_GT(empty, 100);
}
