// The vanilla trainer on the shipped sample scene: steps run, checkpoints resume exactly, a loaded
// model renders what the trainer's model renders.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "support/gpu_test.h"
#include "support/sample_scene.h"
#include "support/temp_dir.h"
#include "support/tiny_config.h"
#include "io/checkpoint/checkpoint.h"
#include "models/fast/fast_field.h"
#include "vknerf/model.h"
#include "vknerf/error.h"
#include "vknerf/trainer.h"

using namespace vknerf;

namespace {

// A small configuration (same recipe, tiny sizes) so each step costs milliseconds.
TrainConfig tinyConfig() {
  TrainConfig c = test::tinyVanillaConfig();
  c.learningRate = 5e-3f;
  c.learningRateFinal = 5e-4f;
  c.decaySteps = 1000;
  return c;
}

const Dataset& scene() { return test::quarterSizeSampleScene(); }

using test::sharedContext;

class TrainerTest : public test::GpuTest {};

// The fast model at a size the sample scene trains in a few dozen steps: a 16^3 occupancy grid,
// 4096 samples and 1024 rays a step.
TrainConfig smallFast() {
  TrainConfig c = TrainConfig::fast(*sharedContext());
  c.fastModel().gridResolution = 16;
  c.fastModel().samplesPerBatch = 4096;
  c.raysPerBatch = 1024;
  return c;
}

}  // namespace

TEST_F(TrainerTest, LossDecreasesOverSteps) {
  Trainer t(sharedContext(), scene(), tinyConfig());
  double first = 0, last = 0;
  for (int i = 0; i < 60; ++i) {
    auto st = t.step(i < 5 || i >= 55);
    if (i < 5) first += st.loss / 5;
    if (i >= 55) last += st.loss / 5;
    if (st.hasLoss) ASSERT_TRUE(std::isfinite(st.loss));
  }
  EXPECT_EQ(t.steps(), 60u);
  EXPECT_LT(last, 0.8 * first) << "first " << first << " last " << last;
}

TEST_F(TrainerTest, ResumeContinuesExactly) {
  const test::TempDir tmp("trainer");
  const auto path = tmp.file("resume.vknerf");
  Trainer a(sharedContext(), scene(), tinyConfig());
  for (int i = 0; i < 5; ++i) a.step();
  a.save(path);
  Trainer b(sharedContext(), scene(), Trainer::configOf(path));
  b.resume(path);
  EXPECT_EQ(b.steps(), 5u);
  // Same step numbers give the same rays, jitter and learning rate. The MLP's weight gradients are
  // summed with float atomics, whose order varies, so the two runs agree to rounding, not bits:
  // losses of the same batch within 1e-4 relative.
  for (int i = 0; i < 3; ++i) {
    auto sa = a.step(true), sb = b.step(true);
    EXPECT_NEAR(sa.loss, sb.loss, 1e-4 * sa.loss) << "step " << sa.step;
  }
}

TEST_F(TrainerTest, RunProgressSetsTheRateSchedule) {
  Trainer t(sharedContext(), scene(), tinyConfig());  // 5e-3 -> 5e-4 over 1000 steps
  EXPECT_FLOAT_EQ(t.learningRate(), 5e-3f);
  t.setRunProgress(0.5);
  EXPECT_FLOAT_EQ(t.learningRate(), float(5e-3 * std::sqrt(0.1)));
  t.setRunProgress(1.0);
  EXPECT_FLOAT_EQ(t.learningRate(), 5e-4f);
  t.setRunProgress(3.0);  // past the run's end (a last step that overran its time): held
  EXPECT_FLOAT_EQ(t.learningRate(), 5e-4f);
  EXPECT_THROW(t.setRunProgress(std::nan("")), Error);
  t.setRunProgress(std::nullopt);  // back to the steps over decay_steps
  for (int i = 0; i < 2; ++i) t.step();
  EXPECT_FLOAT_EQ(t.learningRate(), float(5e-3 * std::pow(0.1, 2.0 / 1000.0)));
}

