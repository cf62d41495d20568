// TrainConfig::vanilla, fast and named (vknerf/config.h): the configurations sized for the device
// they train on (Context::isCpu), so they stand above the Vulkan layer; the rest of TrainConfig is
// src/core/config/config.cpp.
#include <string>

#include "vknerf/config.h"
#include "vknerf/context.h"
#include "vknerf/error.h"

namespace vknerf {

TrainConfig TrainConfig::vanilla(const Context& ctx) {
  TrainConfig c;
  VanillaModel& m = c.vanillaModel();
  if (ctx.isCpu()) {
    // The paper's 8x256 network with 64+128 samples needs days on a CPU. This keeps the recipe
    // (encodings, skip, late direction, coarse + fine) at a size that converges in minutes on
    // 100x100 images: ~1/60 of the paper's FLOPs per ray.
    m.width = 64;
    m.depth = 4;
    m.skipLayer = 2;
    m.coarseSamples = 32;
    m.fineSamples = 64;
    c.raysPerBatch = 1024;
    c.learningRate = 2e-3f;
    c.learningRateFinal = 2e-4f;
    c.decaySteps = 20000;
  } else {
    c.raysPerBatch = 4096;
  }
  return c;
}

TrainConfig TrainConfig::fast(const Context& ctx) {
  TrainConfig c;
  FastModel& m = c.model.emplace<FastModel>();
  m.hashLevels = 16;
  m.hashFeatures = 2;
  m.hashBaseResolution = 16;
  // The table size and the finest resolution (through the growth factor) follow the training data:
  // 0 leaves them to the Trainer (src/models/fast/fast_capacity.h).
  m.hashLog2Size = 0;
  m.hashGrowth = 0;
  m.gridResolution = 128;
  m.marchSteps = 1024;
  m.maxSamplesPerRay = 1024;
  c.raysPerBatch = 1u << 18;  // the most rays a step may take; samplesPerBatch decides
  m.samplesPerBatch = 1u << 18;
  c.learningRate = 1e-2f;
  c.learningRateFinal = 1e-3f;
  c.decaySteps = 20000;
  c.beta1 = 0.9f;
  c.beta2 = 0.99f;
  c.epsilon = 1e-15f;
  if (ctx.isCpu()) {
    // 100x100 views resolve ~2 cm on a 2 m box: 8 levels up to 256 cells and a 64^3 occupancy grid
    // hold all the detail they show, at a fraction of the work per sample. Measured on the sample
    // scene (45 s budgets, held-out PSNR): 128 march steps per diagonal beat 256 (+1.5 dB: half the
    // samples per ray, twice the rays), 2^14 samples per step beat 2^15 and 2^16 (more, cheaper
    // steps), and a 2^15-entry table per level matched 2^17 at a third of the Adam cost (the
    // capacity rule of src/models/fast/fast_capacity.h gives the sample scene that table and 256 cells).
    // The march steps follow the pixel footprint there too (0: 128 for the sample scene, 256 for
    // photos whose pixels are 8 times finer than a step of 128, as the 800x800 object's).
    // 16 levels over the same range did not pay there either: 25.39 dB at 600 s against 25.19 and
    // 25.41 for 8, in 5,955 steps against 8,241 and 9,720 (docs/performance.md, "Sixteen hash levels").
    m.hashLevels = 8;
    // 0: half the march steps per axis, 64^3 at 128 steps, 128^3 at 256 (src/models/fast/fast_capacity.h).
    m.gridResolution = 0;
    m.marchSteps = 0;
    m.maxSamplesPerRay = 0;
    // With cascades (unbounded scenes), instant-ngp's 1/256 marches ~300 points per ray through a
    // fresh grid, past the 128-sample cap, so rays stop short of the far field (docs/unbounded.md:
    // 1/256 lost 1.5 dB to the single grid at 60 s). On the distorted capture at 120 s, 1/64 beat
    // 1/32 by 0.6-0.85 dB in two back-to-back pairs, and 1/32 beat 1/16 and 1/128 (finer steps
    // sharpen the ground seen at grazing angles, until the samples per ray cost too many rays).
    m.coneAngle = 1.0f / 64.0f;
    // mip-NeRF 360's distortion loss (tests/reference/render/distortion_loss.h) is off: at 0.01 it
    // collapsed a hand-held capture close to a wall (an opaque layer on every lens); at 0.001, at
    // equal steps on flower, cup and fruit, it moved held-out PSNR by at most 0.24 dB either way but
    // left 13% of the cup's held-out pixels under 0.5 opacity (the table painted by the far field,
    // black in depth) against 2% without (docs/real_captures.md, "The distortion loss, off").
    m.distortionLoss = 0;
    c.raysPerBatch = 1u << 14;
    // 2^14 samples a step, whatever the march steps (0: src/models/fast/fast_capacity.h).
    m.samplesPerBatch = 0;
    c.decaySteps = 4000;
    m.gridUpdateInterval = 16;
    m.gridWarmupSteps = 64;
  }
  return c;
}

TrainConfig TrainConfig::named(const std::string& name, const Context& ctx) {
  if (name == "vanilla") return vanilla(ctx);
  if (name == "fast") return fast(ctx);
  throw Error("unknown model configuration \"" + name + "\" (expected vanilla or fast)");
}

}  // namespace vknerf
