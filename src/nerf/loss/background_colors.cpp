#include "nerf/loss/background_colors.h"
#include "loss/random_background_shared.h"

namespace vknerf::nerf {
namespace {
using glsl::BackgroundPush;
constexpr uint32_t kBackgroundLocal = 64;

void dispatchBackground(gpu::Recorder& rec, gpu::Kernel& k, const gpu::BufferRange& background,
                        const BackgroundPush& p) {
  rec.dispatch(k, {background}, p, gpu::groupsFor(p.count, kBackgroundLocal), 1, 1, "random_background");
}
}  // namespace

BackgroundColors::BackgroundColors(Context& ctx)
    : kernel_(ctx, {gpu::shaders::random_background, {gpu::Binding::Storage}, sizeof(BackgroundPush), {}}) {}

void BackgroundColors::recordRandom(gpu::Recorder& rec, const gpu::BufferRange& background, uint32_t numRays,
                                    uint32_t seed) {
  dispatchBackground(rec, kernel_, background, {{0, 0, 0, 1}, 1, seed, numRays});
}

void BackgroundColors::recordConstant(gpu::Recorder& rec, const gpu::BufferRange& background, uint32_t numRays,
                                      const std::array<float, 3>& rgb) {
  dispatchBackground(rec, kernel_, background, {{rgb[0], rgb[1], rgb[2], 1}, 0, 0, numRays});
}

}  // namespace vknerf::nerf
