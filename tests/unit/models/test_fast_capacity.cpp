// The fast model's capacity from the data (src/models/fast/fast_capacity.h): the finest hash resolution from
// the cameras' pixel footprint over the inner cube, the table from the training pixels and the box
// in view, where rays start, the caps of a CPU device, and explicit settings kept; and the occupancy
// threshold from the sampler (src/models/fast/fast_choices.h).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "models/fast/fast_capacity.h"
#include "models/fast/fast_choices.h"
#include "models/fast/fast_field.h"
#include "vknerf/camera.h"
#include "vknerf/dataset.h"

using namespace vknerf;

namespace {

// `views` cameras of width x height pixels on a circle of `radius` around a unit box, looking at
// its centre, with black images of their size.
Dataset ring(uint32_t views, uint32_t width, uint32_t height, float fovX, float radius, float boxHalf = 1) {
  Dataset d;
  for (uint32_t i = 0; i < views; ++i) {
    const float a = 6.2831853f * float(i) / float(views);
    d.cameras.push_back(pinholeFromFov(width, height, fovX,
                                       lookAt({radius * std::cos(a), radius * std::sin(a), 0.5f}, {0, 0, 0}, {0, 0, 1})));
    d.images.push_back({width, height, std::vector<uint8_t>(size_t(width) * height * 4, 0)});
  }
  d.bounds = {{-boxHalf, -boxHalf, -boxHalf}, {boxHalf, boxHalf, boxHalf}};
  return d;
}

FastModel openModel() {
  FastModel m;
  m.hashLevels = 8;
  m.hashFeatures = 2;
  m.hashBaseResolution = 16;
  m.hashLog2Size = 0;
  m.hashGrowth = 0;
  return m;
}

double finestOf(const FastModel& m) {
  return m.hashBaseResolution * std::pow(double(m.hashGrowth), double(m.hashLevels - 1));
}

// The open model with `marchSteps` (0: open, from the footprint) and what `set` changes, resolved
// for 4 views of 400x400 at `fovX` degrees on a circle of radius 4; with the note it printed.
struct Resolved {
  FastModel m;
  std::string note;
};
template <class Set>
Resolved resolvedAt(uint32_t marchSteps, float fovX, bool cpu, Set set) {
  Resolved r{openModel(), {}};
  r.m.marchSteps = marchSteps;
  r.m.maxSamplesPerRay = 0;
  set(r.m);
  r.note = models::resolveFastCapacity(r.m, ring(4, 400, 400, fovX, 4), cpu);
  return r;
}

}  // namespace

// Two cells per pixel footprint over the box: focal f = (w/2) / tan(fov/2), footprint = distance / f,
// N = 2 * extent / footprint, rounded up to a power of two.
TEST(FastCapacity, FinestResolutionResolvesThePixelFootprint) {
  const Dataset d = ring(8, 400, 400, 60, 4);
  FastModel m = openModel();
  const std::string note = models::resolveFastCapacity(m, d, false);
  const double focal = 200 / std::tan(30 * M_PI / 180), distance = std::sqrt(16 + 0.25);
  const double wanted = 2 * 2 / (distance / focal);  // ~327
  EXPECT_NEAR(finestOf(m), std::exp2(std::ceil(std::log2(wanted))), 1e-2);
  EXPECT_NE(note.find("finest 512"), std::string::npos) << note;
  // Twice the pixels across: twice the resolution.
  FastModel sharper = openModel();
  models::resolveFastCapacity(sharper, ring(8, 800, 800, 60, 4), false);
  EXPECT_NEAR(finestOf(sharper), 2 * finestOf(m), 1e-2);
}

// The table: at most a parameter per training pixel (levels x features per entry), within 2^15..2^19.
TEST(FastCapacity, TableFollowsTheTrainingPixels) {
  FastModel few = openModel(), many = openModel();
  models::resolveFastCapacity(few, ring(4, 100, 100, 60, 4), false);  // 40k pixels: the floor, 2^15
  EXPECT_EQ(few.hashLog2Size, 15u);
  models::resolveFastCapacity(many, ring(100, 800, 800, 60, 4), false);  // 64M pixels / 16: 2^21, capped
  EXPECT_EQ(many.hashLog2Size, 19u);
  FastModel mid = openModel();
  models::resolveFastCapacity(mid, ring(16, 256, 256, 60, 4), false);  // 1M pixels / 16 = 2^16
  EXPECT_EQ(mid.hashLog2Size, 16u);
}

