// The fast configuration end to end: hash grid + occupancy grid + packed marching learns the sample
// scene, skips empty space once the grid has measured it, keeps its sample budget, and renders the
// same image whichever way its work is sized (host-sized sub-batches, recorded at full capacity,
// reloaded from a checkpoint), stopping each ray of a host render where it has turned opaque.
#include <algorithm>
#include <cmath>
#include <set>
#include <map>
#include <memory>
#include <utility>

#include "gpu/device/device.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "support/temp_dir.h"
#include "io/checkpoint/checkpoint.h"
#include "models/fast/fast_pipeline.h"
#include "support/held_out.h"
#include "nerf/loss/pixel_bindings.h"
#include "nerf/rays/rays.h"
#include "vknerf/error.h"
#include "vknerf/trainer.h"

using namespace vknerf;

namespace {

using test::sharedContext;

const Dataset& scene(const std::string& split) {
  static std::map<std::string, Dataset> cache;
  auto it = cache.find(split);
  if (it == cache.end()) {
    DatasetOptions o;
    o.downscale = 2;  // 50x50
    o.split = split;
    it = cache.emplace(split, Dataset::load(std::string(VKNERF_SOURCE_DIR) + "/assets/tabletop", o)).first;
  }
  return it->second;
}

// The CPU fast recipe, smaller: every stage runs, each step costs tens of milliseconds.
TrainConfig smallFast() {
  TrainConfig c = TrainConfig::fast(test::context());
  FastModel& m = c.fastModel();
  m.hashLevels = 6;
  m.hashLog2Size = 15;
  m.hashGrowth = 1.5f;
  m.width = 32;
  m.gridResolution = 32;
  m.marchSteps = 128;
  m.maxSamplesPerRay = 128;
  m.samplesPerBatch = 1u << 14;
  m.gridUpdateInterval = 8;
  m.gridWarmupSteps = 32;
  c.raysPerBatch = 1u << 12;
  return c;
}

// colour vec4 per ray of camera 0's first `count` pixels, rendered by `pipe`.
std::vector<float> renderBlock(models::FieldPipeline& pipe, const Camera& cam, uint32_t count, bool mayWait) {
  Context& ctx = test::context();
  auto packed = nerf::packCameras(std::span<const Camera>(&cam, 1));
  auto camBuf = gpu::Buffer::of(ctx, packed);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    pipe.recordRender(rec, {camBuf, 0, 0, count, {1, 1, 1}}, mayWait);
  });
  return pipe.color().download<float>(size_t(count) * 4);
}

void expectSameImage(const std::vector<float>& a, const std::vector<float>& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(std::isfinite(a[i]) && std::isfinite(b[i])) << "texel " << i;
    worst = std::max(worst, double(std::fabs(a[i] - b[i])));
  }
  EXPECT_LE(worst, tol);
}

// smallFast() at a quarter of its step: for tests of what the host does over many steps (waits,
// descriptor sets, ray counts), not of what the field learns.
TrainConfig cheapSteps() {
  TrainConfig c = smallFast();
  c.fastModel().samplesPerBatch = 1u << 12;
  c.raysPerBatch = 1u << 10;
  return c;
}

class FastPipelineTest : public test::GpuTest {};

}  // namespace

