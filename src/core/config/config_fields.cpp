// The table of configuration fields (vknerf/config_fields.h): a new field of config.h is one row
// here. Rows are in the order validate() checks them and `vknerf train --help` lists their flags.
// Keys are those of the first checkpoint format (the fast model's training fields at the top level);
// a key added since says what a checkpoint without it reads.
#include "vknerf/config_fields.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/config/config_range.h"
#include "vknerf/error.h"

namespace vknerf {
namespace {

using Type = ConfigValueType;
using Check = ConfigFlag::Check;

// A member's value as the table holds it, and back.
ConfigValue valueOf(uint32_t v) { return v; }
ConfigValue valueOf(float v) { return v; }
ConfigValue valueOf(bool v) { return v; }
ConfigValue valueOf(DensityActivation v) { return uint32_t(v); }
ConfigValue valueOf(FarField v) { return std::string(farFieldName(v)); }
ConfigValue valueOf(Sampler v) { return std::string(samplerName(v)); }
ConfigValue valueOf(const std::array<float, 3>& v) { return v; }

void assign(uint32_t& m, const ConfigValue& v) { m = std::get<uint32_t>(v); }
void assign(float& m, const ConfigValue& v) { m = std::get<float>(v); }
void assign(bool& m, const ConfigValue& v) { m = std::get<bool>(v); }
void assign(DensityActivation& m, const ConfigValue& v) { m = DensityActivation(std::get<uint32_t>(v)); }
void assign(std::array<float, 3>& m, const ConfigValue& v) { m = std::get<std::array<float, 3>>(v); }

// The enumerations a configuration names: every value, and each one's name.
constexpr std::array kFarFields{FarField::Auto, FarField::Constant, FarField::Learned};
constexpr std::array kSamplers{Sampler::Auto, Sampler::March, Sampler::Proposal};
const auto& valuesOf(FarField) { return kFarFields; }
const auto& valuesOf(Sampler) { return kSamplers; }

template <class E, class = decltype(valuesOf(E{}))>
void assign(E& m, const ConfigValue& v) {
  for (E e : valuesOf(E{}))
    if (std::get<std::string>(v) == std::get<std::string>(valueOf(e))) m = e;
}

template <class E, class = decltype(valuesOf(E{}))>
std::vector<std::string> choicesOf(E) {
  std::vector<std::string> names;
  for (E e : valuesOf(E{})) names.push_back(std::get<std::string>(valueOf(e)));
  return names;
}
std::vector<std::string> choicesOf(...) { return {}; }

// The struct a member belongs to, inside a configuration.
TrainConfig& ownerOf(TrainConfig& c, TrainConfig*) { return c; }
VanillaModel& ownerOf(TrainConfig& c, VanillaModel*) { return c.vanillaModel(); }
FastModel& ownerOf(TrainConfig& c, FastModel*) { return c.fastModel(); }
const TrainConfig& ownerOf(const TrainConfig& c, TrainConfig*) { return c; }
const VanillaModel& ownerOf(const TrainConfig& c, VanillaModel*) { return c.vanillaModel(); }
const FastModel& ownerOf(const TrainConfig& c, FastModel*) { return c.fastModel(); }

// "auto, constant or learned"
std::string spelledOut(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return s;
}

// One row, written as a chain: field(...).range(...).flag(...).
struct Row {
  ConfigField f;

  Row& range(double lo, double hi) { return f.range = ConfigRange{lo, hi}, *this; }
  Row& openLow() { return f.range->openLow = true, *this; }
  Row& zeroIsAuto() { return f.range->zeroIsAuto = true, *this; }
  Row& multipleOf(uint32_t m) { return f.range->multipleOf = m, *this; }
  Row& check(std::function<void(const TrainConfig&)> c) { return f.check = std::move(c), *this; }
  // A key added after the first checkpoint format: missing, it reads the field's default, or
  // `legacy` when models saved before it had something else.
  Row& addedLater() { return f.missing = MissingKey::Default, *this; }
  Row& addedLater(ConfigValue legacy) { return f.missing = MissingKey::Legacy, f.legacy = std::move(legacy), *this; }
  // Added later, where what models saved before it had follows from their other keys (those of the
  // rows above it).
  Row& addedLaterFrom(std::function<ConfigValue(const TrainConfig&)> legacy) {
    return f.missing = MissingKey::Derived, f.derivedLegacy = std::move(legacy), *this;
  }

