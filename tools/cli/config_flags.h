#pragma once
// The configuration flags of `vknerf train` (--rays, --width, ... --far-field, --seed), one per
// field of the table of configuration fields (vknerf/config_fields.h) that has a flag: adding a row
// there adds its flag here, with its help, its check, its model and its resume check.
#include <CLI/CLI.hpp>

#include <deque>
#include <optional>
#include <string>

#include "vknerf/config_fields.h"

namespace vknerf::cli {

class ConfigFlags {
 public:
  // Adds the flags to `app`, in the table's order.
  explicit ConfigFlags(CLI::App& app);

  // The first flag given that only the other model reads ("--coarse" for a fast model), or "".
  std::string forTheOtherModel(const TrainConfig& cfg) const;
  // Whether the flag `name` ("--camera-lr") was given.
  bool given(const std::string& name) const;
  // Sets the fields of the flags given. Call after parsing.
  void applyTo(TrainConfig& cfg) const;

  // A flag that would change a checkpoint's configuration (which --resume keeps): the flag with the
  // value it asks for ("--width", "32") and the checkpoint's field with its value ("model/width 16").
  struct Conflict {
    std::string flag, asked, stored;
  };
  // The first flag, once the flags given are applied to `saved`, whose field differs from it.
  std::optional<Conflict> conflictWith(const TrainConfig& saved) const;

 private:
  struct Flag {
    const ConfigField* field;
    ConfigValue value;  // where CLI11 writes the flag's value
    CLI::Option* option = nullptr;
    bool given() const { return option->count() > 0; }
  };
  std::deque<Flag> flags_;  // a deque: CLI11 holds pointers to the values
};

}  // namespace vknerf::cli
