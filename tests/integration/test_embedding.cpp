// The embedding API: Model::recordRender into command buffers, buffers and images that the test
// creates itself, as an application would, on vknerf's context and on an adopted device.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "support/app_device.h"
#include "support/app_vulkan.h"
#include "support/gpu_test.h"
#include "support/temp_dir.h"
#include "vknerf/error.h"
#include "vknerf/trainer.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

// ------------------------------------------------------------------ a small model

// The vanilla recipe at a tiny size. 128 rays per block: the 20x14 views below take three blocks,
// the last one partial, so block offsets are exercised.
TrainConfig tinyConfig(const Context& ctx) {
  TrainConfig c = TrainConfig::vanilla(ctx);
  VanillaModel& m = c.vanillaModel();
  m.width = 16;
  m.depth = 2;
  m.skipLayer = 1;
  m.posLevels = 4;
  m.dirLevels = 2;
  m.coarseSamples = 8;
  m.fineSamples = 8;
  c.raysPerBatch = 128;
  c.learningRate = 1e-2f;
  c.background = {0.25f, 0.5f, 0.75f};  // not white: the background must reach the target
  return c;
}

// Camera at `eye` looking at the origin, +Y up.
Camera lookAtOrigin(float ex, float ey, float ez, uint32_t w, uint32_t h) {
  return pinholeFromFocal(w, h, 1.2f * float(w), lookAt({ex, ey, ez}, {0, 0, 0}, {0, 1, 0}));
}

// Four 16x16 views of a coloured pattern around the unit box: enough for a few training steps to
// give the field structure (depth, opacity and colour that vary over the image).
Dataset tinyDataset() {
  Dataset d;
  const float eyes[4][3] = {{0, 0.5f, 3}, {3, 0.5f, 0}, {0, 0.5f, -3}, {-3, 0.5f, 0}};
  for (int i = 0; i < 4; ++i) {
    d.cameras.push_back(lookAtOrigin(eyes[i][0], eyes[i][1], eyes[i][2], 16, 16));
    ImageRGBA8 img{16, 16, std::vector<uint8_t>(16 * 16 * 4)};
    for (uint32_t y = 0; y < 16; ++y)
      for (uint32_t x = 0; x < 16; ++x) {
        uint8_t* p = &img.rgba[(y * 16 + x) * 4];
        const bool inside = x >= 4 && x < 12 && y >= 4 && y < 12;  // an object in the middle
        p[0] = inside ? uint8_t(40 + 20 * i) : 0;
        p[1] = inside ? uint8_t(200 - 10 * x) : 0;
        p[2] = inside ? uint8_t(60 + 10 * y) : 0;
        p[3] = inside ? 255 : 0;
      }
    d.images.push_back(std::move(img));
    d.names.push_back("view" + std::to_string(i));
  }
  d.boundsSource = "test";
  return d;
}

std::unique_ptr<Trainer> trainedTinyModel(std::shared_ptr<Context> ctx) {
  auto t = std::make_unique<Trainer>(ctx, tinyDataset(), tinyConfig(*ctx));
  for (int i = 0; i < 8; ++i) t->step();
  return t;
}