TEST_F(FastPipelineTest, LearnsTheSampleSceneAndSkipsEmptySpace) {
  const Dataset& train = scene("train");
  const Dataset& test = scene("test");
  TrainConfig cfg = smallFast();
  // Half of smallFast()'s step: 20.40 dB held-out after 120 steps (20.93 at 2^14), occupied 0.35,
  // 10.5 samples a ray. The steps stay: at 60 the grid has not yet left its warm-up (all occupied).
  cfg.fastModel().samplesPerBatch = 1u << 13;
  Trainer trainer(sharedContext(), train, cfg);
  StepStats st;
  for (int i = 0; i < 120; ++i) st = trainer.step(i == 119);
  ASSERT_TRUE(st.hasLoss);
  EXPECT_TRUE(std::isfinite(st.loss));

  const auto score = test::scoreHeldOut(trainer.model(), test, 4);
  const double psnr = score.psnr, baseline = score.constantPsnr;
  const ModelStatistics stats = trainer.statistics();
  ASSERT_TRUE(stats.occupiedFraction.has_value()) << "the fast model reports its occupancy grid";
  const double occupied = *stats.occupiedFraction;
  const double perRay = stats.samplesPerRay;
  const double perStep = double(stats.samplesPerStep);
  std::printf("fast: held-out PSNR %.2f dB (constant %.2f dB), occupied %.3f, %.1f samples/ray, %.0f samples/step\n",
              psnr, baseline, occupied, perRay, perStep);
  // As the vanilla end-to-end test: 3 dB over the best constant colour needs the geometry.
  EXPECT_GT(psnr, baseline + 3.0);
  // The grid starts all occupied (up to 128 samples per ray); once measured, most of the box is
  // empty space that the march skips.
  EXPECT_LT(occupied, 0.5);
  EXPECT_LT(perRay, 40.0);
  // The ray count adapts so that a step marches about samplesPerBatch samples (one step's lag).
  EXPECT_GT(perStep, 0.5 * cfg.fastModel().samplesPerBatch);
  EXPECT_LT(perStep, 2.0 * cfg.fastModel().samplesPerBatch);

  // A checkpoint carries the occupancy grid: the reloaded model renders exactly what the trainer's does.
  const test::TempDir tmp("fast");
  const std::string path = tmp.file("fast.vknerf");
  trainer.save(path);
  Model loaded = Model::load(sharedContext(), path);
  EXPECT_TRUE(loaded.config().isFast());
  RenderedImage a = trainer.model().render(test.cameras[0]);
  RenderedImage b = loaded.render(test.cameras[0]);
  // Same kernels on the same inputs; only the MLP's chunking may differ between the two
  // pipelines' capacities, which changes float summation order by a few ulps at most.
  expectSameImage(a.rgb, b.rgb, 1e-5);
  expectSameImage(a.opacity, b.opacity, 1e-5);
}