// The rate the progress gives is the one the step applies: Adam's first step moves each parameter
// by lr * g / (|g| + eps), i.e. by lr wherever |g| >> eps, so a run at its end (lr_final) moves the
// parameters a tenth as far as a run at its start, from the same initial parameters and batch.
TEST_F(TrainerTest, RunProgressReachesTheOptimizer) {
  const test::TempDir tmp("trainer");
  const auto start = tmp.file("start.vknerf"), end = tmp.file("end.vknerf"), init = tmp.file("init.vknerf");
  Trainer a(sharedContext(), scene(), tinyConfig()), b(sharedContext(), scene(), tinyConfig());
  a.save(init);
  a.step();
  b.setRunProgress(1.0);
  b.step();
  a.save(start);
  b.save(end);
  const auto p0 = io::Checkpoint::load(init).get<float>("coarse.params");
  const auto pa = io::Checkpoint::load(start).get<float>("coarse.params");
  const auto pb = io::Checkpoint::load(end).get<float>("coarse.params");
  ASSERT_EQ(pa.size(), p0.size());
  ASSERT_EQ(pb.size(), p0.size());
  // Parameters that moved by nearly the whole rate at the start (|g| >> eps, not a rounding of a
  // float atomic's order away from zero) moved by a tenth of it at the end: lr_final / lr = 0.1.
  size_t compared = 0;
  for (size_t i = 0; i < p0.size(); ++i) {
    const double da = std::abs(double(pa[i]) - p0[i]), db = std::abs(double(pb[i]) - p0[i]);
    if (da < 0.99 * 5e-3) continue;
    EXPECT_NEAR(db / da, 0.1, 0.005) << "parameter " << i;
    ++compared;
  }
  EXPECT_GT(compared, p0.size() / 2);
}

TEST_F(TrainerTest, LoadedModelRendersLikeTrainer) {
  const test::TempDir tmp("trainer");
  const auto path = tmp.file("render.vknerf");
  Trainer t(sharedContext(), scene(), tinyConfig());
  for (int i = 0; i < 10; ++i) t.step();
  t.save(path);
  Model m = Model::load(sharedContext(), path);
  Camera cam = scene().cameras[3];
  RenderedImage a = t.model().render(cam), b = m.render(cam);
  ASSERT_EQ(a.rgb.size(), size_t(cam.width) * cam.height * 3);
  // Rendering is deterministic (bin centres, fixed draws) and the parameters are the same bits.
  // The two pipelines' sample capacities differ (a training step's against a render tile's), and a
  // render's segments after the first are sized by it (FastPipeline::doRecordRender): the over
  // operator's roundings (1e-6) and, for a ray that turns opaque inside a segment of one and at the
  // end of the other's, the light behind T < 1e-4 (at most 1e-4 of a colour <= 1) may differ.
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_NEAR(a.rgb[i], b.rgb[i], 1e-4 + 1e-5) << i;
  for (size_t i = 0; i < a.depth.size(); ++i) {
    ASSERT_TRUE(std::isfinite(a.depth[i]));
    ASSERT_GE(a.opacity[i], 0.0f);
    ASSERT_LE(a.opacity[i], 1.0f + 1e-6f);
  }
}

TEST_F(TrainerTest, ResumeRejectsADifferentModel) {
  const test::TempDir tmp("trainer");
  const auto path = tmp.file("other.vknerf");
  Trainer a(sharedContext(), scene(), tinyConfig());
  a.save(path);
  TrainConfig wider = tinyConfig();
  wider.vanillaModel().width = 64;
  Trainer b(sharedContext(), scene(), wider);
  EXPECT_THROW(b.resume(path), Error);
}

TEST_F(TrainerTest, EmptyDatasetIsAnError) {
  Dataset empty;
  EXPECT_THROW(Trainer(sharedContext(), empty, tinyConfig()), Error);
}