// Renders `cam` into a storage image of `format` and copies it into `readback` (tightly packed).
void renderIntoImage(const Model& model, AppDevice d, const Camera& cam, VkFormat format, const AppBuffer& readback) {
  AppImage img(d, cam.width, cam.height, format);
  AppCommands app(d);
  app.begin();
  imageLayout(app.cmd, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
              0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
  RenderTarget t;
  t.width = cam.width;
  t.height = cam.height;
  t.imageView = img.view;
  t.imageFormat = format;
  model.recordRender(app.cmd, cam, t);
  imageLayout(app.cmd, img.image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
              VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
              VK_ACCESS_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {cam.width, cam.height, 1};
  vkCmdCopyImageToBuffer(app.cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer, 1, &region);
  memoryBarrier(app.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                VK_ACCESS_HOST_READ_BIT);
  app.submitAndWait();
}

// Records one render into a fresh application buffer (at `offset`) and returns its texels.
std::vector<float> renderIntoBuffer(const Model& model, AppDevice d, const Camera& cam,
                                    RenderChannel channel = RenderChannel::Color, float depthScale = 1.0f) {
  const VkDeviceSize bytes = VkDeviceSize(cam.width) * cam.height * 16;
  AppBuffer target(d, bytes);
  AppCommands app(d);
  app.begin();
  fillBeforeRender(app.cmd, target, -7.0f);
  RenderTarget t;
  t.width = cam.width;
  t.height = cam.height;
  t.channel = channel;
  t.depthScale = depthScale;
  t.buffer = target.buffer;
  model.recordRender(app.cmd, cam, t);
  renderToHost(app.cmd);
  app.submitAndWait();
  return target.floats(0, size_t(cam.width) * cam.height * 4);
}

// The colour channel (rgb, opacity per texel) equals Model::render exactly: the same kernels run on
// the same inputs in the same blocks, and the writer copies the floats unchanged.
void expectColourEqualsRender(const std::vector<float>& texels, const RenderedImage& ref) {
  const size_t n = size_t(ref.width) * ref.height;
  ASSERT_EQ(texels.size(), n * 4);
  for (size_t p = 0; p < n; ++p) {
    for (int k = 0; k < 3; ++k) ASSERT_EQ(texels[p * 4 + k], ref.rgb[p * 3 + k]) << "pixel " << p << " channel " << k;
    ASSERT_EQ(texels[p * 4 + 3], ref.opacity[p]) << "pixel " << p << " opacity";
  }
}

// A render worth comparing: colour, opacity and depth vary over the image.
void expectStructure(const RenderedImage& img) {
  float omin = 1, omax = 0, dmax = 0;
  for (float o : img.opacity) omin = std::min(omin, o), omax = std::max(omax, o);
  for (float d : img.depth) dmax = std::max(dmax, d);
  EXPECT_GT(omax - omin, 0.05f) << "opacity is flat: the test would not see misplaced pixels";
  EXPECT_GT(dmax, 0.5f) << "no depth anywhere";
}

class EmbeddingTest : public test::GpuTest {};

}  // namespace

// ------------------------------------------------------------------ the tests

TEST_F(EmbeddingTest, RenderIntoCallerBufferEqualsModelRender) {
  auto trainer = trainedTinyModel(sharedContext());
  const Model& model = trainer->model();
  const Camera cam = lookAtOrigin(0.8f, 0.6f, 2.8f, 20, 14);
  const RenderedImage ref = model.render(cam);
  expectStructure(ref);

  // At an offset into a larger buffer: the bytes before the target keep the sentinel.
  const VkDeviceSize offset = std::max<VkDeviceSize>(ctx().properties().limits.minStorageBufferOffsetAlignment, 64);
  const size_t texels = size_t(cam.width) * cam.height;
  AppDevice d = AppDevice::of(ctx());
  AppBuffer target(d, offset + texels * 16 + 64);
  AppCommands app(d);
  app.begin();
  fillBeforeRender(app.cmd, target, -7.0f);
  RenderTarget t;
  t.width = cam.width;
  t.height = cam.height;
  t.buffer = target.buffer;
  t.offset = offset;
  model.recordRender(app.cmd, cam, t);
  renderToHost(app.cmd);
  app.submitAndWait();

  expectColourEqualsRender(target.floats(offset, texels * 4), ref);
  for (float v : target.floats(0, offset / 4)) ASSERT_EQ(v, -7.0f) << "written before the target's offset";
  for (float v : target.floats(offset + texels * 16, 16)) ASSERT_EQ(v, -7.0f) << "written past the target";

  // A loaded model (one block per view: its capacity is larger) records the same image.
  const TempDir tmp("embedding");
  const auto path = tmp.file("tiny.vknerf");
  trainer->save(path);
  Model loaded = Model::load(sharedContext(), path);
  expectColourEqualsRender(renderIntoBuffer(loaded, d, cam), ref);
}

TEST_F(EmbeddingTest, RenderIntoStorageImages) {
  auto trainer = trainedTinyModel(sharedContext());
  const Model& model = trainer->model();
  const Camera cam = lookAtOrigin(-1.0f, 1.0f, 2.6f, 20, 14);  // not square: rows and columns must not swap
  const RenderedImage ref = model.render(cam);
  expectStructure(ref);
  const size_t n = size_t(cam.width) * cam.height;
  AppDevice d = AppDevice::of(ctx());

  AppBuffer floats(d, n * 16);
  renderIntoImage(model, d, cam, VK_FORMAT_R32G32B32A32_SFLOAT, floats);
  expectColourEqualsRender(floats.floats(0, n * 4), ref);

  // UNORM: the store converts each value to 8 bits; Vulkan leaves the rounding direction to the
  // implementation, so a texel is within one step (1/255) of the reference, plus float rounding.
  AppBuffer bytes(d, n * 4);
  renderIntoImage(model, d, cam, VK_FORMAT_R8G8B8A8_UNORM, bytes);
  const auto* px = static_cast<const uint8_t*>(bytes.mapped);
  for (size_t p = 0; p < n; ++p) {
    const float want[4] = {ref.rgb[p * 3], ref.rgb[p * 3 + 1], ref.rgb[p * 3 + 2], ref.opacity[p]};
    for (int k = 0; k < 4; ++k)
      ASSERT_TRUE(test::near(px[p * 4 + k] / 255.0, std::clamp(want[k], 0.0f, 1.0f), 0, 1.0 / 255 + 1e-6))
          << "pixel " << p << " channel " << k;
  }
}

TEST_F(EmbeddingTest, DepthChannel) {
  auto trainer = trainedTinyModel(sharedContext());
  const Model& model = trainer->model();
  const Camera cam = lookAtOrigin(0.8f, 0.6f, 2.8f, 20, 14);
  const RenderedImage ref = model.render(cam);
  expectStructure(ref);
  const float scale = 0.25f;
  const auto texels = renderIntoBuffer(model, AppDevice::of(ctx()), cam, RenderChannel::Depth, scale);
  for (size_t p = 0; p < size_t(cam.width) * cam.height; ++p) {
    // Depth = sum / opacity on the device vs on the host: Vulkan allows a division 2.5 ulp off the
    // correctly rounded quotient, and the scale adds one rounding: 1e-6 relative covers both.
    for (int k = 0; k < 3; ++k)
      ASSERT_TRUE(test::near(texels[p * 4 + k], double(ref.depth[p]) * scale, 1e-6, 1e-7)) << "pixel " << p;
    ASSERT_EQ(texels[p * 4 + 3], ref.opacity[p]) << "pixel " << p;
  }
}

TEST_F(EmbeddingTest, TwoCamerasInOneCommandBuffer) {
  auto trainer = trainedTinyModel(sharedContext());
  const Model& model = trainer->model();
  const Camera a = lookAtOrigin(0.8f, 0.6f, 2.8f, 20, 14), b = lookAtOrigin(2.8f, -0.5f, -0.9f, 20, 14);
  const RenderedImage refA = model.render(a), refB = model.render(b);
  ASSERT_NE(refA.rgb, refB.rgb) << "the two views must differ for the test to mean anything";
  const size_t n = size_t(a.width) * a.height;
  AppDevice d = AppDevice::of(ctx());
  AppBuffer targetA(d, n * 16), targetB(d, n * 16);
  AppCommands app(d);
  app.begin();
  fillBeforeRender(app.cmd, targetA, -7.0f);
  fillBeforeRender(app.cmd, targetB, -7.0f);
  RenderTarget t;
  t.width = a.width;
  t.height = a.height;
  t.buffer = targetA.buffer;
  model.recordRender(app.cmd, a, t);
  t.buffer = targetB.buffer;
  model.recordRender(app.cmd, b, t);  // reuses the model's scratch and camera buffer
  renderToHost(app.cmd);
  app.submitAndWait();
  expectColourEqualsRender(targetA.floats(0, n * 4), refA);
  expectColourEqualsRender(targetB.floats(0, n * 4), refB);
}

TEST_F(EmbeddingTest, TwoContextsInOneProcessRenderTheSame) {
  auto trainer = trainedTinyModel(sharedContext());
  const TempDir tmp("embedding");
  const auto path = tmp.file("tiny.vknerf");
  trainer->save(path);
  const Camera cam = lookAtOrigin(0.8f, 0.6f, 2.8f, 20, 14);
  std::vector<float> first, second;
  {
    auto c1 = Context::create(), c2 = Context::create();
    Model m1 = Model::load(c1, path), m2 = Model::load(c2, path);
    // Interleaved: each context's model keeps its own record state.
    first = renderIntoBuffer(m1, AppDevice::of(*c1), cam);
    second = renderIntoBuffer(m2, AppDevice::of(*c2), cam);
    expectColourEqualsRender(first, m1.render(cam));
    EXPECT_EQ(c1->validationMessages(), 0u);
    EXPECT_EQ(c2->validationMessages(), 0u);
  }
  EXPECT_EQ(first, second);
}

TEST_F(EmbeddingTest, AdoptedDeviceRendersAndKeepsTheCallersObjects) {
  auto trainer = trainedTinyModel(sharedContext());
  const TempDir tmp("embedding");
  const auto path = tmp.file("tiny.vknerf");
  trainer->save(path);
  const Camera cam = lookAtOrigin(0.8f, 0.6f, 2.8f, 20, 14), cam2 = lookAtOrigin(2.8f, -0.5f, -0.9f, 20, 14);
  const size_t n = size_t(cam.width) * cam.height;
  uint32_t messages = 0, probeMessages = 0;
  {
    OwnDevice own(messages);
    ASSERT_NE(own.device, VK_NULL_HANDLE);
    const AppDevice d = own.app();
    AppBuffer target(d, n * 16), target2(d, n * 16);  // created before the context, used after it
    AppCommands app(d);
    {
      auto adopted = Context::adopt({own.instance, own.phys, own.device, own.family, own.queue, own.floatAtomics});
      Model model = Model::load(adopted, path);
      // Two renders in one command buffer, under synchronization validation: the second one's
      // commands reuse the first one's scratch and camera buffers.
      app.begin();
      fillBeforeRender(app.cmd, target, -7.0f);
      fillBeforeRender(app.cmd, target2, -7.0f);
      RenderTarget t;
      t.width = cam.width;
      t.height = cam.height;
      t.buffer = target.buffer;
      model.recordRender(app.cmd, cam, t);
      t.buffer = target2.buffer;
      model.recordRender(app.cmd, cam2, t);
      renderToHost(app.cmd);
      app.submitAndWait();
      expectColourEqualsRender(target.floats(0, n * 4), model.render(cam));
      expectColourEqualsRender(target2.floats(0, n * 4), model.render(cam2));
    }
    // vknerf is gone: the application's device, queue, pool and buffer still work.
    app.begin();
    fillBeforeRender(app.cmd, target, 3.0f);
    app.submitAndWait();
    EXPECT_EQ(target.floats(0, 1)[0], 3.0f);
    if (own.validating) {
      // Probe: a deliberate write-after-write hazard (never submitted) must be reported, so zero
      // messages means a clean run, not a layer that is absent or a counter that is not wired.
      const uint32_t before = messages;
      std::fprintf(stderr, "(the next synchronization hazard is deliberate)\n");
      app.begin();
      vkCmdFillBuffer(app.cmd, target.buffer, 0, VK_WHOLE_SIZE, 0);
      vkCmdFillBuffer(app.cmd, target.buffer, 0, VK_WHOLE_SIZE, 0);
      ASSERT_EQ(vkEndCommandBuffer(app.cmd), VK_SUCCESS);
      probeMessages = messages - before;
      EXPECT_GT(probeMessages, 0u) << "synchronization validation did not report the deliberate hazard";
    }
  }  // device, messenger and instance destroyed here; the layer reports vknerf objects left behind
  EXPECT_EQ(messages - probeMessages, 0u)
      << "the validation layer of the test's own instance reported messages (see stderr)";
}

TEST_F(EmbeddingTest, BadTargetsAreClearErrors) {
  auto trainer = trainedTinyModel(sharedContext());
  const Model& model = trainer->model();
  const Camera cam = lookAtOrigin(0.8f, 0.6f, 2.8f, 20, 14);
  AppDevice d = AppDevice::of(ctx());
  AppBuffer target(d, size_t(cam.width) * cam.height * 16);
  AppImage image(d, cam.width, cam.height, VK_FORMAT_R32G32B32A32_SFLOAT);
  AppCommands app(d);
  app.begin();

  auto message = [&](const Camera& c, const RenderTarget& t, VkCommandBuffer cmd) -> std::string {
    try {
      model.recordRender(cmd, c, t);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  RenderTarget good;
  good.width = cam.width;
  good.height = cam.height;
  good.buffer = target.buffer;
  auto expectError = [&](const RenderTarget& t, const std::string& field, const Camera& c, VkCommandBuffer cmd) {
    const std::string m = message(c, t, cmd);
    std::fprintf(stderr, "  %s\n", m.c_str());
    EXPECT_NE(m.find(field), std::string::npos) << "message '" << m << "' does not name '" << field << "'";
    EXPECT_EQ(m.find('\n'), std::string::npos) << "not one line: " << m;
  };

  RenderTarget t = good;
  t.width = cam.width + 1;
  expectError(t, "width/height", cam, app.cmd);
  t = good;
  t.imageView = image.view;
  t.imageFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
  expectError(t, "both buffer and imageView", cam, app.cmd);
  t = good;
  t.buffer = VK_NULL_HANDLE;
  expectError(t, "neither buffer nor imageView", cam, app.cmd);
  t.imageView = image.view;
  t.imageFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
  expectError(t, "imageFormat", cam, app.cmd);
  t.imageFormat = VK_FORMAT_UNDEFINED;
  expectError(t, "imageFormat", cam, app.cmd);
  t = good;
  t.channel = RenderChannel(7);
  expectError(t, "channel", cam, app.cmd);
  t = good;
  t.channel = RenderChannel::Depth;
  t.depthScale = std::numeric_limits<float>::infinity();
  expectError(t, "depthScale", cam, app.cmd);
  const VkDeviceSize align = ctx().properties().limits.minStorageBufferOffsetAlignment;
  if (align > 1) {
    t = good;
    t.offset = align / 2;
    expectError(t, "offset", cam, app.cmd);
  }
  Camera flat = cam;
  flat.fx = 0;
  expectError(good, "focal length", flat, app.cmd);
  Camera empty = cam;
  empty.width = 0;
  t = good;
  t.width = 0;
  expectError(t, "empty image size", empty, app.cmd);
  expectError(good, "command buffer", cam, VK_NULL_HANDLE);

  // Every check runs before the first command: the application's command buffer is untouched
  // and still submits cleanly (the fixture fails on any validation message).
  app.submitAndWait();
}

TEST_F(EmbeddingTest, CallerResourcesBindThroughARingNotTheCache) {
  // A caller's handle may be destroyed and its value reused for a new object, so it must never key
  // the descriptor cache; transient sets are rewritten on every call, in a ring.
  gpu::Kernel k(ctx(), gpu::KernelDesc{gpu::shaders::write_render_target,
                                       {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                                       20,
                                       {}});
  gpu::Buffer color(ctx(), 64), depth(ctx(), 16), target(ctx(), 64);
  const gpu::BufferRange external = gpu::BufferRange::externalBuffer(target.handle(), 0, 64);
  const gpu::BufferRange cachedOnly[] = {color, depth, external};
  EXPECT_THROW(k.descriptorSet(cachedOnly), Error);
  const gpu::BufferRange wholeExternal[] = {color, depth, gpu::BufferRange::externalBuffer(target.handle(), 0, VK_WHOLE_SIZE)};
  EXPECT_THROW(k.transientSet(wholeExternal), Error) << "a caller's buffer has no size vknerf could see";
  std::vector<VkDescriptorSet> sets;
  for (uint32_t i = 0; i <= gpu::Kernel::kTransientSets; ++i) sets.push_back(k.transientSet(cachedOnly));
  EXPECT_NE(sets[0], sets[1]);
  EXPECT_EQ(sets[0], sets[gpu::Kernel::kTransientSets]) << "the ring wraps after kTransientSets calls";
}

TEST_F(EmbeddingTest, FastModelRecordsWhatItRenders) {
  // The fast model sizes a host render from the march's sample count; recorded into a command
  // buffer it cannot, and records its field kernels for the whole sample capacity, cut on the
  // device to the marched total (row limits). Rows are independent in every kernel on the way, so
  // the same samples give the same image.
  TrainConfig c = TrainConfig::fast(ctx());
  FastModel& m = c.fastModel();
  m.hashLevels = 4;
  m.hashLog2Size = 12;
  m.hashGrowth = 1.5f;
  m.width = 16;
  m.gridResolution = 16;
  m.marchSteps = 32;
  m.maxSamplesPerRay = 32;
  m.samplesPerBatch = 4096;
  m.gridUpdateInterval = 2;
  m.gridWarmupSteps = 4;
  c.raysPerBatch = 128;  // the 20x14 view takes three blocks
  c.background = {0.25f, 0.5f, 0.75f};
  Trainer trainer(sharedContext(), tinyDataset(), c);
  for (int i = 0; i < 8; ++i) trainer.step();
  const Camera cam = lookAtOrigin(0.8f, 0.6f, 2.8f, 20, 14);
  const RenderedImage ref = trainer.model().render(cam);
  expectStructure(ref);
  AppDevice d = AppDevice::of(ctx());
  // A host render marches in segments (32 samples first: every sample of this model's rays) and
  // adds each ray's background after compositing its samples over black; the recorded one adds it
  // inside the compositing. Same samples, same field: the two differ by a float rounding or two of
  // values <= 1.
  const std::vector<float> texels = renderIntoBuffer(trainer.model(), d, cam);
  const size_t n = size_t(ref.width) * ref.height;
  ASSERT_EQ(texels.size(), n * 4);
  for (size_t p = 0; p < n; ++p) {
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(texels[p * 4 + k], ref.rgb[p * 3 + k], 1e-6) << "pixel " << p << " channel " << k;
    ASSERT_NEAR(texels[p * 4 + 3], ref.opacity[p], 1e-6) << "pixel " << p << " opacity";
  }
}
