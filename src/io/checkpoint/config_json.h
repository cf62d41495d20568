#pragma once
// TrainConfig <-> JSON, as stored in checkpoints, made from the table of fields
// (src/core/config/config_fields.cpp).
#include <nlohmann/json.hpp>

#include <string>

#include "vknerf/config.h"

namespace vknerf::io {

nlohmann::json toJson(const TrainConfig& c);
// Keys added after the first checkpoint version fall back to the defaults (or to what models saved
// before them had); a missing or mistyped original key, or a value TrainConfig::validate rejects,
// throws vknerf::Error naming `file` and the key.
TrainConfig trainConfigFromJson(const nlohmann::json& j, const std::string& file);

}  // namespace vknerf::io
