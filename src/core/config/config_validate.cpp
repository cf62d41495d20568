// TrainConfig::validate: one check of a configuration's fields, for flags and checkpoints alike,
// made from the table of fields (src/core/config/config_fields.cpp). Field names are the checkpoint's keys
// (src/io/checkpoint/config_json.cpp), so a message points into the file.
#include <cmath>
#include <cstdio>
#include <string>

#include "core/config/config_range.h"
#include "vknerf/config.h"
#include "vknerf/config_fields.h"
#include "vknerf/error.h"

namespace vknerf {
namespace {

std::string text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

void checkRange(const std::string& field, const ConfigValue& value, const ConfigRange& r) {
  if (const uint32_t* v = std::get_if<uint32_t>(&value)) {
    if (r.zeroIsAuto && *v == 0) return;
    checkCount(field, *v, uint64_t(r.lo), uint64_t(r.hi));
    if (*v % r.multipleOf)
      throw Error(field + " must be a multiple of " + std::to_string(r.multipleOf) + ", got " + std::to_string(*v));
  } else if (const float* v = std::get_if<float>(&value)) {
    if (r.zeroIsAuto && *v == 0) return;
    checkReal(field, *v, r.lo, r.hi, r.openLow);
  } else if (const auto* colour = std::get_if<std::array<float, 3>>(&value)) {
    for (float c : *colour) checkReal(field, c, r.lo, r.hi, r.openLow);
  } else {
    throw Error(field + ": a switch or a name has no range");  // a row of the table is wrong
  }
}

}  // namespace

void checkCount(const std::string& field, uint64_t v, uint64_t lo, uint64_t hi) {
  if (v < lo || v > hi)
    throw Error(field + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                std::to_string(v));
}

void checkReal(const std::string& field, float v, double lo, double hi, bool openLow) {
  if (!std::isfinite(v) || (openLow ? !(v > lo) : !(v >= lo)) || !(v < hi))
    throw Error(field + " must be finite and in " + (openLow ? "(" : "[") + text(lo) + ", " + text(hi) + "), got " +
                text(v));
}

void TrainConfig::validate() const {
  for (const ConfigField& f : configFields()) {
    if (!f.appliesTo(*this)) continue;
    if (f.range) checkRange(f.path(), f.get(*this), *f.range);
    if (f.check) f.check(*this);
  }
}

}  // namespace vknerf
