#pragma once
// The configuration's fields as one table (src/core/config/config_fields.cpp): a row per member of
// TrainConfig or of a model, with its checkpoint key, the models it belongs to, the range the models
// accept and the `vknerf train` flag that sets it. The checkpoint's reader and writer, validate()
// and the train command's flags and resume checks are all made from it, so a new field is a member
// in config.h and a row in the table.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "vknerf/config.h"

namespace vknerf {

// A field's value: a count (an enumeration is stored as its number), a real, a switch, a name (the
// far field's) or a colour. ConfigValueType names the alternatives, in this order.
using ConfigValue = std::variant<uint32_t, float, bool, std::string, std::array<float, 3>>;
enum class ConfigValueType { Count, Real, Switch, Name, Colour };

// The value as a checkpoint writes it (JSON: 16, 0.015625, true, "learned", [1.0,1.0,1.0]).
std::string configValueJson(const ConfigValue& v);

// The values validate() accepts: counts in [lo, hi]; reals finite and in [lo, hi), or (lo, hi).
struct ConfigRange {
  double lo = 0, hi = 0;
  bool openLow = false;     // learning rates and epsilon must be > 0, betas may be 0
  bool zeroIsAuto = false;  // 0 means "from the dataset" and is not checked
  uint32_t multipleOf = 1;
};

// The `vknerf train` flag that sets a field.
struct ConfigFlag {
  const char* name = nullptr;  // "--cone-angle"; null: no flag sets the field
  const char* help = "";
  ConfigValueType type = ConfigValueType::Count;  // the flag's value (not always the field's: --hash-max-resolution)
  // What the command line accepts as it parses, in the flag's type: often narrower than the field's
  // range (what was tried). Choice: one of the field's `choices`.
  enum class Check { None, Range, Positive, Choice } check = Check::None;
  double lo = 0, hi = 0;
  // What giving the flag does where it is more than setting the field (--march-steps also caps the
  // samples per ray); empty: set the field.
  std::function<void(TrainConfig&, const ConfigValue&)> apply;
};

// How a checkpoint without the field's key reads.
enum class MissingKey {
  Error,    // a key of the first checkpoint format
  Default,  // added later: the field's default
  Legacy,   // added later: `legacy`, what models saved before the key had
  Derived,  // added later: `derivedLegacy` of the fields read before it
};

struct ConfigField {
  const char* key = "";  // in a checkpoint's configuration
  // Under "model", or at the top level (where the first format put the fast model's training fields).
  bool inModel = false;
  bool vanilla = false, fast = false;  // the models it belongs to (both: TrainConfig's own fields)
  ConfigValueType type = ConfigValueType::Count;
  std::function<ConfigValue(const TrainConfig&)> get;
  std::function<void(TrainConfig&, const ConfigValue&)> set;  // throws vknerf::Error for a name not among `choices`
  std::vector<std::string> choices;                           // a name's values
  MissingKey missing = MissingKey::Error;
  ConfigValue legacy;
  std::function<ConfigValue(const TrainConfig&)> derivedLegacy;
  std::optional<ConfigRange> range;                // none: every value is valid
  std::function<void(const TrainConfig&)> check;   // what a range cannot say (a bound from another field)
  ConfigFlag flag;

  // The key with its section, as messages name it: "model.cone_angle" ('.') or "model/cone_angle" ('/').
  std::string path(char separator = '.') const { return inModel ? std::string("model") + separator + key : key; }
  bool appliesTo(const TrainConfig& c) const { return c.isFast() ? fast : vanilla; }
};

// Every field, in the order validate() and the flags' help list them.
const std::vector<ConfigField>& configFields();

}  // namespace vknerf