// The proposal estimator end to end: the field learns at the samples the proposal places, the
// proposal from the interlevel loss (reported under its configuration field), a ray gets at most
// its samples, and the reloaded model, and a render recorded without waits, draw what the
// trainer's does.
TEST_F(FastPipelineTest, TheProposalPlacesTheSamplesItIsTrainedFor) {
  const Dataset& train = scene("train");
  const Dataset& test = scene("test");
  TrainConfig cfg = smallFast();
  cfg.fastModel().sampler = Sampler::Proposal;
  cfg.fastModel().proposalSamples = 16;
  auto trainer = std::make_unique<Trainer>(sharedContext(), train, cfg);
  const test::TempDir tmp("proposal");
  const std::string path = tmp.file("proposal.vknerf"), initial = tmp.file("initial.vknerf");
  trainer->save(initial);
  StepStats st;
  // 60 steps: 19.3 dB held-out against the bar of 17.1 below (measured; 21.3 dB at 120 steps).
  for (int i = 0; i < 60; ++i) {
    st = trainer->step(i == 0 || i == 59);
    if (!st.hasLoss) continue;
    EXPECT_TRUE(std::isfinite(st.loss));
    ASSERT_EQ(st.lossTerms.size(), 1u);
    EXPECT_EQ(st.lossTerms[0].first, "proposal_loss");
    EXPECT_TRUE(std::isfinite(st.lossTerms[0].second) && st.lossTerms[0].second > 0) << st.lossTerms[0].second;
    EXPECT_LE(st.samples, 16ull * st.rays) << "at most the proposal's samples a ray";
  }
  trainer->save(path);
  // The interlevel loss is the proposal's only gradient (Adam makes its weight a mere scale):
  // its network has moved from where it started.
  const auto before = io::Checkpoint::load(initial).get<float>("proposal.mlp.params");
  const auto after = io::Checkpoint::load(path).get<float>("proposal.mlp.params");
  ASSERT_EQ(before.size(), after.size());
  double moved = 0;
  for (size_t i = 0; i < before.size(); ++i) moved = std::max(moved, double(std::fabs(after[i] - before[i])));
  EXPECT_GT(moved, 1e-3) << "the proposal's network never learned";

  const auto score = test::scoreHeldOut(trainer->model(), test, 4);
  std::printf("fast with a proposal: held-out PSNR %.2f dB (constant %.2f dB)\n", score.psnr, score.constantPsnr);
  EXPECT_GT(score.psnr, score.constantPsnr + 3.0);

  EXPECT_FALSE(io::Checkpoint::load(path).get<float>("proposal.encoding.params").empty());
  Model loaded = Model::load(sharedContext(), path);
  EXPECT_TRUE(loaded.config().fastModel().usesProposal());
  EXPECT_EQ(loaded.config().fastModel().proposalSamples, 16u);
  RenderedImage a = trainer->model().render(test.cameras[0]);
  RenderedImage b = loaded.render(test.cameras[0]);
  // Same kernels on the same inputs, up to the MLP's chunking (a few ulps), as above.
  expectSameImage(a.rgb, b.rgb, 1e-5);
  expectSameImage(a.opacity, b.opacity, 1e-5);

  // A render may place another count of samples a ray (RenderSettings::proposalSamples): the
  // trained count draws the very same image, half of it half the samples at most; a profile names
  // the proposal's kernels apart from the field's.
  RenderSettings asTrained, half;
  asTrained.proposalSamples = 16;
  half.proposalSamples = 8;
  half.profile = true;
  const RenderedImage same = Model::load(sharedContext(), path, asTrained).render(test.cameras[0]);
  expectSameImage(b.rgb, same.rgb, 0.0);
  EXPECT_EQ(same.samples, b.samples);
  const RenderedImage fewer = Model::load(sharedContext(), path, half).render(test.cameras[0]);
  const uint64_t pixels = uint64_t(test.cameras[0].width) * test.cameras[0].height;
  EXPECT_GT(fewer.samples, 0u);
  EXPECT_LE(fewer.samples, 8 * pixels);
  EXPECT_LT(fewer.samples, b.samples);
  for (float v : fewer.rgb) ASSERT_TRUE(std::isfinite(v));
  if (!fewer.kernelMs.empty()) {  // a device whose compute queue has no timestamps times no kernel
    const auto timed = [&](const std::string& name) {
      return std::any_of(fewer.kernelMs.begin(), fewer.kernelMs.end(), [&](const auto& k) { return k.first == name; });
    };
    EXPECT_TRUE(timed("encode_hash")) << "the field's hash grid";
    EXPECT_TRUE(timed("proposal: encode_hash")) << "the proposal's hash grid, apart";
    EXPECT_TRUE(timed("proposal: proposal_sample"));
  }
  // The setting needs a model whose samples a proposal places.
  const std::string marched = tmp.file("marched.vknerf");
  TrainConfig marching = smallFast();
  marching.fastModel().sampler = Sampler::March;
  Trainer(sharedContext(), train, marching).save(marched);
  EXPECT_THROW(Model::load(sharedContext(), marched, half), Error);

  // A render recorded into one command buffer draws what a waited one does, in blocks of rays
  // whose every candidate fits the march's capacity (a trainer's: a few blocks for 2048 rays).
  models::FastPipeline pipe(test::context(), cfg, train.bounds, 2048, true);
  const std::vector<float> waited = renderBlock(pipe, test.cameras[1], 2048, true);
  const std::vector<float> recorded = renderBlock(pipe, test.cameras[1], 2048, false);
  expectSameImage(waited, recorded, 0.0);
}

TEST_F(FastPipelineTest, TheProposalsFieldBatchIsSizedForAStepNotForEveryRay) {
  // A step with the proposal places N samples on each of about samplesPerBatch / N rays, so the
  // field's batch needs the step's budget with the march's headroom whatever N is. Sized for every
  // ray the pipeline holds at N samples, it grew with N (the cup at 32: 848 MiB against 152
  // without the proposal); here it went from 86 MiB at 16 samples a ray to 249 at 64. Step-sized,
  // the two are the same but for the proposal's per-ray buffers (offsets: bytes).
  const Dataset& train = scene("train");
  auto deviceMiB = [&](uint32_t samples) {
    TrainConfig cfg = smallFast();
    cfg.fastModel().sampler = Sampler::Proposal;
    cfg.fastModel().proposalSamples = samples;
    return Trainer(sharedContext(), train, cfg).statistics().deviceMiB;
  };
  const double at16 = deviceMiB(16), at64 = deviceMiB(64);
  std::printf("device buffers: %.1f MiB at 16 samples a ray, %.1f at 64\n", at16, at64);
  EXPECT_LT(at64, at16 + 1.0);
}

