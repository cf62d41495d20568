#pragma once
// Model and training configuration. A model is one of two descriptions: VanillaModel (the NeRF
// paper's recipe: positional encoding, coarse + fine MLPs, hierarchical sampling) or FastModel
// (instant-ngp style: hash grid, occupancy grid, a tiny MLP). `TrainConfig::vanilla()` and
// `TrainConfig::fast()` size them for the device: on a CPU device, ones that converge in minutes on
// 100x100 images. Each field is also a row of the table of fields (src/core/config/config_fields.cpp,
// see vknerf/config_fields.h): its checkpoint key, its valid range and its `vknerf train` flag.
#include <array>
#include <cstdint>
#include <string>
#include <variant>

#include "vknerf/context.h"
#include "vknerf/density_activation.h"

namespace vknerf {

struct VanillaModel {
  uint32_t width = 256, depth = 8, skipLayer = 4;  // trunk: depth layers of width, gamma(x) re-injected at skipLayer
  uint32_t posLevels = 10, dirLevels = 4;          // frequency bands: 63 and 27 input dims
  DensityActivation density = DensityActivation::Relu;
  uint32_t coarseSamples = 64, fineSamples = 128;  // per ray
  bool separateFineNetwork = true;                 // paper: two networks; false: one network queried twice
};

// Multiresolution hash grid -> trunk of `depth` x `width` (sigma and a feature) -> with SH(d) ->
// colour layer; samples marched through an occupancy grid.
enum class FarField : uint32_t { Auto = 0, Constant = 1, Learned = 2 };
// "auto", "constant", "learned": the names a checkpoint and `--far-field` use.
const char* farFieldName(FarField f);

// Where a ray's field samples come from. March: every sample the occupancy march finds (front to
// back, until the ray is opaque). Proposal: FastModel::proposalSamples a ray, placed by a small
// proposal density field (nerfacto's estimator). Auto: the Trainer picks the proposal for photos
// without alpha and the march for photos with alpha (docs/real_captures.md, "The proposal by
// default"); a pipeline built from a configuration left open marches.
enum class Sampler : uint32_t { Auto = 0, March = 1, Proposal = 2 };
// "auto", "march", "proposal": the names a checkpoint uses.
const char* samplerName(Sampler s);

struct FastModel {
  // hashLog2Size (table entries per level) and hashGrowth (per-level resolution factor b, which sets
  // the finest resolution N b^(L-1)): 0 = from the dataset, as the Trainer sizes them (TrainConfig::fast).
  uint32_t hashLevels = 16, hashFeatures = 2, hashLog2Size = 19, hashBaseResolution = 16;
  float hashGrowth = 1.5f;
  uint32_t shDegree = 4;              // direction encoding: shDegree^2 coefficients
  // Per-photo appearance embedding (0: none; a multiple of 4, at most 64): a learned vector of this
  // many floats per training photo, fed to the colour network beside the direction encoding, so
  // that exposure and white balance that change from photo to photo are explained there and not by
  // density (nerfacto: 32, instant-ngp: 16). Renders use the mean of the photos' vectors.
  uint32_t appearanceDims = 0;
  uint32_t width = 64, depth = 1;     // instant-ngp: one hidden layer for density, the colour layer after it
  // The features the density network passes to the colour layer (a multiple of 4, at most width;
  // 0: width, as models saved before this field): instant-ngp passes 16 (15 and the density).
  uint32_t featureWidth = 16;
  DensityActivation density = DensityActivation::TruncExp;
  // Occupancy cells per axis of each cascade; 0: from the march steps (src/models/fast/fast_capacity.h).
  uint32_t gridResolution = 64;
  // Nested occupancy cascades (instant-ngp): the outermost covers the scene box, each one inside it
  // half the side about its centre, all at gridResolution; more than one marches with cone steps
  // that grow with distance. 0: from the dataset (1 + ceil(log2(aabb_scale)), 1 without one).
  uint32_t cascades = 0;
  float coneAngle = 1.0f / 256.0f;    // with cascades: step = clamp(t coneAngle, smallest, outermost cell)
  // With cascades: the hash grid spans the box contracted about the inner cube (mip-NeRF 360's
  // contraction with the max norm, as nerfacto's grid), so its levels resolve the inner cube and
  // thin out with distance beyond it; else it spans the box at the inner cube's finest cell size.
  bool contraction = false;
  // Rays start this far in front of the camera (or where they enter the box), in the scene's units,
  // so that no density grows on the lens. 0: from the dataset, as the Trainer sets it (a share of
  // the inner cascade's side, TrainConfig::fast).
  float nearDistance = 0;
  uint32_t marchSteps = 512;          // march step = the inner cascade's diagonal / marchSteps
  uint32_t maxSamplesPerRay = 512;