  Row& flag(const char* name, const char* help) {
    f.flag.name = name, f.flag.help = help, f.flag.type = f.type;
    if (!f.choices.empty()) f.flag.check = Check::Choice;
    return *this;
  }
  Row& flagRange(double lo, double hi) { return f.flag.check = Check::Range, f.flag.lo = lo, f.flag.hi = hi, *this; }
  Row& flagPositive() { return f.flag.check = Check::Positive, *this; }
  Row& flagTakes(Type t) { return f.flag.type = t, *this; }
  Row& flagApplies(std::function<void(TrainConfig&, const ConfigValue&)> a) { return f.flag.apply = std::move(a), *this; }

  operator ConfigField() const { return f; }
};

template <class T, class Owner>
Row member(const char* key, bool inModel, T Owner::*m) {
  Row r;
  r.f.key = key;
  r.f.inModel = inModel;
  r.f.vanilla = !std::is_same_v<Owner, FastModel>;
  r.f.fast = !std::is_same_v<Owner, VanillaModel>;
  r.f.type = Type(valueOf(T{}).index());
  r.f.choices = choicesOf(T{});
  r.f.get = [m](const TrainConfig& c) { return valueOf(ownerOf(c, (Owner*)nullptr).*m); };
  // A name outside the choices is an error naming the key, as a checkpoint's "painted" far field.
  r.f.set = [m, path = r.f.path(), choices = r.f.choices](TrainConfig& c, const ConfigValue& v) {
    if (const std::string* name = std::get_if<std::string>(&v); name && std::find(choices.begin(), choices.end(), *name) == choices.end())
      throw Error(path + " must be " + spelledOut(choices) + ", got \"" + *name + "\"");
    assign(ownerOf(c, (Owner*)nullptr).*m, v);
  };
  return r;
}

// TrainConfig's own fields, at the top level.
template <class T>
Row top(const char* key, T TrainConfig::*m) { return member(key, false, m); }
// A model's field under "model"; one of the fast model's training fields at the top level.
template <class T, class Model>
Row model(const char* key, T Model::*m) { return member(key, true, m); }
template <class T>
Row fastTop(const char* key, T FastModel::*m) { return member(key, false, m); }
// A field both models have, under one key.
template <class T>
Row model(const char* key, T VanillaModel::*v, T FastModel::*f) {
  Row r = member(key, true, v);
  const Row fast = member(key, true, f);
  r.f.fast = true;
  r.f.get = [v = r.f.get, f = fast.f.get](const TrainConfig& c) { return c.isFast() ? f(c) : v(c); };
  r.f.set = [v = r.f.set, f = fast.f.set](TrainConfig& c, const ConfigValue& x) { c.isFast() ? f(c, x) : v(c, x); };
  return r;
}

// Keep N_min and the finest resolution `finest`, and spread the levels geometrically between them.
void spreadHashLevels(FastModel& f, double finest) {
  f.hashGrowth = f.hashLevels > 1 ? float(std::pow(finest / f.hashBaseResolution, 1.0 / (f.hashLevels - 1))) : 1.0f;
}

std::vector<ConfigField> table() {
  return {
      top("rays_per_batch", &TrainConfig::raysPerBatch).range(1, 1u << 26)
          .flag("--rays", "Rays per batch (default: sized for the device)")
          .flagApplies([](TrainConfig& c, const ConfigValue& v) {  // 0: sized for the device, as without the flag
            if (std::get<uint32_t>(v)) c.raysPerBatch = std::get<uint32_t>(v);
          }),
      model("width", &VanillaModel::width, &FastModel::width).range(8, 4096).multipleOf(8)
          .flag("--width", "MLP width (multiple of 8)").flagRange(8, 1024),
      model("depth", &VanillaModel::depth, &FastModel::depth).range(1, 64)
          .flag("--depth", "MLP trunk layers").flagRange(2, 16)
          .flagApplies([](TrainConfig& c, const ConfigValue& v) {
            const uint32_t depth = std::get<uint32_t>(v);
            if (auto* m = std::get_if<VanillaModel>(&c.model))
              m->depth = depth, m->skipLayer = std::min(m->skipLayer, depth - 1);  // the skip stays inside the trunk
            else
              c.fastModel().depth = depth;
          }),
      model("skip_layer", &VanillaModel::skipLayer).check([](const TrainConfig& c) {
        const VanillaModel& m = c.vanillaModel();
        if (m.skipLayer >= m.depth)
          throw Error("model.skip_layer must be below model.depth (" + std::to_string(m.depth) + "), got " +
                      std::to_string(m.skipLayer));
      }),
      model("pos_levels", &VanillaModel::posLevels).range(1, 32),
      model("dir_levels", &VanillaModel::dirLevels).range(1, 32),
      model("density", &VanillaModel::density, &FastModel::density).check([](const TrainConfig& c) {
        const DensityActivation d = c.isFast() ? c.fastModel().density : c.vanillaModel().density;
        if (uint32_t(d) > uint32_t(DensityActivation::Softplus))
          throw Error("model.density is not a known activation (0 relu, 1 trunc_exp, 2 softplus), got " +
                      std::to_string(uint32_t(d)));
      }),
      model("coarse_samples", &VanillaModel::coarseSamples).range(1, 4096)
          .flag("--coarse", "vanilla: stratified samples per ray").flagRange(1, 1024),
      model("fine_samples", &VanillaModel::fineSamples).range(0, 4096)
          .flag("--fine", "vanilla: importance samples per ray").flagRange(1, 1024),
      model("separate_fine", &VanillaModel::separateFineNetwork),

      // Models saved before the feature width was a setting passed the whole trunk width (0).
      model("feature_width", &FastModel::featureWidth).addedLater(0u)
          .check([](const TrainConfig& c) {
            const FastModel& m = c.fastModel();
            if (m.featureWidth == 0) return;  // the whole width
            checkCount("model.feature_width", m.featureWidth, 4, m.width);
            if (m.featureWidth % 4)
              throw Error("model.feature_width must be a multiple of 4, got " + std::to_string(m.featureWidth));
          })
          .flag("--feature-width", "fast: features the density layer passes to the colour layer (multiple of 4, at most --width)")
          .flagRange(4, 1024),
      model("hash_levels", &FastModel::hashLevels).addedLater().range(1, 32)
          .flag("--hash-levels", "fast: hash grid levels").flagRange(1, 24)
          .flagApplies([](TrainConfig& c, const ConfigValue& v) {
            FastModel& f = c.fastModel();
            f.hashLevels = std::get<uint32_t>(v);
            // A growth left to the dataset (0) stays so: the finest resolution it picks is then spread
            // over the levels asked for. Else the levels asked for span what 8 levels of this growth did.
            if (f.hashGrowth != 0) spreadHashLevels(f, f.hashBaseResolution * std::pow(double(f.hashGrowth), 7.0));
          }),
      model("hash_features", &FastModel::hashFeatures).addedLater().range(1, 8),
      // 0: from the dataset (src/models/fast/fast_capacity.h)
      model("hash_log2_size", &FastModel::hashLog2Size).addedLater().range(2, 26).zeroIsAuto()
          .flag("--hash-log2-size", "fast: log2 of the hash table entries per level").flagRange(2, 24),
      model("hash_base_resolution", &FastModel::hashBaseResolution).addedLater().range(1, 65536),
      // The flag gives the finest resolution; the growth factor follows from it and the levels (after --hash-levels).
      model("hash_growth", &FastModel::hashGrowth).addedLater().range(1.0, 16.0).zeroIsAuto()
          .flag("--hash-max-resolution", "fast: finest grid level's cells per axis").flagTakes(Type::Count).flagRange(2, 65536)
          .flagApplies([](TrainConfig& c, const ConfigValue& v) { spreadHashLevels(c.fastModel(), std::get<uint32_t>(v)); }),
      model("sh_degree", &FastModel::shDegree).addedLater().range(1, 8),
      model("appearance_dims", &FastModel::appearanceDims).addedLater(0u).range(0, 64).multipleOf(4)
          .flag("--appearance-dims", "fast: a learned appearance vector of N floats per training photo (exposure, white balance; multiple of 4, 0: none)")
          .flagRange(0, 64),
      // 0: from the march steps (src/models/fast/fast_capacity.h)
      model("grid_resolution", &FastModel::gridResolution).addedLater().range(1, 256).zeroIsAuto()
          .flag("--grid", "fast: occupancy grid cells per axis (default on a CPU: half the march steps, 64 to 128; 64 with the proposal sampler)").flagRange(1, 256),
      model("cascades", &FastModel::cascades).addedLater(1u).range(0, 8)  // models saved before cascades have one
          .flag("--cascades", "fast: nested occupancy cascades (default: from the scene's aabb_scale)").flagRange(1, 8),
      model("cone_angle", &FastModel::coneAngle).addedLater().range(0.0, 1.0)
          .flag("--cone-angle", "fast, with cascades: step = t * angle beyond the inner cube").flagRange(1e-6, 1.0),
      // Models saved before it spanned the whole box.
      model("contraction", &FastModel::contraction).addedLater(false)
          .flag("--contraction", "fast, with cascades: the hash grid spans the box contracted about its inner cube (mip-NeRF 360's contraction)"),
      // Models saved before it started rays at the vanilla model's near plane (0).
      model("near_distance", &FastModel::nearDistance).addedLater(0.0f).range(0.0, 1e30)
          .flag("--near", "fast: rays start this far in front of the camera, in the scene's units (default: 5% of the inner cascade's side)")
          .flagPositive(),
      model("march_steps", &FastModel::marchSteps).addedLater().range(1, 65536).zeroIsAuto()
          .flag("--march-steps", "fast: march steps per scene-box diagonal").flagRange(1, 65536)
          .flagApplies([](TrainConfig& c, const ConfigValue& v) {
            FastModel& f = c.fastModel();
            f.marchSteps = f.maxSamplesPerRay = std::get<uint32_t>(v);
          }),
      model("max_samples_per_ray", &FastModel::maxSamplesPerRay).addedLater().range(1, 65536).zeroIsAuto(),
      fastTop("samples_per_batch", &FastModel::samplesPerBatch).addedLater().range(1, 1u << 28).zeroIsAuto()
          .flag("--samples-per-step", "fast: samples a training step aims for (default on a CPU: from the march steps)").flagRange(256, 1u << 26),
      fastTop("grid_update_interval", &FastModel::gridUpdateInterval).addedLater().range(1, UINT32_MAX),
      fastTop("grid_warmup_steps", &FastModel::gridWarmupSteps).addedLater(),
      // Models saved before it trained with instant-ngp's 1%.
      fastTop("occupancy_threshold", &FastModel::occupancyThreshold).addedLater(0.01f).range(0.0, 1.0).openLow().zeroIsAuto()
          .flag("--occupancy-threshold", "fast: a cell is skipped where one march step through it is less opaque than this (default: instant-ngp's 0.01, 0.001 with the proposal sampler)")
          .flagRange(1e-6, 0.5),
      // Models saved before it marched one sample a step.
      fastTop("step_opacity", &FastModel::stepOpacity).addedLater(0.0f).range(0.0, 1.0)
          .flag("--step-opacity", "fast, with cascades: a sample through faint cells stands for several steps while it stays at most this opaque (0: one a step)")
          .flagRange(0.0, 0.5),
      fastTop("hash_lr_scale", &FastModel::hashLearningRateScale).addedLater().range(0.0, 1e6).openLow(),
      fastTop("early_termination", &FastModel::earlyTermination).addedLater()
          .flag("--no-early-termination", "fast: train on every marched sample, also behind opaque surfaces")
          .flagApplies([](TrainConfig& c, const ConfigValue&) { c.fastModel().earlyTermination = false; }),
      // Models saved before it trained without.
      fastTop("distortion_loss", &FastModel::distortionLoss).addedLater(0.0f).range(0.0, 1e3)
          .flag("--distortion-loss", "fast: weight of mip-NeRF 360's distortion loss against fog and floaters (default 0: off; 0.001 leaves half-transparent surfaces the far field paints)")
          .flagRange(0.0, 100.0),
      // Models saved before it left the far field out of the loss.
      fastTop("distortion_far_field", &FastModel::distortionFarField).addedLater(false)
          .flag("--distortion-far-field", "fast, with --distortion-loss: the weight a ray leaves to the far field counts in the loss, as an interval at its far end"),
      // Models saved before it had none: 0, read as the march.
      fastTop("proposal_samples", &FastModel::proposalSamples).addedLater(0u).range(0, FastModel::kMaxProposalSamples)
          .flag("--proposal-samples", "fast: each ray's field samples, placed by a small proposal density field trained to bound the field's weights (nerfacto's proposal estimator; 0: the march's, every marched sample; default: 24 where the photos have no alpha, the march where they have)")
          .flagRange(0, FastModel::kMaxProposalSamples)
          .flagApplies([](TrainConfig& c, const ConfigValue& v) {
            FastModel& m = c.fastModel();
            m.proposalSamples = std::get<uint32_t>(v);
            m.sampler = m.proposalSamples ? Sampler::Proposal : Sampler::March;
          }),
      // Models saved before it sampled with the proposal where they had its samples (0: none).
      fastTop("sampler", &FastModel::sampler)
          .addedLaterFrom([](const TrainConfig& c) {
            return valueOf(c.fastModel().proposalSamples ? Sampler::Proposal : Sampler::March);
          })
          .check([](const TrainConfig& c) {
            const FastModel& m = c.fastModel();
            checkCount("sampler", uint32_t(m.sampler), 0, uint32_t(Sampler::Proposal));
            if (m.sampler == Sampler::Proposal && m.proposalSamples == 0)
              throw Error("sampler proposal needs proposal_samples >= 1, got 0");
          }),
      fastTop("proposal_levels", &FastModel::proposalLevels).addedLater(5u).range(1, 16)
          .flag("--proposal-levels", "fast, with the proposal sampler: the proposal's hash-grid levels").flagRange(1, 16),
      fastTop("proposal_stride", &FastModel::proposalStride).addedLater(1u).range(1, 64)
          .flag("--proposal-stride", "fast, with the proposal sampler and cascades: one proposal evaluation stands for up to this many march steps through occupied cells (default 8)").flagRange(1, 64),
      // Models saved before it trained their proposal without annealing.
      fastTop("proposal_anneal_steps", &FastModel::proposalAnnealSteps).addedLater(0u).range(0, 1u << 24)
          .flag("--proposal-anneal-steps", "fast, with the proposal sampler: the training steps over which the proposal's weights take over its samples' placement from an even spread (nerfacto's annealing; default 1000, 0: from the first step)").flagRange(0, 1u << 24),
      fastTop("proposal_loss", &FastModel::proposalLoss).addedLater(1.0f).range(0.0, 1e3).openLow(),
      // Models saved before it had a constant far field.
      model("far_field", &FastModel::farField).addedLater(std::string("constant"))
          .check([](const TrainConfig& c) { checkCount("model.far_field", uint32_t(c.fastModel().farField), 0, uint32_t(FarField::Learned)); })
          .flag("--far-field", "fast: what rays see behind the scene box: learned (a colour per direction, trained), constant (white in renders, a random colour behind each training ray) or auto (learned when no training pixel has alpha)"),

      fastTop("refine_cameras", &FastModel::refineCameras).addedLater()
          .flag("--refine-cameras", "fast: learn a correction of each training photo's pose while training (docs/real_captures.md)"),
      fastTop("camera_lr", &FastModel::cameraLearningRate).addedLater().range(0.0, 1e3).openLow()
          .flag("--camera-lr", "fast, with --refine-cameras: the pose corrections' initial learning rate").flagPositive(),
      fastTop("camera_penalty", &FastModel::cameraPenalty).addedLater().range(0.0, 1e6)
          .flag("--camera-penalty", "fast, with --refine-cameras: weight of the L2 penalty that keeps each pose near its given one").flagRange(0.0, 1e6),

      top("lr", &TrainConfig::learningRate).range(0.0, 1e3).openLow(),
      top("lr_final", &TrainConfig::learningRateFinal).range(0.0, 1e3).openLow(),
      top("decay_steps", &TrainConfig::decaySteps).range(1, UINT32_MAX),
      top("beta1", &TrainConfig::beta1).range(0.0, 1.0),
      top("beta2", &TrainConfig::beta2).range(0.0, 1.0),
      top("epsilon", &TrainConfig::epsilon).range(0.0, 1.0).openLow(),
      top("random_background", &TrainConfig::randomBackground),
      top("background", &TrainConfig::background).range(0.0, 1.0 + 1e-6),
      top("seed", &TrainConfig::seed).flag("--seed", "Random seed"),
  };
}

}  // namespace

const std::vector<ConfigField>& configFields() {
  static const std::vector<ConfigField> fields = table();
  return fields;
}

std::string configValueJson(const ConfigValue& v) {
  return std::visit([](const auto& x) { return nlohmann::json(x).dump(); }, v);
}

}  // namespace vknerf