TEST_F(FastPipelineTest, SubBatchesAndRecordedRendersMatch) {
  // An untrained field with every cell occupied: each ray marches up to 64 samples, no ray turns
  // opaque, and a render marches each in two segments of 32 (SegmentAccumulator); a training-sized
  // sample capacity holds 32 samples of only 256 rays, so the host renders the 2048 in 8 blocks.
  TrainConfig cfg = smallFast();
  cfg.fastModel().marchSteps = 64;  // at most 64 samples on any ray through the box
  cfg.fastModel().maxSamplesPerRay = 64;
  cfg.fastModel().samplesPerBatch = 1u << 12;
  const Aabb box = scene("train").bounds;
  const Camera& cam = scene("test").cameras[1];
  const uint32_t count = 2048;
  models::FastPipeline small(test::context(), cfg, box, count, true);  // sample capacity ~8k
  models::FastPipeline large(test::context(), cfg, box, count, false);  // 64 samples per ray of capacity: 131k
  auto split = renderBlock(small, cam, count, true);
  auto whole = renderBlock(large, cam, count, true);
  expectSameImage(split, whole, 1e-5);
  // Recorded (no host round trip): the field runs over the whole capacity; 64 samples per ray fit,
  // as many as any ray has, so no ray is cut and the image is the same.
  auto recorded = renderBlock(large, cam, count, false);
  expectSameImage(recorded, whole, 1e-5);
  // The untrained field is a near-uniform fog: a ray through the box is partly opaque.
  double opacity = 0;
  for (uint32_t r = 0; r < count; ++r) opacity += whole[r * 4 + 3] / count;
  EXPECT_GT(opacity, 0.05);
}

// Recorded into a caller's command buffer, a pipeline whose sample capacity is small for its
// tile (a trainer's: ~8k samples for 2048 rays of up to 128 samples each) marches the tile in blocks
// that give every ray all its samples, and draws what a render with the host's waits draws: a
// trainer's model drawn by an embedding application is the model its checkpoint renders.
TEST_F(FastPipelineTest, ARecordedRenderGivesEveryRayItsSamplesWhateverTheCapacity) {
  TrainConfig cfg = smallFast();
  cfg.fastModel().marchSteps = 128;
  cfg.fastModel().maxSamplesPerRay = 128;
  cfg.fastModel().samplesPerBatch = 1u << 12;
  const Aabb box = scene("train").bounds;
  const Camera& cam = scene("test").cameras[1];
  const uint32_t count = 2048;
  models::FastPipeline small(test::context(), cfg, box, count, true);
  const auto waited = renderBlock(small, cam, count, true), recorded = renderBlock(small, cam, count, false);
  // The same segments of the same rays through the same kernels: only the chunking of the last
  // kernels may differ, a few roundings of values <= 1.
  expectSameImage(recorded, waited, 1e-6);
  double opacity = 0;
  for (uint32_t r = 0; r < count; ++r) opacity += waited[r * 4 + 3] / count;
  EXPECT_GT(opacity, 0.05) << "the untrained fog should make the rays partly opaque";
}

// Every MLP parameter set to `value` (padding included): with 0.3 the density is ~e^6 wherever the
// hash features are near 0 (all of an untrained table), so a ray through the box is opaque after a
// few of its 64 samples.
void setNetworkParameters(models::FastPipeline& pipe, float value) {
  for (const auto& s : pipe.state())
    if (s.name.rfind("mlp", 0) == 0 && !s.optimizer) s.buffer->upload(std::vector<float>(s.count, value));
}

// Submissions of a render of camera 1's first `count` pixels.
size_t renderSubmissions(models::FieldPipeline& pipe, const Camera& cam, uint32_t count) {
  Context& ctx = test::context();
  auto packed = nerf::packCameras(std::span<const Camera>(&cam, 1));
  auto camBuf = gpu::Buffer::of(ctx, packed);
  gpu::Recorder rec(ctx);
  rec.startLog();
  rec.begin();
  pipe.recordRender(rec, {camBuf, 0, 0, count, {1, 1, 1}}, true);
  const size_t n = rec.submissions().size();
  rec.end();
  rec.submitAndWait();
  return n;
}