// A CPU device: the table at most 2^17 and the finest level at most 512, whatever the data asks for.
TEST(FastCapacity, CpuDeviceCapsTheModel) {
  FastModel m = openModel();
  const std::string note = models::resolveFastCapacity(m, ring(100, 800, 800, 60, 4), true);
  EXPECT_EQ(m.hashLog2Size, 17u);
  EXPECT_NEAR(finestOf(m), 512, 1e-2);
  EXPECT_NE(note.find("at most 512 on a CPU"), std::string::npos) << note;
}

// What the configuration sets is kept, and only what it leaves open is filled.
TEST(FastCapacity, ExplicitSettingsWin) {
  FastModel m = openModel();
  m.hashLog2Size = 17;
  m.hashGrowth = 1.5f;
  const FastModel before = m;
  models::resolveFastCapacity(m, ring(100, 800, 800, 60, 4), false);
  EXPECT_EQ(m.hashLog2Size, before.hashLog2Size);
  EXPECT_EQ(m.hashGrowth, before.hashGrowth);
  FastModel growthOnly = openModel();
  growthOnly.hashGrowth = 1.5f;
  models::resolveFastCapacity(growthOnly, ring(100, 800, 800, 60, 4), false);
  EXPECT_EQ(growthOnly.hashGrowth, 1.5f);
  EXPECT_EQ(growthOnly.hashLog2Size, 19u);
}

// Cascades (aabb_scale 4: a box 4 times the inner cube's side): the inner cube keeps the resolution
// a box of its own size would get, and the grid spans the whole box at that cell size with one level
// more per doubling; on a CPU the cap holds for the inner cube.
TEST(FastCapacity, CascadesKeepTheInnerCubesDetail) {
  FastModel alone = openModel();
  models::resolveFastCapacity(alone, ring(8, 400, 400, 60, 4), false);
  FastModel cascaded = openModel();
  cascaded.cascades = 3;
  const std::string note = models::resolveFastCapacity(cascaded, ring(8, 400, 400, 60, 4, 4), false);
  EXPECT_EQ(cascaded.hashLevels, alone.hashLevels + 2);
  EXPECT_NEAR(finestOf(cascaded), 4 * finestOf(alone), 1e-2 * finestOf(alone)) << note;
  FastModel cpu = openModel();
  cpu.cascades = 3;
  models::resolveFastCapacity(cpu, ring(100, 800, 800, 60, 4, 4), true);
  EXPECT_NEAR(finestOf(cpu), 4 * 512, 1e-1);
}

// Contracted, the grid spans twice the inner cube whatever the cascades: one level more than the
// inner cube alone at twice its finest resolution; and the encoding contracts about the inner cube
// (S = 2^(cascades - 1)), only where there are cascades.
TEST(FastCapacity, AContractedGridSpansTwiceTheInnerCube) {
  FastModel alone = openModel();
  models::resolveFastCapacity(alone, ring(8, 400, 400, 60, 4), false);
  FastModel contracted = openModel();
  contracted.cascades = 4, contracted.contraction = true;
  const std::string note = models::resolveFastCapacity(contracted, ring(8, 400, 400, 60, 4, 8), false);
  EXPECT_EQ(contracted.hashLevels, alone.hashLevels + 1) << note;
  EXPECT_NEAR(finestOf(contracted), 2 * finestOf(alone), 1e-2 * finestOf(alone)) << note;
  EXPECT_NE(note.find("contracted box"), std::string::npos) << note;
  EXPECT_EQ(models::hashGridConfigFor(contracted).contraction, 8u);
  FastModel single = openModel();
  single.contraction = true;
  models::resolveFastCapacity(single, ring(8, 400, 400, 60, 4), false);
  EXPECT_EQ(single.hashLevels, alone.hashLevels);
  EXPECT_EQ(models::hashGridConfigFor(single).contraction, 0u);
}

