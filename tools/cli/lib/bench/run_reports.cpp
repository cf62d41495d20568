#include "lib/bench/run_reports.h"

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vknerf/error.h"

namespace vknerf::bench {
namespace {

// The number following `prefix` on the last line that starts with it (after leading spaces), if any.
std::optional<double> numberAfter(const std::string& log, const std::string& prefix) {
  std::istringstream lines(log);
  std::string line;
  std::optional<double> found;
  while (std::getline(lines, line)) {
    const size_t start = line.find_first_not_of(' ');
    if (start == std::string::npos || line.compare(start, prefix.size(), prefix) != 0) continue;
    const std::string rest = line.substr(start + prefix.size());
    char* end = nullptr;
    const double v = std::strtod(rest.c_str(), &end);
    if (end != rest.c_str() && std::isfinite(v)) found = v;
  }
  return found;
}

double finiteNumber(const nlohmann::json& j, const char* key, const std::string& what) {
  if (!j.contains(key) || !j[key].is_number() || !std::isfinite(j[key].get<double>()))
    throw Error(what + ": no finite number \"" + key + "\"");
  return j[key].get<double>();
}

nlohmann::json parseObject(const std::string& text, const std::string& what) {
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object()) throw Error(what + ": not a JSON object");
  return j;
}

}  // namespace

TrainReport readTrainSummary(const std::string& json, const std::string& what) {
  const nlohmann::json j = parseObject(json, what);
  TrainReport r;
  r.steps = uint32_t(finiteNumber(j, "steps", what));
  if (j.contains("samples_per_ray")) r.samplesPerRay = finiteNumber(j, "samples_per_ray", what);
  if (j.contains("device_mib")) r.deviceMiB = finiteNumber(j, "device_mib", what);
  return r;
}

TrainReport parseTrainLog(const std::string& log) {
  TrainReport r;
  // "done after N steps" or, stopped by a signal, "interrupted after N steps".
  for (const char* word : {"done after ", "interrupted after "})
    if (auto n = numberAfter(log, word); n && *n >= 0) r.steps = uint32_t(*n);
  r.samplesPerRay = numberAfter(log, "samples per ray (mean over all steps)");
  if (!r.samplesPerRay) r.samplesPerRay = numberAfter(log, "samples per ray (last step)");
  // "memory: host peak H MiB; device D MiB (...)": D follows "; device ".
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("memory: ", 0) != 0) continue;
    const size_t at = line.find("; device ");
    if (at == std::string::npos) continue;
    if (auto d = numberAfter(line.substr(at + 2), "device "); d) r.deviceMiB = d;
  }
  return r;
}

EvalReport readEvalJson(const std::string& json, const std::string& what) {
  const nlohmann::json j = parseObject(json, what);
  EvalReport r;
  r.psnr = finiteNumber(j, "psnr", what);
  r.ssim = finiteNumber(j, "ssim", what);
  r.secondsPerView = finiteNumber(j, "seconds_per_image", what);
  r.views = uint64_t(finiteNumber(j, "count", what));
  if (j.contains("samples_per_pixel")) r.samplesPerPixel = finiteNumber(j, "samples_per_pixel", what);
  return r;
}

}  // namespace vknerf::bench