  // Training
  uint32_t samplesPerBatch = 1u << 16;   // rays per step adapt to march about this many samples; 0: from the march steps (a Trainer sets it)
  uint32_t gridUpdateInterval = 16;      // steps between occupancy updates
  uint32_t gridWarmupSteps = 256;        // until then every cell is re-measured at each update
  // A cell is empty where one march step (the trained, smallest) through it is less opaque than
  // this; higher skips more of a young field's fog (fewer samples per ray). 0: instant-ngp's 1%
  // for the march, 0.1% with the proposal estimator, whose candidates are the march's samples and
  // which does not pay a field sample for each (at 1% the far end of a faint table got none and the
  // far field painted it: docs/real_captures.md). The Trainer sets it (src/models/fast/fast_choices.h).
  float occupancyThreshold = 0;
  // With cascades: a march sample through faint occupied cells stands for several steps, as many
  // as keep it at most this opaque by the grid's densities (fewer samples per ray through a fog);
  // 0: one sample a step, as instant-ngp marches.
  float stepOpacity = 0.0f;
  float hashLearningRateScale = 1.0f;    // the hash table's learning rate relative to the MLP's
  bool earlyTermination = true;          // train only on samples in front of transmittance 1e-4
  // Weight of mip-NeRF 360's distortion loss per ray against the photometric loss (0: none): it
  // gathers each ray's weight into few samples, against fog and floaters.
  float distortionLoss = 0;
  // With the distortion loss: the weight a ray leaves to the far field (or the background) counts
  // as one more interval at its far end, so that a half-transparent surface costs the loss instead
  // of lowering it.
  bool distortionFarField = false;
  // The proposal estimator (nerfacto's), where `sampler` is Proposal: a small density field, the
  // proposal, is evaluated at every sample the march finds, and each ray's field samples, this
  // many, are placed by inverse CDF of the proposal's weights, where the ray's weight lies however
  // thick the fog in front of it. The proposal learns from mip-NeRF 360's interlevel loss (its
  // weights bound the field's), of weight proposalLoss; it is a hash grid of proposalLevels levels
  // and a network 16 wide.
  Sampler sampler = Sampler::Auto;
  uint32_t proposalSamples = 24;
  static constexpr uint32_t kMaxProposalSamples = 1024;  // a ray's most (the configuration's and a render's)
  uint32_t proposalLevels = 5;
  // The proposal's candidates: with cascades, one stands for up to this many march steps through
  // occupied cells (1: every step), evaluated at its middle.
  uint32_t proposalStride = 8;
  // The proposal's weights place a training step's samples in full only after this many steps:
  // from uniform by length at the first step (nerfacto's annealing, over its 1000 steps; 0: from the
  // first step, where fruit at 16 samples learned near-camera floaters: docs/real_captures.md).
  uint32_t proposalAnnealSteps = 1000;
  float proposalLoss = 1.0f;
  // What a ray sees behind the field when it leaves the scene box partly transparent. Learned: a
  // colour per direction at infinity (a hash grid on the unit sphere and a small MLP, trained with
  // the field: the sky, and whatever the box leaves out), for photos without alpha. Constant:
  // TrainConfig::background (random in training when the photos have alpha). Auto: the Trainer picks
  // Learned when every training pixel is opaque, else Constant.
  FarField farField = FarField::Auto;
  // Camera refinement: each training photo's pose gets a learned correction (a rotation and a
  // translation, nerfstudio's SO3xR3), trained with its own Adam rate (following the field's decay)
  // and an L2 penalty of this weight that keeps it near the pose the photo came with. Off by
  // default, and 1e-4 rather than 1e-3: each photo sees a few dozen rays a step, and at 1e-3 Adam's
  // steps on that noise walk exact poses ~0.2 degrees and ~1% off (docs/real_captures.md).
  bool refineCameras = false;
  float cameraLearningRate = 1e-4f;
  float cameraPenalty = 1e-4f;

  // Whether the field's samples are the proposal's (an open sampler marches).
  bool usesProposal() const { return sampler == Sampler::Proposal; }
};

using ModelConfig = std::variant<VanillaModel, FastModel>;

// "vanilla" or "fast": the name a checkpoint and `--config` use.
const char* modelName(const ModelConfig& model);

struct TrainConfig {
  ModelConfig model = VanillaModel{};
  uint32_t raysPerBatch = 1024;  // vanilla: rays per step; fast: the most rays a step may take
  // Exponential decay from learningRate to learningRateFinal over `decaySteps`; the rate holds at
  // learningRateFinal after them.
  float learningRate = 5e-4f, learningRateFinal = 5e-5f;
  uint32_t decaySteps = 250000;
  float beta1 = 0.9f, beta2 = 0.999f, epsilon = 1e-7f;
  // Training rays see a random background colour behind the scene (unless a learned far field gives
  // it): empty space learns zero density, and a ray through an opaque pixel must turn opaque.
  bool randomBackground = true;
  std::array<float, 3> background{1, 1, 1};               // for evaluation and rendering
  uint32_t seed = 0;

  bool isFast() const { return std::holds_alternative<FastModel>(model); }
  // The model's description; throws vknerf::Error when the model is of the other kind.
  VanillaModel& vanillaModel();
  const VanillaModel& vanillaModel() const;
  FastModel& fastModel();
  const FastModel& fastModel() const;

  static TrainConfig vanilla(const Context& ctx);  // sized for the device
  static TrainConfig fast(const Context& ctx);
  // "vanilla" or "fast"; throws vknerf::Error for anything else.
  static TrainConfig named(const std::string& name, const Context& ctx);
  std::string describe() const;                    // one line, printed at the start of training
  // Every field finite and in the range the models accept; throws vknerf::Error naming the first
  // field that is not, under its checkpoint key ("model.coarse_samples must be in [1, 4096], got 0").
  // Used for a configuration built from command-line flags and for one read from a checkpoint.
  void validate() const;
};

}  // namespace vknerf