// The march step, left open: the power of two nearest 4 pixel footprints of the typical camera over
// the inner cube's diagonal, within 128..1024 (..512 on a CPU), and as many samples per ray at most.
// A ring at distance sqrt(16.25) around a box of side 2: steps = 2 sqrt(3) focal / (4 distance),
// ~0.215 focal, with focal = 200 / tan(fov / 2) for 400-pixel photos.
TEST(FastCapacity, MarchStepFollowsThePixelFootprint) {
  auto stepsFor = [](float fovX, bool cpu, uint32_t cascades = 1, float boxHalf = 1) {
    FastModel m = openModel();
    m.marchSteps = m.maxSamplesPerRay = 0;
    m.cascades = cascades;
    const std::string note = models::resolveFastCapacity(m, ring(4, 400, 400, fovX, 4, boxHalf), cpu);
    EXPECT_EQ(m.maxSamplesPerRay, m.marchSteps);
    EXPECT_NE(note.find("march: " + std::to_string(m.marchSteps) + " steps"), std::string::npos) << note;
    return m.marchSteps;
  };
  auto wanted = [](float fovX) {
    const double focal = 200 / std::tan(fovX / 2 * M_PI / 180), distance = std::sqrt(16.25);
    return 2 * std::sqrt(3.0) / (4 * distance / focal);
  };
  EXPECT_NEAR(wanted(60), 74.4, 0.1);  // coarse pixels: the floor
  EXPECT_EQ(stepsFor(60, true), 128u);
  EXPECT_NEAR(wanted(17.5f), 279, 1);  // 2^8.1: 256, not the next power up
  EXPECT_EQ(stepsFor(17.5f, true), 256u);
  EXPECT_NEAR(wanted(13), 377, 1);  // 2^8.56: 512
  EXPECT_EQ(stepsFor(13, false), 512u);
  EXPECT_NEAR(wanted(4.6f), 1069, 1);  // the ceiling: 1024 on a GPU, 512 on a CPU
  EXPECT_EQ(stepsFor(4.6f, false), 1024u);
  EXPECT_EQ(stepsFor(4.6f, true), 512u);
  // Cascades: the inner cube's diagonal, whatever the box around it.
  EXPECT_EQ(stepsFor(17.5f, true, 3, 4), 256u);
  // What the configuration sets is kept; a cap left open follows the steps.
  auto resolved = [](uint32_t marchSteps, uint32_t maxSamplesPerRay, float fovX) {
    FastModel m = openModel();
    m.marchSteps = marchSteps;
    m.maxSamplesPerRay = maxSamplesPerRay;
    models::resolveFastCapacity(m, ring(4, 400, 400, fovX, 4), true);
    return std::pair{m.marchSteps, m.maxSamplesPerRay};
  };
  EXPECT_EQ(resolved(200, 0, 4.6f), std::pair(200u, 200u));
  EXPECT_EQ(resolved(0, 64, 17.5f), std::pair(256u, 64u));
}

// Rays start 5% of the inner cube's side in front of the camera: the same share in any units (the
// box 10 times larger, 10 times the distance), the inner cube with cascades; one set is kept.
TEST(FastCapacity, NearDistanceFollowsTheInnerCube) {
  FastModel m = openModel();
  models::resolveFastCapacity(m, ring(8, 100, 100, 60, 4), true);
  EXPECT_FLOAT_EQ(m.nearDistance, 0.05f * 2);
  FastModel large = openModel();
  models::resolveFastCapacity(large, ring(8, 100, 100, 60, 40, 10), true);
  EXPECT_FLOAT_EQ(large.nearDistance, 0.05f * 20);
  FastModel cascaded = openModel();
  cascaded.cascades = 3;
  models::resolveFastCapacity(cascaded, ring(8, 100, 100, 60, 4, 4), true);
  EXPECT_FLOAT_EQ(cascaded.nearDistance, 0.05f * 2);
  FastModel set = openModel();
  set.nearDistance = 0.3f;
  models::resolveFastCapacity(set, ring(8, 100, 100, 60, 4), true);
  EXPECT_EQ(set.nearDistance, 0.3f);
}