TEST_F(TrainerTest, FastModelNestsCascadesForAabbScale) {
  // aabb_scale 8: 1 + log2(8) = 4 cascades, resolved by the trainer and kept in the checkpoint;
  // a scene without one keeps one grid.
  TrainConfig c = smallFast();
  Dataset unbounded = scene();
  unbounded.aabbScale = 8;
  Trainer t(sharedContext(), unbounded, c);
  t.step();
  auto s = t.statistics();
  ASSERT_EQ(s.occupiedFractionPerCascade.size(), 4u);
  ASSERT_TRUE(s.meanSamplesPerRay.has_value());
  EXPECT_GT(*s.meanSamplesPerRay, 0.0);
  const test::TempDir tmp("trainer");
  t.save(tmp.file("cascades.vknerf"));
  EXPECT_EQ(Trainer::configOf(tmp.file("cascades.vknerf")).fastModel().cascades, 4u);
  Trainer one(sharedContext(), scene(), c);
  EXPECT_EQ(one.statistics().occupiedFractionPerCascade.size(), 1u);
}

// A contracted grid (FastModel::contraction) trains, and the checkpoint keeps it: the loaded model
// renders what the trainer's does (a grid spanning the box uncontracted would draw another image).
TEST_F(TrainerTest, AContractedGridTrainsAndItsCheckpointRendersTheSame) {
  TrainConfig c = smallFast();
  c.fastModel().contraction = true;
  Dataset unbounded = scene();
  unbounded.aabbScale = 4;
  Trainer t(sharedContext(), unbounded, c);
  double first = 0, last = 0;
  for (int i = 0; i < 30; ++i) (i == 0 ? first : last) = t.step(true).loss;
  EXPECT_LT(last, first);
  const test::TempDir tmp("trainer");
  t.save(tmp.file("contracted.vknerf"));
  const TrainConfig saved = Trainer::configOf(tmp.file("contracted.vknerf"));
  EXPECT_TRUE(saved.fastModel().contraction);
  const Model m = Model::load(sharedContext(), tmp.file("contracted.vknerf"));
  const RenderedImage a = t.model().render(unbounded.cameras[0]), b = m.render(unbounded.cameras[0]);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  // The same kernels on the same parameters: equal up to float-atomic orders, which a render has none of.
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << "value " << i;
  TrainConfig flat = saved;
  flat.fastModel().contraction = false;
  EXPECT_NE(models::hashGridConfigFor(flat.fastModel()).contraction, models::hashGridConfigFor(saved.fastModel()).contraction);
}

// FastModel::occupancyThreshold decides which cells the march skips: the same training with a
// higher threshold leaves fewer cells occupied and marches fewer samples per ray.
TEST_F(TrainerTest, AHigherOccupancyThresholdSkipsMoreOfTheBox) {
  auto run = [](float threshold) {
    TrainConfig c = smallFast();
    c.fastModel().occupancyThreshold = threshold;
    Trainer t(sharedContext(), scene(), c);
    for (int i = 0; i < 48; ++i) t.step();
    return t.statistics();
  };
  const ModelStatistics usual = run(0.01f), sharp = run(0.3f);
  ASSERT_TRUE(usual.occupiedFraction && sharp.occupiedFraction);
  EXPECT_LT(*sharp.occupiedFraction, *usual.occupiedFraction);
  EXPECT_GT(*sharp.occupiedFraction, 0.0);
  EXPECT_LT(*sharp.meanSamplesPerRay, *usual.meanSamplesPerRay);
}

// FastModel::stepOpacity stretches march samples through faint cells: the same cascaded training
// with a loose bound marches fewer samples per ray and still learns, the checkpoint keeps the bound,
// and the loaded model renders what the trainer's does (it marches the same stretched samples).
TEST_F(TrainerTest, StretchedStepsMarchFewerSamplesAndTheCheckpointKeepsThem) {
  const test::TempDir tmp("trainer");
  Dataset unbounded = scene();
  unbounded.aabbScale = 4;
  auto run = [&](float stepOpacity) {
    TrainConfig c = smallFast();
    c.fastModel().stepOpacity = stepOpacity;
    auto t = std::make_unique<Trainer>(sharedContext(), unbounded, c);
    double first = 0, last = 0;
    for (int i = 0; i < 48; ++i) (i == 0 ? first : last) = t->step(true).loss;
    EXPECT_LT(last, first) << "step opacity " << stepOpacity;
    return t;
  };
  const auto plain = run(0.0f), stretched = run(0.3f);
  EXPECT_LT(*stretched->statistics().meanSamplesPerRay, 0.9 * *plain->statistics().meanSamplesPerRay);
  stretched->save(tmp.file("stretched.vknerf"));
  EXPECT_EQ(Trainer::configOf(tmp.file("stretched.vknerf")).fastModel().stepOpacity, 0.3f);
  const Model m = Model::load(sharedContext(), tmp.file("stretched.vknerf"));
  const RenderedImage a = stretched->model().render(unbounded.cameras[0]), b = m.render(unbounded.cameras[0]);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_EQ(a.samples, b.samples);
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << "value " << i;
}