// A render marches its rays in segments and stops each where it has turned opaque
// (SegmentAccumulator): on an opaque field it shades far fewer samples than the whole march
// (RenderSettings::minTransmittance 0), in one submission when every ray ends in its first segment,
// and its image differs from the whole march's by no more than the light behind the cut. A render
// recorded into a command buffer (segments of the same length, no host read-back) gives the same.
TEST_F(FastPipelineTest, ARenderStopsEachRayWhereItIsOpaque) {
  TrainConfig cfg = smallFast();
  cfg.fastModel().marchSteps = 256;  // ~80 samples on a ray through the box, most past the first segment
  cfg.fastModel().maxSamplesPerRay = 128;
  const Aabb box = scene("train").bounds;
  const Camera& cam = scene("test").cameras[1];
  const uint32_t count = 2048;
  RenderSettings everySample;
  everySample.minTransmittance = 0;
  models::FastPipeline opaque(test::context(), cfg, box, count, false),
      whole(test::context(), cfg, box, count, false, everySample);
  setNetworkParameters(opaque, 0.3f);
  setNetworkParameters(whole, 0.3f);
  EXPECT_EQ(renderSubmissions(opaque, cam, count), 1u);
  EXPECT_GE(renderSubmissions(whole, cam, count), 2u);
  const uint64_t shaded = opaque.renderedSamples(), wholeMarch = whole.renderedSamples();
  std::printf("samples shaded: %llu of the whole march's %llu\n", (unsigned long long)shaded,
              (unsigned long long)wholeMarch);
  EXPECT_GT(shaded, 0u);
  EXPECT_LT(shaded, wholeMarch / 2);
  auto segmented = renderBlock(opaque, cam, count, true), everything = renderBlock(whole, cam, count, true);
  double opacity = 0;
  for (uint32_t r = 0; r < count; ++r) opacity += segmented[r * 4 + 3] / count;
  EXPECT_GT(opacity, 0.3) << "the field is not opaque: nothing is cut";
  // A ray stops once its transmittance is below 1e-4: what it leaves out adds at most that times
  // a colour or background in [0, 1] to each channel and to the opacity; the over operator and a
  // segment's resumed march add a few float roundings of values <= 1 (1e-6).
  expectSameImage(segmented, everything, 1e-4 + 1e-5);
  // Recorded: the same first segment, in which every ray ends; only the roundings of the last
  // kernels' chunking may differ.
  expectSameImage(renderBlock(opaque, cam, count, false), segmented, 1e-6);
}

// A training step whose forward runs in segments (SegmentRows: the field over the rows the
// compositor will read) composites exactly what one forward over every marched sample does: each
// row it reads is computed by the same kernels with the same inputs, so the batch's colours, the
// samples kept and the loss partials are equal bit for bit. The field is made dense enough (every
// MLP parameter 0.3) that a ray keeps about 19 of its 64 samples: rays end in the later segments
// too, and most rows are skipped.
TEST_F(FastPipelineTest, ATrainingStepInSegmentsCompositesWhatOneForwardDoes) {
  const Dataset& train = scene("train");
  TrainConfig cfg = smallFast();
  cfg.fastModel().marchSteps = 256;
  cfg.fastModel().maxSamplesPerRay = 256;
  cfg.fastModel().gridWarmupSteps = 0;
  Context& ctx = test::context();
  std::vector<uint64_t> pixelCounts;
  for (const auto& cam : train.cameras) pixelCounts.push_back(uint64_t(cam.width) * cam.height);
  nerf::TrainingPixels pixels(ctx, nerf::planPixelBindings(pixelCounts, nerf::pixelBytesPerBinding(ctx)));
  for (uint32_t i = 0; i < train.images.size(); ++i) pixels.upload(i, train.images[i].rgba.data());
  auto cameras = gpu::Buffer::of(ctx, nerf::packCameras(train.cameras, pixels.layout().images));
  const models::TrainingData data{pixels.bindings(), &cameras, uint32_t(train.cameras.size()), true};
  struct Step {
    models::FieldPipeline::StepSize size;
    std::vector<float> color, partials;
    double samplesPerRay;
  };
  auto step = [&](double segmentsBelowKept) {
    models::FastPipeline pipe(ctx, cfg, train.bounds, cfg.raysPerBatch, true, {}, models::TrainingPhotos{data.numCameras});
    pipe.segmentTrainingBelowKept(segmentsBelowKept);
    setNetworkParameters(pipe, 0.3f);
    gpu::Recorder rec(ctx);
    Step s;
    auto loss = gpu::Buffer::hostReadable(ctx, pipe.lossPartials().size());
    pipe.submitTrainStep(rec, data, nerf::OptimizerStep::at(0), loss);
    rec.wait();
    s.size = pipe.collectTrainStep(0);
    s.color = pipe.color().download<float>(size_t(s.size.rays) * 4);
    s.partials = pipe.lossPartials().download<float>();
    s.samplesPerRay = pipe.statistics().samplesPerRay;
    return s;
  };
  const Step segmented = step(1.0), whole = step(-1.0);
  ASSERT_GT(whole.size.rays, 0u);
  const double marched = whole.samplesPerRay * whole.size.rays, kept = double(whole.size.samples);
  std::printf("%u rays, %.1f samples a ray marched, %.1f kept\n", whole.size.rays, whole.samplesPerRay,
              kept / whole.size.rays);
  EXPECT_LT(kept, 0.5 * marched) << "the field is not dense enough: no row is skipped";
  EXPECT_GT(kept, 4.0 * whole.size.rays) << "the rays end in the first segment: the later ones are not exercised";
  EXPECT_EQ(segmented.size.rays, whole.size.rays);
  EXPECT_EQ(segmented.size.samples, whole.size.samples);
  EXPECT_EQ(segmented.samplesPerRay, whole.samplesPerRay);
  ASSERT_EQ(segmented.color.size(), whole.color.size());
  for (size_t i = 0; i < whole.color.size(); ++i) {
    ASSERT_TRUE(std::isfinite(whole.color[i])) << "colour float " << i;
    ASSERT_EQ(segmented.color[i], whole.color[i]) << "colour float " << i;
  }
  EXPECT_EQ(segmented.partials, whole.partials);
}