// A step's samples, left open: 2^14 whatever the march steps (resolved first, from the footprint,
// or as configured), and the note says so; a set value is kept.
TEST(FastCapacity, SamplesPerStepAreTheSameAtEveryMarch) {
  auto samplesFor = [](uint32_t marchSteps, float fovX, uint32_t samplesPerBatch = 0) {
    const Resolved r = resolvedAt(marchSteps, fovX, true, [&](FastModel& m) { m.samplesPerBatch = samplesPerBatch; });
    if (samplesPerBatch == 0)
      EXPECT_NE(r.note.find("about " + std::to_string(r.m.samplesPerBatch) + " marched samples (whatever the " +
                            std::to_string(r.m.marchSteps) + " march steps"),
                std::string::npos)
          << r.note;
    else
      EXPECT_EQ(r.note.find("marched samples"), std::string::npos) << r.note;
    return std::pair{r.m.marchSteps, r.m.samplesPerBatch};
  };
  EXPECT_EQ(samplesFor(0, 60), std::pair(128u, 1u << 14));     // coarse pixels: 128 steps
  EXPECT_EQ(samplesFor(0, 17.5f), std::pair(256u, 1u << 14));  // 256 steps (flower, the 800x800 object)
  EXPECT_EQ(samplesFor(0, 4.6f), std::pair(512u, 1u << 14));   // the CPU's finest march
  EXPECT_EQ(samplesFor(100, 60), std::pair(100u, 1u << 14));   // under 128 steps
  EXPECT_EQ(samplesFor(0, 17.5f, 5000), std::pair(256u, 5000u));
}

// With the proposal estimator a step's samples, left open, are 2^13 (its rays take its few samples
// each), and the note says how many rays that is; a set value is kept.
TEST(FastCapacity, TheProposalTakesSmallerSteps) {
  const Resolved open = resolvedAt(0, 60, true, [](FastModel& m) { m.sampler = Sampler::Proposal, m.samplesPerBatch = 0; });
  EXPECT_EQ(open.m.samplesPerBatch, 1u << 13);
  EXPECT_NE(open.note.find("about 8192 field samples, 341 rays at the proposal's 24"), std::string::npos) << open.note;
  const Resolved set = resolvedAt(0, 60, true, [](FastModel& m) { m.sampler = Sampler::Proposal, m.samplesPerBatch = 1u << 14; });
  EXPECT_EQ(set.m.samplesPerBatch, 1u << 14);
  EXPECT_EQ(set.note.find("field samples"), std::string::npos) << set.note;
}

// The occupancy threshold, left open (0): instant-ngp's 1% for the march, 0.1% with the proposal
// (whose candidates must reach faint cells), written into the model so that a checkpoint records
// it, and said in the note with the proposal; a set value is kept either way.
TEST(FastChoices, OccupancyThresholdFollowsTheSampler) {
  auto chosen = [](Sampler sampler, float threshold) {
    FastModel m = openModel();
    m.sampler = sampler;
    m.occupancyThreshold = threshold;
    const bool proposal = sampler == Sampler::Proposal;
    EXPECT_EQ(models::occupancyThresholdOf(m), threshold > 0 ? threshold : proposal ? 0.001f : 0.01f);
    const std::string note = models::chooseFastModel(m, ring(4, 100, 100, 60, 4), true, false);
    EXPECT_EQ(note.find("occupancy threshold") != std::string::npos, proposal && threshold == 0) << note;
    return m.occupancyThreshold;
  };
  EXPECT_FLOAT_EQ(chosen(Sampler::March, 0), 0.01f);
  EXPECT_FLOAT_EQ(chosen(Sampler::Proposal, 0), 0.001f);
  EXPECT_FLOAT_EQ(chosen(Sampler::March, 0.05f), 0.05f);
  EXPECT_FLOAT_EQ(chosen(Sampler::Proposal, 0.05f), 0.05f);
}

