#pragma once
// The range checks of TrainConfig::validate (src/core/config/config_validate.cpp), for the checks of
// the table of fields (src/core/config/config_fields.cpp) that a ConfigRange cannot say. `field` is
// the name the message starts with, the checkpoint key ("model.feature_width").
#include <cstdint>
#include <string>

namespace vknerf {

// v in [lo, hi]: "model.coarse_samples must be in [1, 4096], got 0".
void checkCount(const std::string& field, uint64_t v, uint64_t lo, uint64_t hi);
// v finite and in [lo, hi), or (lo, hi) when `openLow`.
void checkReal(const std::string& field, float v, double lo, double hi, bool openLow);

}  // namespace vknerf