TEST_F(FastPipelineTest, RenderSettingsOutOfRangeAreErrors) {
  const Aabb box = scene("train").bounds;
  for (float t : {-1e-3f, 1.0f, std::nanf("")}) {
    RenderSettings s;
    s.minTransmittance = t;
    EXPECT_THROW(models::FastPipeline(test::context(), smallFast(), box, 64, false, s), Error) << t;
  }
  // More samples a ray than a configuration may hold, refused before anything is sized for them.
  TrainConfig proposal = smallFast();
  proposal.fastModel().sampler = Sampler::Proposal;
  RenderSettings tooMany;
  tooMany.proposalSamples = FastModel::kMaxProposalSamples + 1;
  EXPECT_THROW(models::FastPipeline(test::context(), proposal, box, 64, false, tooMany), Error);
  tooMany.proposalSamples = UINT32_MAX;
  EXPECT_THROW(models::FastPipeline(test::context(), proposal, box, 64, false, tooMany), Error);
}

TEST_F(FastPipelineTest, UnknownConfigurationIsAnError) {
  // The model is a variant: an unknown kind cannot be built in code, only named in a string.
  EXPECT_THROW(TrainConfig::named("turbo", test::context()), Error);
  // Asking a fast configuration for its vanilla description is an error, not a default.
  TrainConfig cfg = smallFast();
  EXPECT_THROW(cfg.vanillaModel(), Error);
}

// Each step binds ranges sized by its own ray and sample counts. The kernels' descriptor-set cache
// must not grow with the number of steps (a GPU run of many thousand steps would keep adding sets
// and texel views). Keyed by exact ranges it grew by about 3 sets a step here (237 sets after 60
// steps, 602 after 180); with ranges rounded to powers of two it made 77 and then 82. A drift of the
// counts may still reach a new power of two, hence a margin of a quarter rather than none.
TEST_F(FastPipelineTest, ALongRunKeepsItsDescriptorSetsBounded) {
  Trainer trainer(sharedContext(), scene("train"), cheapSteps());
  const auto& sets = gpu::device(*sharedContext()).cachedDescriptorSets();
  const auto run = [&](int steps) {
    for (int i = 0; i < steps; ++i) trainer.step(false);
    return sets.load();
  };
  const uint64_t warm = run(60), later = run(120);
  EXPECT_LE(later - warm, warm / 4) << warm << " sets after 60 steps, " << later << " after 180";
}