// A render says how many field samples it shaded: the vanilla model every sample of every pixel,
// the coarse ones and then coarse and fine together through the fine network (the paper's 64 + 192
// of 128 fine); the fast model, which marches only occupied cells and ends rays where they turn
// opaque, some but fewer than its cap per pixel.
TEST_F(TrainerTest, ARenderCountsTheSamplesItShaded) {
  Trainer vanilla(sharedContext(), scene(), tinyConfig());
  const Camera cam = scene().cameras[0];
  const VanillaModel v = tinyConfig().vanillaModel();
  EXPECT_EQ(vanilla.model().render(cam).samples, uint64_t(cam.width) * cam.height * (2 * v.coarseSamples + v.fineSamples));
  TrainConfig c = smallFast();
  Trainer fast(sharedContext(), scene(), c);
  for (int i = 0; i < 64; ++i) fast.step();
  const RenderedImage a = fast.model().render(cam), b = fast.model().render(cam);
  EXPECT_GT(a.samples, 0u);
  EXPECT_LT(a.samples, uint64_t(cam.width) * cam.height * fast.model().config().fastModel().maxSamplesPerRay);
  EXPECT_EQ(a.samples, b.samples);  // a render's own count, not the pipeline's running total
}

// A render asked to profile (RenderSettings::profile) says where its time went, one row per kernel,
// inside the render's wall time, and draws the image an unprofiled render draws.
TEST_F(TrainerTest, AProfiledRenderTimesItsKernelsAndDrawsTheSameImage) {
  TrainConfig c = smallFast();
  Trainer fast(sharedContext(), scene(), c);
  for (int i = 0; i < 32; ++i) fast.step();
  const test::TempDir tmp("trainer");
  const auto path = tmp.file("profiled.vknerf");
  fast.save(path);
  RenderSettings profiled;
  profiled.profile = true;
  const Model plain = Model::load(sharedContext(), path), timed = Model::load(sharedContext(), path, profiled);
  const Camera cam = scene().cameras[0];
  const auto start = std::chrono::steady_clock::now();
  const RenderedImage b = timed.render(cam);
  const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const RenderedImage a = plain.render(cam);
  EXPECT_TRUE(a.kernelMs.empty());
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << "value " << i;
  EXPECT_EQ(a.samples, b.samples);
  std::set<std::string> names;
  double sum = 0;
  for (const auto& [name, ms] : b.kernelMs) {
    EXPECT_TRUE(names.insert(name).second) << name << " has two rows";
    EXPECT_GE(ms, 0.0) << name;
    sum += ms;
  }
  if (b.kernelMs.empty()) return;  // a device whose compute queue has no timestamps times no kernel
  EXPECT_TRUE(std::any_of(names.begin(), names.end(), [](const std::string& n) { return n.rfind("march_", 0) == 0; }))
      << "the march is timed";
  EXPECT_TRUE(names.count("encode_hash")) << "the field is timed";
  EXPECT_GT(sum, 0.0);
  EXPECT_LE(sum, wallMs);  // one queue runs the kernels one after another, inside the render
}