// The sampler, left open: the proposal for opaque photos, the march where some pixel has alpha;
// written into the model (a checkpoint records it, so a resumed model keeps it), said in the note,
// and the choices that follow it (the step's samples, the threshold) follow the one made. A set
// sampler is kept whatever the photos.
TEST(FastChoices, TheSamplerFollowsThePhotosAlpha) {
  auto chosen = [](Sampler sampler, bool transparentPixels) {
    FastModel m = openModel();
    m.sampler = sampler;
    m.samplesPerBatch = 0;
    const std::string note = models::chooseFastModel(m, ring(4, 100, 100, 60, 4), true, transparentPixels);
    EXPECT_EQ(note.find("sampler:") != std::string::npos, sampler == Sampler::Auto) << note;
    EXPECT_EQ(m.samplesPerBatch, m.usesProposal() ? 1u << 13 : 1u << 14);
    EXPECT_FLOAT_EQ(m.occupancyThreshold, m.usesProposal() ? 0.001f : 0.01f);
    // A march's model holds no proposal samples (a build from before the sampler's key reads it right).
    EXPECT_EQ(m.proposalSamples, m.usesProposal() ? 24u : 0u);
    return m.sampler;
  };
  EXPECT_EQ(chosen(Sampler::Auto, false), Sampler::Proposal);
  EXPECT_EQ(chosen(Sampler::Auto, true), Sampler::March);
  EXPECT_EQ(chosen(Sampler::March, false), Sampler::March);
  EXPECT_EQ(chosen(Sampler::Proposal, true), Sampler::Proposal);
  EXPECT_EQ(models::samplerFor(false), Sampler::Proposal);
  // Left open with no proposal samples: the march, whatever the photos.
  FastModel none = openModel();
  none.proposalSamples = 0;
  const std::string note = models::chooseFastModel(none, ring(4, 100, 100, 60, 4), true, false);
  EXPECT_EQ(none.sampler, Sampler::March);
  EXPECT_NE(note.find("sampler: the march (no proposal samples asked for)"), std::string::npos) << note;
}

// The occupancy grid, left open: half the march steps per axis (the steps resolved first, or as
// configured), within 64..128 on a CPU (64 with the proposal sampler) and 64..256 elsewhere; a set
// value is kept.
TEST(FastCapacity, OccupancyGridFollowsTheMarchSteps) {
  auto gridFor = [](uint32_t marchSteps, float fovX, bool cpu, uint32_t gridResolution = 0,
                    Sampler sampler = Sampler::March) {
    const Resolved r = resolvedAt(marchSteps, fovX, cpu, [&](FastModel& m) {
      m.gridResolution = gridResolution;
      m.sampler = sampler;
    });
    if (gridResolution == 0)
      EXPECT_NE(r.note.find("occupancy grid: " + std::to_string(r.m.gridResolution) + "^3"), std::string::npos) << r.note;
    else
      EXPECT_EQ(r.note.find("occupancy grid"), std::string::npos) << r.note;
    return std::pair{r.m.marchSteps, r.m.gridResolution};
  };
  EXPECT_EQ(gridFor(0, 60, true), std::pair(128u, 64u));      // coarse pixels: 128 steps, 64^3
  EXPECT_EQ(gridFor(0, 17.5f, true), std::pair(256u, 128u));  // the 800x800 object's 256 steps
  EXPECT_EQ(gridFor(0, 4.6f, true), std::pair(512u, 128u));   // the CPU's cap
  EXPECT_EQ(gridFor(0, 4.6f, false), std::pair(1024u, 256u));
  EXPECT_EQ(gridFor(64, 60, true), std::pair(64u, 64u));      // a coarser march: the floor
  EXPECT_EQ(gridFor(0, 17.5f, true, 32), std::pair(256u, 32u));
  // With the proposal: 64^3 on a CPU whatever the march (flower's and the full-size cup's 256 steps),
  // a GPU's rule unchanged; a set value kept.
  EXPECT_EQ(gridFor(0, 17.5f, true, 0, Sampler::Proposal), std::pair(256u, 64u));
  EXPECT_EQ(gridFor(0, 4.6f, true, 0, Sampler::Proposal), std::pair(512u, 64u));
  EXPECT_EQ(gridFor(0, 4.6f, false, 0, Sampler::Proposal), std::pair(1024u, 256u));
  EXPECT_EQ(gridFor(0, 17.5f, true, 128, Sampler::Proposal), std::pair(256u, 128u));
}
