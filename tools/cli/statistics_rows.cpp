#include "command.h"

namespace vknerf::cli {

std::vector<std::pair<std::string, double>> statisticsRows(const ModelStatistics& s) {
  std::vector<std::pair<std::string, double>> rows;
  if (s.occupiedFraction) rows.push_back({"occupied fraction", *s.occupiedFraction});
  if (s.occupiedFractionPerCascade.size() > 1)
    for (size_t c = 0; c < s.occupiedFractionPerCascade.size(); ++c)
      rows.push_back({"occupied fraction, cascade " + std::to_string(c), s.occupiedFractionPerCascade[c]});
  if (s.occupiedBoxFraction) rows.push_back({"occupied cells' bounding box / scene box (volume)", *s.occupiedBoxFraction});
  rows.push_back({"samples per ray (last step)", s.samplesPerRay});
  if (s.meanSamplesPerRay) rows.push_back({"samples per ray (mean over all steps)", *s.meanSamplesPerRay});
  rows.push_back({"rays per step (last step)", double(s.raysPerStep)});
  rows.push_back({"samples per step (last step)", double(s.samplesPerStep)});
  if (s.keptByEarlyTermination) rows.push_back({"samples kept by early termination (all steps)", *s.keptByEarlyTermination});
  if (s.encodingParameters) rows.push_back({"parameters (hash grid)", double(s.encodingParameters)});
  rows.push_back({"parameters (MLP)", double(s.mlpParameters)});
  rows.push_back({"device buffers MiB", s.deviceMiB});
  return rows;
}

}  // namespace vknerf::cli