TEST_F(TrainerTest, StepProfileAttributesTheWholeStep) {
  Trainer t(sharedContext(), scene(), tinyConfig());
  t.step();
  t.step(true);
  const StepProfile p = t.lastStepProfile();
  ASSERT_FALSE(p.submissions.empty());
  double sum = p.hostAfterMs, kernels = 0;
  size_t named = 0;
  for (const auto& s : p.submissions) {
    sum += s.hostBeforeMs + s.waitMs;
    for (const auto& [name, ms] : s.kernels) kernels += ms, named += ms >= 0 && !name.empty();
    EXPECT_GE(s.hostBeforeMs, 0.0);
    EXPECT_GE(s.waitMs, 0.0);
  }
  // Host time and waits tile the step: they add up to its wall time (timer reads between them aside).
  EXPECT_GT(p.wallMs, 0.0);
  EXPECT_NEAR(sum, p.wallMs, 0.05 * p.wallMs + 0.05);
  EXPECT_EQ(named, t.lastStepTimings().size());
  if (named) EXPECT_GT(kernels, 0.0);  // devices without compute timestamps time no kernel
}

namespace {
// The sample scene as photos without alpha: composited over white, every pixel opaque.
Dataset opaqueScene() {
  Dataset d = scene();
  for (auto& im : d.images)
    for (size_t p = 0; p + 3 < im.rgba.size(); p += 4) {
      const unsigned a = im.rgba[p + 3];
      for (int k = 0; k < 3; ++k) im.rgba[p + k] = uint8_t((im.rgba[p + k] * a + 255u * (255u - a) + 127u) / 255u);
      im.rgba[p + 3] = 255;
    }
  return d;
}

}  // namespace

// Left open, the sampler follows the photos: the proposal for photos without alpha (its samples a
// ray, at most, in every step), the march for photos with alpha; the model records the choice, so
// its checkpoint (and a run resumed from it) keeps it.
TEST_F(TrainerTest, FastModelSamplesOpaquePhotosWithTheProposal) {
  const test::TempDir tmp("trainer");
  Trainer opaque(sharedContext(), opaqueScene(), smallFast());
  EXPECT_NE(opaque.capacityNote().find("sampler: 24 samples a ray placed by a proposal"), std::string::npos)
      << opaque.capacityNote();
  for (int i = 0; i < 4; ++i) {
    const StepStats st = opaque.step(true);
    if (st.hasLoss) EXPECT_LE(st.samples, 24ull * st.rays);
  }
  opaque.save(tmp.file("opaque.vknerf"));
  const FastModel saved = Trainer::configOf(tmp.file("opaque.vknerf")).fastModel();
  EXPECT_EQ(saved.sampler, Sampler::Proposal);
  EXPECT_EQ(saved.proposalSamples, 24u);

  Trainer withAlpha(sharedContext(), scene(), smallFast());
  EXPECT_NE(withAlpha.capacityNote().find("sampler: the march"), std::string::npos) << withAlpha.capacityNote();
  EXPECT_EQ(withAlpha.model().config().fastModel().sampler, Sampler::March);
  // Its checkpoint holds no proposal samples: a build from before the sampler's key reads the march.
  withAlpha.save(tmp.file("alpha.vknerf"));
  EXPECT_EQ(Trainer::configOf(tmp.file("alpha.vknerf")).fastModel().proposalSamples, 0u);
}