// A training step waits for the device once, for its own submission: what the host reports of it
// is copied into host-readable memory within that submission. On a discrete GPU (the amd-rdna2
// profile: device-local buffers the host cannot map) each read of a device buffer would be a
// submission and a wait of its own: three more a step before (the ray count, the sample total,
// the per-ray kept counts), and one more when the loss is read.
TEST_F(FastPipelineTest, ATrainingStepWaitsOnceForTheDeviceOnADiscreteGpu) {
  ContextOptions o;
  o.profile = "amd-rdna2";
  o.validation = ctx().validationEnabled();
  auto discrete = Context::create(o);
  ASSERT_FALSE(gpu::device(*discrete).unifiedMemory());
  DatasetOptions d;
  d.downscale = 4;
  const Dataset photos = Dataset::load(std::string(VKNERF_SOURCE_DIR) + "/assets/tabletop", d);
  Trainer trainer(discrete, photos, cheapSteps());
  const auto& waits = gpu::device(*discrete).hostWaits();
  // Warm-up: the first steps and the first occupancy update allocate their scratch buffers (and
  // fill them, a one-time submission each).
  for (int i = 0; i < 20; ++i) trainer.step(false);
  const uint64_t before = waits.load();
  // Every other step reads its loss too: copied within the step like its counts.
  for (int i = 0; i < 20; ++i) trainer.step(i % 2 == 0);
  EXPECT_EQ(waits.load() - before, 20u);
  EXPECT_EQ(discrete->validationMessages(), 0u);
}

// submitStep queues a step behind the one the device still runs: when it returns, its own step is
// in flight and the host has waited only for the step before it (once a step, never for the step
// it just submitted), on a discrete GPU too. The statistics arrive one step late, in order, and a
// save in between waits for the step in flight.
TEST_F(FastPipelineTest, ASubmittedStepIsNotWaitedForUntilTheNextIsSubmitted) {
  ContextOptions o;
  o.profile = "amd-rdna2";
  o.validation = ctx().validationEnabled();
  auto discrete = Context::create(o);
  DatasetOptions d;
  d.downscale = 4;
  const Dataset photos = Dataset::load(std::string(VKNERF_SOURCE_DIR) + "/assets/tabletop", d);
  Trainer trainer(discrete, photos, cheapSteps());
  const auto& waits = gpu::device(*discrete).hostWaits();
  for (int i = 0; i < 20; ++i) trainer.step(false);  // warm-up, as above
  EXPECT_FALSE(trainer.submitStep(true).has_value()) << "no step was in flight before the first";
  EXPECT_EQ(trainer.stepsInFlight(), 1u);
  const uint64_t before = waits.load();
  for (uint32_t i = 0; i < 20; ++i) {
    const auto done = trainer.submitStep(i % 2 == 1);
    EXPECT_EQ(trainer.stepsInFlight(), 1u);
    ASSERT_TRUE(done.has_value());
    EXPECT_EQ(done->step, trainer.steps() - 1);
    EXPECT_EQ(done->hasLoss, i % 2 == 0) << "the loss belongs to the step that asked for it";
    EXPECT_GT(done->rays, 0u);
    EXPECT_EQ(waits.load() - before, i + 1);
  }
  test::TempDir dir("submit_save");
  trainer.save(dir.file("m.vknerf"));
  EXPECT_EQ(trainer.stepsInFlight(), 0u);
  const auto last = trainer.finishSteps();
  ASSERT_TRUE(last.has_value()) << "the step the save waited for is still reported";
  EXPECT_EQ(last->step, trainer.steps());
  EXPECT_FALSE(trainer.finishSteps().has_value());
  EXPECT_EQ(discrete->validationMessages(), 0u);
}

