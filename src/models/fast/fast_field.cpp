#include "models/fast/fast_field.h"

#include <utility>

#include "vknerf/error.h"

namespace vknerf::models {

namespace {

// A training field runs its forward with the activations kept layer by layer (MlpTuning::fused);
// its occupancy update needs only the density (NerfMlp::recordDensity: the same trunk kernels and
// a small sigma kernel), so no fused inference kernel is compiled for it (~20 s on a fresh lavapipe).
nerf::MlpTuning mlpTuningFor(const Context& ctx, bool training) {
  nerf::MlpTuning t = nerf::MlpTuning::forDevice(ctx);
  if (training && !(t.fused & 2u)) t.fused = 0;
  return t;
}

// The field's table: the dense step while a step touches much of each level's slot, and the skip
// of the entries a step did not touch once a slot holds more than kDenseEntriesPerSample entries per
// sample a step marches (their zero gradients are read, nothing else), so that Adam's cost follows
// the touched entries and not the table's size (docs/performance.md, "Adam on large tables"). Every
// level alike: a coarse level's few entries are all touched every step either way, and the unused
// part of its slot (past its (res + 1)^3 vertices) would cost the dense step as much as a used one.
constexpr uint64_t kDenseEntriesPerSample = 4;
nerf::AdamConfig fieldTableAdamOf(const TrainConfig& config, const nerf::HashGridConfig& grid) {
  nerf::AdamConfig a = tableAdamOf(config);
  if ((uint64_t(1) << grid.log2TableSize) > kDenseEntriesPerSample * config.fastModel().samplesPerBatch)
    a.skipZeroGradientsFrom = 0;
  return a;
}

std::unique_ptr<nerf::Encoding> checked(std::unique_ptr<nerf::Encoding> e) {
  if (!e) throw Error("fast model: no position encoding");
  return e;
}

}  // namespace

nerf::HashGridConfig hashGridConfigFor(const FastModel& m) {
  if (m.hashLog2Size == 0 || m.hashGrowth == 0)
    throw Error("fast model: the hash table size or finest resolution is left to the dataset (0); a Trainer sets it");
  nerf::HashGridConfig c;
  c.levels = m.hashLevels;
  c.featuresPerLevel = m.hashFeatures;
  c.log2TableSize = m.hashLog2Size;
  c.baseResolution = m.hashBaseResolution;
  c.growthFactor = m.hashGrowth;
  if (m.contraction && m.cascades > 1) c.contraction = 1u << (m.cascades - 1);
  return c;
}

// Every table entry takes an Adam step, also one no sample touched (its momentum carries it on).
// instant-ngp skips those (AdamConfig::skipZeroGradientsFrom) to save time where the gradients are
// sparse; at these tables (2^15 entries a level, ~16k samples a step) they are not: the skip saved
// about 1 ms of a ~65 ms step, and held-out PSNR in equal time was the same or better without it
// (docs/performance.md: +0.5 dB on the sample scene at 60 s and on an 800x800 object scene at 120 s).
nerf::AdamConfig tableAdamOf(const TrainConfig& config) {
  return adamConfigOf(config, config.fastModel().hashLearningRateScale);
}

PositionEncoding hashGridPosition(Context& ctx, const TrainConfig& config, bool training) {
  const nerf::HashGridConfig grid = hashGridConfigFor(config.fastModel());
  return {std::make_unique<nerf::HashEncoding>(ctx, grid),
          training ? std::optional(fieldTableAdamOf(config, grid)) : std::nullopt};
}

FastField::FastField(Context& ctx, const TrainConfig& config, bool training, uint32_t capacity, uint32_t densityRows,
                     PositionEncoding position, const std::string& stateName)
    : position_(checked(std::move(position.encoding))),
      sh_(ctx, config.fastModel().shDegree),
      mlp_(ctx, nerf::MlpConfig{.depth = config.fastModel().depth,
                                .width = config.fastModel().width,
                                .skipLayer = 0,  // the encoded features need no re-injection through a shallow trunk
                                .posDims = position_->outputDims(),
                                // (an appearance vector enters as a bias on the colour layer, FieldRows::colourBias)
                                .dirDims = sh_.outputDims(),
                                .density = config.fastModel().density,
                                .seed = config.seed,
                                .featureWidth = config.fastModel().featureWidth},
           mlpTuningFor(ctx, training)),
      encoding_(ctx, stateName + "encoding", position_->initialParameters(config.seed), position.adam,
                position_->trainedParts()),
      network_(ctx, stateName + "mlp", mlp_.initialParameters(), training ? std::optional(adamConfigOf(config)) : std::nullopt),
      batch_(ctx, mlp_, capacity, training) {
  if (training) dEncoded_ = gpu::Buffer::zeros(ctx, VkDeviceSize(capacity) * mlp_.posStride() * 4, "the encoding gradients");
  if (densityRows)
    densityFeatures_ = gpu::Buffer::zeros(ctx, VkDeviceSize(densityRows) * mlp_.posStride() * 4,
                                          "the occupancy update's position encodings");
}

void FastField::recordForward(gpu::Recorder& rec, const FieldRows& rows, bool keep) {
  FieldBatch& f = batch_;
  position_->recordForward(rec, {rows.count, f.positions, f.posFeatures, mlp_.posStride(), 0, rows.limit, rows.gather},
                           encoding_.params());
  nerf::NerfRows mlpRows = f.mlpRows(rows.count);
  mlpRows.rowLimit = rows.limit;
  mlpRows.colourBias = rows.colourBias;
  mlpRows.rowGather = rows.gather;
  mlpRows.densityOnly = rows.densityOnly;
  // The direction's encoding only where the network reads it.
  if (!rows.densityOnly)
    sh_.recordForward(rec, {rows.count, f.directions, f.dirFeatures, mlp_.dirStride(), 0, rows.limit, rows.gather});
  mlp_.recordForward(rec, mlpRows, network_.params(), keep ? f.workspace.get() : nullptr);
}

void FastField::recordDensity(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& positions,
                              const gpu::BufferRange& density) {
  // The density alone: the colour branch would cost more than the trunk and is not looked at.
  position_->recordForward(rec, {count, positions, densityFeatures_, mlp_.posStride(), 0}, encoding_.params());
  mlp_.recordDensity(rec, count, network_.params(), densityFeatures_, density);
}

void FastField::recordBackward(gpu::Recorder& rec, const FieldBackwardRows& rows, const FieldGradientTargets& targets) {
  FieldBatch& f = batch_;
  nerf::NerfGradients gradients{f.dField, network_.grads(), gpu::BufferRange(dEncoded_)};
  gradients.rowGather = rows.gather;
  gradients.dColour = targets.dColour;
  nerf::NerfRows mlpRows = f.mlpRows(rows.count);
  mlpRows.rowLimit = rows.limit;
  mlpRows.densityOnly = rows.densityOnly;
  mlp_.recordBackward(rec, mlpRows, network_.params(), gradients, *f.workspace);
  // The encoding's backward also gives dL/dp where it is asked for, from its parameters before
  // their optimizer step.
  const nerf::EncodedRows encoded{rows.count, rows.positions, dEncoded_, mlp_.posStride(), 0, rows.limit};
  position_->recordBackward(rec, encoded, {encoding_.params(), encoding_.grads(), targets.dPosition});
}

}  // namespace vknerf::models