// A render's batch of rays (RenderSettings::raysPerBatch) is a matter of memory and submissions,
// never of the image: 200 rays a batch split the 25x25 view into four (the last of 25), against
// the model's own batch holding it whole. The proposal marches and places each ray's samples alone,
// so its pixels are the same bits. The march renders in segments sized by the batch's sample
// capacity (FastPipeline::doRecordRender): as for LoadedModelRendersLikeTrainer, the over
// operator's roundings (1e-6) and, for a ray that turns opaque inside a segment in one and at its
// end in the other, the light behind T < 1e-4 (at most 1e-4 of a colour <= 1) may differ.
TEST_F(TrainerTest, ARenderIsTheSameWhateverItsBatchOfRays) {
  const test::TempDir tmp("trainer");
  struct Case {
    const char* name;
    Dataset photos;
    float tolerance;
  };
  const Case cases[] = {{"proposal", opaqueScene(), 0.0f}, {"march", scene(), 1e-4f + 1e-5f}};
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    Trainer t(sharedContext(), k.photos, smallFast());
    ASSERT_EQ(t.model().config().fastModel().sampler == Sampler::Proposal, k.tolerance == 0.0f);
    for (int i = 0; i < 24; ++i) t.step();
    const std::string path = tmp.file(std::string(k.name) + ".vknerf");
    t.save(path);
    RenderSettings small;
    small.raysPerBatch = 200;
    const Camera cam = k.photos.cameras[2];
    ASSERT_GT(cam.width * cam.height, 3 * small.raysPerBatch);
    const RenderedImage whole = Model::load(sharedContext(), path).render(cam);
    const RenderedImage split = Model::load(sharedContext(), path, small).render(cam);
    ASSERT_EQ(whole.rgb.size(), split.rgb.size());
    for (size_t i = 0; i < whole.rgb.size(); ++i) ASSERT_NEAR(whole.rgb[i], split.rgb[i], k.tolerance) << "value " << i;
    for (size_t i = 0; i < whole.opacity.size(); ++i)
      ASSERT_NEAR(whole.opacity[i], split.opacity[i], k.tolerance) << "pixel " << i;
    if (k.tolerance == 0.0f) EXPECT_EQ(whole.samples, split.samples);
  }
  RenderSettings tooMany;
  tooMany.raysPerBatch = (1u << 20) + 1;
  Trainer t(sharedContext(), scene(), smallFast());
  t.save(tmp.file("any.vknerf"));
  EXPECT_THROW(Model::load(sharedContext(), tmp.file("any.vknerf"), tooMany), Error);
}

// Photos without alpha get the learned far field, photos with alpha the constant (random in
// training) background; the learned one is saved with the model and renders the same after loading.
TEST_F(TrainerTest, FastModelLearnsTheFarFieldOfOpaquePhotos) {
  const test::TempDir tmp("trainer");
  const Dataset opaque = opaqueScene();
  Trainer t(sharedContext(), opaque, smallFast());
  EXPECT_NE(t.capacityNote().find("far field: learned"), std::string::npos) << t.capacityNote();
  for (int i = 0; i < 8; ++i) t.step();
  t.save(tmp.file("learned.vknerf"));
  EXPECT_EQ(Trainer::configOf(tmp.file("learned.vknerf")).fastModel().farField, FarField::Learned);
  Model m = Model::load(sharedContext(), tmp.file("learned.vknerf"));
  const Camera cam = opaque.cameras[2];
  RenderedImage a = t.model().render(cam), b = m.render(cam);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  // The two pipelines' sample capacities differ (a training step's against a render tile's), and a
  // render's segments after the first are sized by it (FastPipeline::doRecordRender): the over
  // operator's roundings (1e-6) and, for a ray that turns opaque inside a segment of one and at the
  // end of the other's, the light behind T < 1e-4 (at most 1e-4 of a colour <= 1) may differ.
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_NEAR(a.rgb[i], b.rgb[i], 1e-4 + 1e-5) << i;
  // Eight steps have moved the far field off its start (white, clamped to 0.95) where the image is
  // transparent: what the loaded model renders there is what was learnt, not the initial colour.
  double moved = 0;
  size_t transparent = 0;
  for (size_t i = 0; i < a.opacity.size(); ++i)
    if (a.opacity[i] < 1e-2f) ++transparent, moved = std::max(moved, std::fabs(double(a.rgb[3 * i]) - 0.95));
  ASSERT_GT(transparent, 0u);
  EXPECT_GT(moved, 1e-3);

  Trainer withAlpha(sharedContext(), scene(), smallFast());
  EXPECT_NE(withAlpha.capacityNote().find("far field: constant"), std::string::npos) << withAlpha.capacityNote();
  TrainConfig forced = smallFast();
  forced.fastModel().farField = FarField::Learned;
  try {
    Trainer bad(sharedContext(), scene(), forced);
    ADD_FAILURE() << "a learned far field was accepted for photos with alpha";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("far_field"), std::string::npos) << e.what();
  }
}