// A run's numbers do not depend on when the host waits: steps submitted two deep take the ray
// counts and sample totals of steps waited for one at a time, exactly (what the host decides from a
// step's counts applies two steps later either way), and so train to the same losses.
TEST_F(FastPipelineTest, SubmittedStepsTrainAsWaitedSteps) {
  DatasetOptions d;
  d.downscale = 4;
  const Dataset photos = Dataset::load(std::string(VKNERF_SOURCE_DIR) + "/assets/tabletop", d);
  TrainConfig cfg = cheapSteps();
  cfg.fastModel().gridUpdateInterval = 4;  // the occupancy updates and their threshold change too
  constexpr uint32_t kSteps = 40;
  std::vector<StepStats> waited, submitted;
  {
    Trainer trainer(sharedContext(), photos, cfg);
    for (uint32_t i = 0; i < kSteps; ++i) waited.push_back(trainer.step(true));
  }
  {
    Trainer trainer(sharedContext(), photos, cfg);
    for (uint32_t i = 0; i < kSteps; ++i) {
      if (auto done = trainer.submitStep(true)) submitted.push_back(*done);
      if (i == kSteps / 2) (void)trainer.statistics();  // a wait mid-run changes nothing
    }
    if (auto done = trainer.finishSteps()) submitted.push_back(*done);
  }
  ASSERT_EQ(submitted.size(), waited.size());
  std::set<uint32_t> rayCounts;
  for (uint32_t i = 0; i < kSteps; ++i) {
    EXPECT_EQ(submitted[i].step, waited[i].step);
    EXPECT_EQ(submitted[i].rays, waited[i].rays) << "step " << i + 1;
    EXPECT_EQ(submitted[i].samples, waited[i].samples) << "step " << i + 1;
    // Float atomic adds in the gradients sum in the order the device's threads reach them: two runs
    // of the same steps agree to rounding, not bit for bit (as a resumed run does: 1e-4 relative).
    EXPECT_NEAR(submitted[i].loss, waited[i].loss, 1e-4 * waited[i].loss) << "step " << i + 1;
    rayCounts.insert(waited[i].rays);
  }
  EXPECT_GT(rayCounts.size(), 2u) << "the ray count never adapted: the rule is not exercised";
}

// Every term of the loss is reported by the configuration field that weighs it, its weight
// applied: the distortion loss (summed over the step's rays on the device) and camera
// refinement's penalty (over the cameras). The first step of two runs that differ only in the
// distortion loss's weight composites the same batch through the same field, so its reported
// distortion loss doubles with the weight; the penalty is 0 while the corrections are, and later
// (penalty / 2) |corrections|^2 of the corrections the step started from, as the checkpoint holds them.
TEST_F(FastPipelineTest, EachLossTermIsReportedByItsConfigurationField) {
  auto config = [](float distortion) {
    TrainConfig c = smallFast();
    c.fastModel().distortionLoss = distortion;
    c.fastModel().refineCameras = true;
    c.fastModel().cameraPenalty = 10.0f;
    c.fastModel().cameraLearningRate = 1e-3f;
    return c;
  };
  Trainer a(sharedContext(), scene("train"), config(0.01f)), b(sharedContext(), scene("train"), config(0.02f));
  const StepStats first = a.step(true), doubled = b.step(true);
  ASSERT_EQ(first.lossTerms.size(), 2u);
  EXPECT_EQ(first.lossTerms[0].first, "distortion_loss");
  EXPECT_EQ(first.lossTerms[1].first, "camera_penalty");
  const double distortion = first.lossTerms[0].second;
  EXPECT_TRUE(std::isfinite(distortion) && distortion > 0) << distortion;
  // Exactly twice in float (the weight per ray doubles exactly); the host adds the partials in double.
  EXPECT_NEAR(doubled.lossTerms[0].second, 2 * distortion, 1e-12 * distortion);
  EXPECT_EQ(first.lossTerms[1].second, 0.0);

  for (int i = 0; i < 5; ++i) a.step(false);
  const test::TempDir tmp("loss_terms");
  a.save(tmp.file("a.vknerf"));
  const auto corrections = io::Checkpoint::load(tmp.file("a.vknerf")).get<float>("cameras.params");
  double want = 0, sizes = 0;
  for (float c : corrections) want += 0.5 * 10.0 * double(c) * c;
  for (float c : corrections) sizes += std::fabs(double(c));
  ASSERT_GT(want, 0.0) << "the corrections did not move";
  const StepStats later = a.step(true);
  ASSERT_EQ(later.lossTerms.size(), 2u);
  // A float per camera (six squares, a few roundings each) summed in float trees of 128: well
  // within 1e-5 of the value.
  EXPECT_NEAR(later.lossTerms[1].second, want, 1e-5 * want);

  // Without the weights, no terms.
  TrainConfig plain = smallFast();
  plain.fastModel().distortionLoss = 0;
  Trainer c(sharedContext(), scene("train"), plain);
  EXPECT_TRUE(c.step(true).lossTerms.empty());
}
