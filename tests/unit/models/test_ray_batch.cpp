// The training batch's backgrounds: random with TrainConfig::randomBackground, whether or not the
// photos have alpha (behind opaque photos a random colour makes every ray turn opaque inside the
// box); the constant background without it.
#include <vector>

#include "models/common/ray_batch.h"
#include "nerf/rays/rays.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"

using namespace vknerf;

namespace {

class RayBatchBackground : public test::GpuTest {
 protected:
  std::vector<float> backgrounds(bool random, bool transparentPixels) {
    Camera cam;
    cam.width = cam.height = 4;
    cam.fx = cam.fy = 4;
    cam.cx = cam.cy = 2;
    auto cameras = gpu::Buffer::of(ctx(), nerf::packCameras(std::vector<Camera>{cam}));
    gpu::Buffer images(ctx(), 4 * 4 * 4);
    const gpu::BufferRange pixels[] = {images};
    TrainConfig config;
    config.randomBackground = random;
    config.background = {0.25f, 0.5f, 0.75f};
    models::RayBatch batch(ctx(), 64);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      batch.recordTraining(rec, {pixels, &cameras, 1, transparentPixels}, 7, 64, Aabb{}, config);
    });
    return batch.background().download<float>(64 * 4);
  }
};

}  // namespace

TEST_F(RayBatchBackground, RandomWhenAskedWithOrWithoutAlpha) {
  for (bool transparent : {true, false}) {
    const auto random = backgrounds(true, transparent), constant = backgrounds(false, transparent);
    bool varies = false;
    for (int i = 0; i < 64; ++i) {
      for (int k = 0; k < 3; ++k) EXPECT_EQ(constant[4 * i + k], (std::array<float, 3>{0.25f, 0.5f, 0.75f})[k]) << i;
      varies = varies || random[4 * i] != random[0];
    }
    EXPECT_TRUE(varies) << "transparent pixels: " << transparent;
  }
}
