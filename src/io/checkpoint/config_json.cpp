#include "io/checkpoint/config_json.h"

#include "vknerf/config_fields.h"
#include "vknerf/error.h"

namespace vknerf::io {

using nlohmann::json;

namespace {

json jsonOf(const ConfigValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

// The alternative of `type`; a value of another JSON type throws json::exception.
ConfigValue valueOf(const json& j, ConfigValueType type) {
  switch (type) {
    case ConfigValueType::Count: return j.get<uint32_t>();
    case ConfigValueType::Real: return j.get<float>();
    case ConfigValueType::Switch: return j.get<bool>();
    case ConfigValueType::Name: return j.get<std::string>();
    case ConfigValueType::Colour: return j.get<std::array<float, 3>>();
  }
  throw Error("unknown configuration value type");
}

}  // namespace

// The layout is the first checkpoint format's, so older checkpoints still load and older builds
// read newer ones: the model's own fields under "model" (with its name), TrainConfig's and the fast
// model's training fields at the top level (src/core/config/config_fields.cpp says which).
json toJson(const TrainConfig& c) {
  json j = json::object();
  j["model"] = {{"name", modelName(c.model)}};
  for (const ConfigField& f : configFields())
    if (f.appliesTo(c)) (f.inModel ? j["model"] : j)[f.key] = jsonOf(f.get(c));
  return j;
}

TrainConfig trainConfigFromJson(const json& j, const std::string& file) {
  try {
    TrainConfig c;
    const json& m = j.at("model");
    const std::string name = m.at("name");
    if (name == "fast")
      c.model.emplace<FastModel>();
    else if (name != "vanilla")
      throw Error("unknown model \"" + name + "\"");
    for (const ConfigField& f : configFields()) {
      if (!f.appliesTo(c)) continue;
      const json& section = f.inModel ? m : j;
      const auto it = section.find(f.key);
      if (it != section.end())
        f.set(c, valueOf(*it, f.type));
      else if (f.missing == MissingKey::Error)
        (void)section.at(f.key);  // throws json's "key 'width' not found"
      else if (f.missing == MissingKey::Legacy)
        f.set(c, f.legacy);
      else if (f.missing == MissingKey::Derived)
        f.set(c, f.derivedLegacy(c));
    }
    c.validate();
    return c;
  } catch (const json::exception& e) {
    throw Error(file + ": checkpoint config: " + e.what());
  } catch (const Error& e) {
    throw Error(file + ": checkpoint config: " + e.what());
  }
}

}  // namespace vknerf::io
