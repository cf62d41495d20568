#include "config_flags.h"

namespace vknerf::cli {

namespace {

// What the flag accepts as it is parsed, in the flag's own type (the help shows it: "UINT in [8 - 1024]").
void addCheck(CLI::Option* option, const ConfigField& f) {
  const ConfigFlag& flag = f.flag;
  switch (flag.check) {
    case ConfigFlag::Check::None: break;
    case ConfigFlag::Check::Positive: option->check(CLI::PositiveNumber); break;
    case ConfigFlag::Check::Choice: option->check(CLI::IsMember(f.choices)); break;
    case ConfigFlag::Check::Range:
      if (flag.type == ConfigValueType::Real)
        option->check(CLI::Range(float(flag.lo), float(flag.hi)));
      else
        option->check(CLI::Range(uint32_t(flag.lo), uint32_t(flag.hi)));
      break;
  }
}

}  // namespace

ConfigFlags::ConfigFlags(CLI::App& app) {
  for (const ConfigField& f : configFields()) {
    if (!f.flag.name) continue;
    Flag& flag = flags_.emplace_back(Flag{&f, {}});
    switch (f.flag.type) {
      case ConfigValueType::Count: flag.option = app.add_option(f.flag.name, flag.value.emplace<uint32_t>(), f.flag.help); break;
      case ConfigValueType::Real: flag.option = app.add_option(f.flag.name, flag.value.emplace<float>(), f.flag.help); break;
      case ConfigValueType::Switch: flag.option = app.add_flag(f.flag.name, flag.value.emplace<bool>(), f.flag.help); break;
      case ConfigValueType::Name: flag.option = app.add_option(f.flag.name, flag.value.emplace<std::string>(), f.flag.help); break;
      case ConfigValueType::Colour: throw std::logic_error(std::string(f.flag.name) + ": no flag takes a colour");
    }
    addCheck(flag.option, f);
  }
}

std::string ConfigFlags::forTheOtherModel(const TrainConfig& cfg) const {
  for (const Flag& flag : flags_)
    if (flag.given() && !flag.field->appliesTo(cfg)) return flag.field->flag.name;
  return "";
}

bool ConfigFlags::given(const std::string& name) const {
  for (const Flag& flag : flags_)
    if (flag.field->flag.name == name) return flag.given();
  return false;
}

void ConfigFlags::applyTo(TrainConfig& cfg) const {
  for (const Flag& flag : flags_) {
    if (!flag.given() || !flag.field->appliesTo(cfg)) continue;
    if (flag.field->flag.apply)
      flag.field->flag.apply(cfg, flag.value);
    else
      flag.field->set(cfg, flag.value);
  }
}

std::optional<ConfigFlags::Conflict> ConfigFlags::conflictWith(const TrainConfig& saved) const {
  TrainConfig asked = saved;
  applyTo(asked);
  for (const Flag& flag : flags_) {
    const ConfigField& f = *flag.field;
    if (!f.appliesTo(saved)) continue;
    const ConfigValue a = f.get(asked), b = f.get(saved);
    if (a != b) return Conflict{f.flag.name, configValueJson(a), f.path('/') + " " + configValueJson(b)};
  }
  return std::nullopt;
}

}  // namespace vknerf::cli
